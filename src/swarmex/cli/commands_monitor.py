"""``swarmex monitor``: serve the live page for a simulated mission, a record, or a live feed.

* ``--scenario FILE.toml`` runs the scenario's mission (through the Mission contract, as
  ``swarmex run`` does) and streams its frames *while it runs*, paced in scaled time
  (``--speed`` mission seconds per wall second), starting when the first viewer connects
  (:mod:`swarmex.viz.monitor.live`);
* ``--record FILE.json`` replays a finished run's record the same way;
* ``--connect tcp://HOST:P`` shows a networked mission live (the producer of
  :func:`swarmex.net.events.network_producer` reads the mission server's event stream);
* none of these: the page waits for a producer on ``ws://127.0.0.1:PORT/ingest`` (how other
  programs feed it; schema at ``/schema`` and in docs/monitor.md).

Every mission's world is rebuilt from the record's parameters the way its own command builds
it (:func:`record_world`): traversal and exploration grids, the foraging grid with its nest
and food, the roadmap's polygons, roadmap and goal.

The first line printed is the page's address. The server listens on 127.0.0.1 only; ``--port
0`` (the default) takes a free port. ``--linger S`` stops it S seconds after the mission ends
(default: serve until Ctrl-C).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import app, console
from swarmex.cli.outputs import check_output
from swarmex.cli.shared import _say, check_connect
from swarmex.errors import InputError, check_number, require


def scenario_mission(scenario: Path) -> tuple[Any, Any]:
    """A scenario file's mission and checked params (the file's output keys, json and render,
    are ignored here)."""
    from swarmex.experiments.scenario import (
        in_file,
        load_scenario,
        mission_shapes,
        scenario_values,
    )
    from swarmex.missions.registry import get

    scn = load_scenario(scenario)
    options = {k: v for k, v in scn.options.items() if k not in ("json", "render")}
    scn = type(scn)(scn.path, scn.mission, options)
    try:
        mission = get(scn.mission)
        return mission, mission.params(scenario_values(scn, mission_shapes(scn.mission)))
    except InputError as exc:
        raise in_file(scenario, exc) from None


def check_record(record: Any, path: Path) -> None:
    """What the replay reads of a record, checked up front so that a JSON file that is not a
    result record is one line, not a traceback from inside the event builder: the agents
    (objects with an id, their trajectories ``[t, x, y]`` rows) and a numeric makespan."""

    def bad(what: str) -> InputError:
        return InputError(f"{path} is not a result record ({what})")

    if not isinstance(record, dict) or "agents" not in record:
        raise bad("no agents")
    agents = record["agents"]
    if not isinstance(agents, list) or not all(
        isinstance(a, dict) and "id" in a for a in agents
    ):
        raise bad("'agents' must be a list of objects with an 'id'")
    for a in agents:
        for key in ("trajectory", "jobs"):
            rows = a.get(key, [])
            if not isinstance(rows, list) or not all(
                isinstance(r, list) and len(r) >= 3
                and all(isinstance(v, int | float) and not isinstance(v, bool) for v in r[:3])
                for r in rows
            ):
                raise bad(f"agent {a['id']}: '{key}' must be a list of [t, x, y] rows")
    makespan = record.get("makespan")
    if makespan is not None and (isinstance(makespan, bool)
                                 or not isinstance(makespan, int | float)):
        raise bad(f"'makespan' must be a number, got {makespan!r}")


def address_note(port: int, *, wait: bool, has_mission: bool, connect: str | None) -> str:
    """What the server does, said after the page's address: a replayed record or a scenario
    run in this process (``has_mission``) waits for a viewer or streams at once; otherwise
    the page shows a networked mission or whatever a producer sends to /ingest. (A scenario
    run used to be announced as "waiting for events on /ingest", which it never needs.)"""
    if connect is not None:
        return f"showing the mission at {connect}"
    if has_mission:
        return "waiting for the first viewer" if wait else "streaming"
    return f"waiting for events on ws://127.0.0.1:{port}/ingest"


def run_scenario_record(scenario: Path) -> dict:
    """Run a scenario file's mission in this process (through the Mission contract) and
    return its result record."""
    mission, params = scenario_mission(scenario)
    return mission.run(params).record.to_dict()


def _path(text: str, base: Path | None) -> Path:
    """A path from a record: as written (the run's working directory), else beside ``base``.

    Records store paths as they were typed, so a record replayed from elsewhere finds its map
    next to the record file.
    """
    p = Path(text).expanduser()
    if not p.is_absolute() and not p.exists() and base is not None and (base / p).exists():
        return base / p
    return p


def free_cells(record: dict, base: Path | None = None):
    """The map of a traversal record (rebuilt from its params), else None (bounds only)."""
    params = record.get("params") or {}
    if record.get("mission") != "traversal" or (record.get("world") or {}).get("kind") != "grid":
        return None
    from swarmex.missions.traversal.mission import build_world
    from swarmex.missions.traversal.params import TraversalParams

    try:
        map_file = _path(params["map"], base) if params.get("map") else None
        world = build_world(
            TraversalParams.from_values(
                map=map_file,
                grid=params.get("grid"),
                obstacles=params.get("obstacles") or (),
                connectivity=params.get("connectivity", 4),
                center=params.get("center"),
                radius=params.get("radius"),
                nodes_on_edge=params.get("nodes_on_edge"),
                agents=1,
            )
        )
    except (InputError, KeyError, TypeError):
        return None  # the map moved or the record is from elsewhere: draw the bounds only
    return world.free


def foraging_world(record: dict) -> dict:
    """The g×g grid of a foraging record (every cell free) with its nest and food marked.

    As the mission has it (:func:`swarmex.missions.foraging.mission.world_of`): the nest is
    the grid's centre cell, the food the cell the run used (given or drawn from the seed),
    which the record keeps; a grid or food the mission would refuse raises InputError.
    """
    from swarmex.missions.foraging.mission import world_of
    from swarmex.viz.monitor.events import world_event

    params = record.get("params") or {}
    world = world_of(params["grid"], tuple(params["food"]))
    (nx, ny), (fx, fy) = world.nest, world.food
    marks: list[dict[str, Any]] = [
        {"kind": "nest", "x": nx, "y": ny},
        {"kind": "food", "x": fx, "y": fy, "units": params.get("food_units")},
    ]
    return world_event(record, world.free, marks=marks)


def exploration_world(record: dict, base: Path | None) -> dict:
    """The true occupancy grid of an exploration record, loaded as ``swarmex explore`` does."""
    import re

    from swarmex.missions.exploration.mission import build_world
    from swarmex.missions.exploration.params import ExplorationParams
    from swarmex.viz.monitor.events import world_event

    world = record.get("world") or {}
    cell = world.get("cell_m", (record.get("params") or {}).get("cell"))
    source = str(world.get("source", ""))
    empty = re.fullmatch(r"empty (\S+)x(\S+) m", source)
    if empty:  # --empty WxH: the record names the size in its source
        where: dict[str, Any] = {"empty": f"{empty.group(1)}x{empty.group(2)}"}
    else:
        where = {"map": _path(source, base)}
    grid = build_world(ExplorationParams.from_values(where, cell=cell, robots=1))
    return world_event(record, grid.free)  # record_world drops it if the size changed


def roadmap_world(record: dict, base: Path | None) -> dict | None:
    """The polygon world of a roadmap record (its ``--env`` file), the roadmap and the goal."""
    import shapely
    from shapely.geometry import Polygon

    from swarmex.missions.roadmap.mission import load_environment
    from swarmex.viz.monitor.events import world_event

    world = record.get("world") or {}
    pw = load_environment(_path(str((record.get("params") or {})["env"]), base))
    if world.get("bounds") is not None and not all(
        abs(a - b) <= 1e-9 * max(1.0, abs(b))
        for a, b in zip(pw.bounds, world["bounds"], strict=True)
    ):
        return None  # the file changed since the run

    def ring(coords: Any) -> list[list[float]]:
        return [[round(x, 6), round(y, 6)] for x, y in list(coords)[:-1]]

    rings = []
    for part in shapely.get_parts(pw.union):
        if isinstance(part, Polygon):  # disjoint parts: even-odd filling is exact
            rings += [ring(part.exterior.coords), *(ring(h.coords) for h in part.interiors)]
    edges: list[list[float]] = []
    roadmap = record.get("roadmap") or {}
    nodes = roadmap.get("nodes") or []
    for i, j in roadmap.get("edges") or []:
        edges.append([*nodes[i], *nodes[j]])
    for a, b in roadmap.get("legs") or []:  # entry legs and the leg to the goal
        edges.append([*a, *b])
    marks = []
    goal = record.get("goal")
    if goal is not None:
        marks.append({"kind": "goal", "x": goal[0], "y": goal[1]})
    return world_event(
        record,
        bounds=list(pw.bounds),
        y_up=not pw.y_down,
        polygons=rings,
        edges=edges,
        marks=marks,
    )


def record_world(record: dict, base: Path | None = None) -> dict:
    """The world event of any mission's record, its map rebuilt from the record's parameters
    the way the mission's command built it; the bounds only when that cannot be done (the map
    file moved or changed, a record from elsewhere).

    ``base`` is a second folder to look for relative map paths in (the record file's).
    """
    from swarmex.viz.monitor.events import world_event

    mission = record.get("mission")
    built: dict | None = None
    try:
        if mission == "traversal":
            built = world_event(record, free_cells(record, base))
        elif mission == "foraging":
            built = foraging_world(record)
        elif mission == "exploration":
            built = exploration_world(record, base)
        elif mission == "roadmap":
            built = roadmap_world(record, base)
    except (InputError, KeyError, IndexError, TypeError, ValueError, OSError):
        built = None
    world = record.get("world") or {}
    size = (world.get("width"), world.get("height"))
    cells = built["cells"] if built is not None else None
    if cells and None not in size and (len(cells[0]), len(cells)) != size:
        built = None  # the map file changed since the run: not the world it used
    return built if built is not None else world_event(record)


@app.command()
def monitor(
    scenario: Path | None = typer.Option(
        None, "--scenario", help="Run this scenario and stream it live.", show_default=False
    ),
    record_file: Path | None = typer.Option(
        None, "--record", help="Replay a result record (--json of any mission).", show_default=False
    ),
    connect: str | None = typer.Option(
        None,
        "--connect",
        help="Show a networked mission: its server's address (tcp://HOST:P).",
        show_default=False,
    ),
    port: int = typer.Option(0, "--port", help="Port on 127.0.0.1 (0: a free one)."),
    speed: float = typer.Option(
        1.0, "--speed", help="Mission seconds per wall second (inf: all at once)."
    ),
    wait: bool = typer.Option(
        True, "--wait/--no-wait", help="Start the mission when the first viewer connects."
    ),
    linger: float | None = typer.Option(
        None,
        "--linger",
        help="Stop this many seconds after the mission ends (default: until Ctrl-C).",
        show_default=False,
    ),
    json_path: Path | None = typer.Option(
        None, "--json", show_default=False,
        help="Also write the run's record here (--scenario, --record; for --connect, serve "
        "--json writes it).",
    ),
    snapshot_every: tuple[float, Path] | None = typer.Option(
        None,
        "--snapshot-every",
        help="Save the page's view as a PNG every S seconds into DIR (needs a viewer open).",
        metavar="S DIR",
        show_default=False,
    ),
) -> None:
    """Serve the live monitor page of a simulated (or networked) mission on 127.0.0.1."""
    import asyncio

    from swarmex.engine.record import read_record, write_json_atomic
    from swarmex.viz.monitor.events import record_events
    from swarmex.viz.monitor.hub import replay
    for module in ("starlette", "uvicorn", "websockets"):
        require(module, "monitor", "swarmex monitor")
    from swarmex.viz.monitor.server import MonitorServer

    if sum(x is not None for x in (scenario, record_file, connect)) > 1:
        raise InputError("give at most one of --scenario, --record and --connect")
    if not speed > 0:  # inf is allowed: frames as fast as they come
        raise InputError(f"--speed must be > 0 (or inf), got {speed}")
    if linger is not None:
        check_number(linger, "--linger", at_least=0)
    if port < 0 or port > 65535:
        raise InputError(f"--port must be in 0..65535, got {port}")
    if connect is not None and json_path is not None:  # the stream carries no record
        raise InputError("--json with --connect: the networked run's record is written by "
                         "'swarmex serve --json FILE'")
    check_output(json_path, "--json")  # now, not after the whole run
    snapshots = None
    if snapshot_every is not None:
        every, folder = snapshot_every
        if not every > 0 or math.isinf(every):
            raise InputError(f"--snapshot-every: S must be a positive number of seconds, "
                             f"got {every}")
        if folder.exists() and not folder.is_dir():
            raise InputError(f"--snapshot-every: {folder} is not a folder")
        from swarmex.viz.monitor.server import SnapshotDir

        try:
            snapshots = SnapshotDir(every, folder)
        except OSError as exc:
            raise InputError(f"--snapshot-every: cannot make {folder}: "
                             f"{exc.strerror or exc}") from None
    record: dict | None = None
    live: tuple[Any, Any, dict] | None = None
    if scenario is not None:
        from swarmex.viz.monitor.live import skeleton_record

        mission, params = scenario_mission(scenario)
        live = (mission, params, skeleton_record(mission, params))
        skeleton = live[2]
        console.print(
            f"{skeleton.get('mission')} · {skeleton.get('algorithm')} · "
            f"{len(skeleton['agents'])} agents · live (streamed while it runs)",
            highlight=False,
        )
    elif record_file is not None:
        record = read_record(record_file)
        check_record(record, record_file)
    if record is not None and json_path is not None:
        write_json_atomic(record, json_path)
    if record is not None:
        done = "complete" if record.get("complete") else "incomplete"
        messages = (record.get("metrics") or {}).get("messages")
        makespan = record.get("makespan")
        console.print(
            f"{record.get('mission')} · {record.get('algorithm')} · {len(record['agents'])} agents"
            f" · {done} · makespan "
            + (f"{makespan:.1f}" if makespan is not None else "?")
            + f" {record.get('time_unit', '')}"
            + (f" · {messages} messages" if messages is not None else ""),
            highlight=False,
        )
    server = MonitorServer(port, record, snapshots)
    producer: Any = None
    if live is not None:
        from swarmex.viz.monitor.live import stream_run

        mission, params, skeleton = live

        def keep(final: dict) -> None:
            server.record = final  # what /record serves from now on
            if json_path is not None:
                write_json_atomic(final, json_path)

        def producer(hub):
            return stream_run(hub, mission, params, skeleton, record_world(skeleton), speed,
                              wait, on_record=keep)

    if record is not None:
        base = record_file.resolve().parent if record_file is not None else None
        try:
            events = record_events(record, speed=speed, world=record_world(record, base))
        except (TypeError, KeyError, ValueError, IndexError) as exc:  # a hand-made record
            raise InputError(f"{record_file} is not a result record: {exc}") from None

        def producer(hub):
            return replay(hub, events, speed, wait)

    if connect is not None:
        check_connect(connect)
        try:
            from swarmex.net.events import network_producer
        except ImportError as exc:
            raise InputError(f"--connect needs the networked runtime: {exc}") from None
        def lost() -> None:  # a --linger counts from here, as from an end event
            if linger is not None:
                asyncio.get_running_loop().call_later(linger, server.stop_now)

        producer = network_producer(connect, say=_say, on_lost=lost)

    def ready(srv: MonitorServer) -> None:
        what = address_note(srv.port, wait=wait, has_mission=record is not None or live is not None,
                            connect=connect)
        console.print(f"swarmex monitor: {srv.url} ({what})", soft_wrap=True, highlight=False)
        console.file.flush()

    asyncio.run(server.run(producer, linger, ready))
