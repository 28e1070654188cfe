"""``swarmex traverse`` and ``swarmex demo`` (seed 000's traversal mission).

Conventions the options follow (also in ``--help``):

* Cells are ``x,y`` with x the column and y the row, row 0 the first map row (DESIGN.md);
  lists are ``"x,y;x,y;…"``.
* ``--travel-time`` is seconds per unit edge (a diagonal of ``--connectivity 8`` takes √2
  times as long); ``--job-time`` seconds per job.
* Nests: agent *i* starts at nest ``i mod len(nests)``, so fewer nests than agents are shared
  round-robin (the thesis runs 1..m nests; several agents on one nest is its standard
  setting), and listing a cell twice is the same as sharing it. More nests than agents is an
  error (a nest nobody uses is a typo). Without ``--nests`` every agent starts at the first
  free cell in row-major order (smallest y, then smallest x).
* Obstacles listed twice are harmless; ``--obstacles`` may add walls to a ``--map`` too.

Every bad input raises :class:`~swarmex.errors.InputError` before the mission runs (output
paths included), so a long run never dies at the end on an unwritable file.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.table import Table

from swarmex.cli.app import app, console
from swarmex.cli.outputs import RENDER_SUFFIXES, check_output
from swarmex.errors import InputError

# Defaults of the timing options: the thesis's base agent (§5.1: 6.67 m edges flown at 3 m/s,
# 10 s jobs, climb 1.5 m/s, descent 0.3 m/s) without the 5 m takeoff, so additional_time is
# the return flight alone unless --altitude is given.
DEFAULTS: dict[str, Any] = {
    "travel_time": 2.22,
    "job_time": 10.0,
    "objective": "sum",
    "connectivity": 4,
    "start_interval": 0.5,
    "altitude": 0.0,
    "up_speed": 1.5,
    "down_speed": 0.3,
    "comm_range": None,
    "loss": 0.0,
    "delay": 0.0,
    "job_failure": 0.0,
}
OBJECTIVES = ("sum", "makespan")
MAX_GRID_CELLS = 16_000_000  # a 4000x4000 grid; beyond that the arrays alone exhaust memory

_CELL = re.compile(r"^\s*(-?\d+)\s*,\s*(-?\d+)\s*$")
_GRID = re.compile(r"^\s*(\d+)\s*[xX×]\s*(\d+)\s*$")


# ---------------------------------------------------------------------------- parsing


def parse_cells(text: str, option: str) -> list[tuple[int, int]]:
    """``"x,y;x,y"`` → ``[(x, y), …]``; empty parts (a trailing ``;``) are skipped."""
    cells = []
    for part in text.split(";"):
        if not part.strip():
            continue
        m = _CELL.match(part)
        if not m:
            raise InputError(f'{option}: malformed cell {part.strip()!r} (expected "x,y;x,y;…")')
        cells.append((int(m[1]), int(m[2])))
    return cells


def parse_grid(spec: str) -> tuple[int, int]:
    m = _GRID.match(spec)
    if not m:
        raise InputError(f"--grid: expected WxH such as 10x10, got {spec!r}")
    w, h = int(m[1]), int(m[2])
    if w < 1 or h < 1:
        raise InputError(f"--grid: width and height must be >= 1, got {spec!r}")
    if w * h > MAX_GRID_CELLS:
        raise InputError(f"--grid: {w}x{h} has more than {MAX_GRID_CELLS:,} cells")
    return w, h


def build_world(
    map_file: Path | None,
    grid: str | None,
    obstacles: list[tuple[int, int]],
    connectivity: int,
):
    """The GridWorld of ``--map`` or ``--grid``, with the ``--obstacles`` cells blocked."""
    from swarmex.worlds import GridWorld, load_movingai

    if (map_file is None) == (grid is None):
        raise InputError("give exactly one of --map FILE or --grid WxH")
    if connectivity not in (4, 8):
        raise InputError(f"--connectivity must be 4 or 8, got {connectivity}")
    if map_file is not None:
        base = load_movingai(map_file, connectivity=connectivity)
    else:
        w, h = parse_grid(grid)
        base = GridWorld(np.ones((h, w), dtype=bool), connectivity, source=f"grid {w}x{h}")
    if not obstacles:
        return base
    free = base.free.copy()
    for x, y in _checked(base, obstacles, "--obstacles"):
        free[y, x] = False
    return GridWorld(free, connectivity, source=base.source, terrain=base.terrain)


def _checked(world, cells: list[tuple[int, int]], option: str) -> list[tuple[int, int]]:
    for x, y in cells:
        if not world.in_bounds(x, y):
            raise InputError(
                f"{option}: cell ({x},{y}) is outside the {world.width}x{world.height} map"
            )
    return cells


def resolve_nests(world, nests: str | None, agents: int) -> list[int]:
    """One start vertex per agent (round-robin over the given nests; see module doc)."""
    if agents < 1:
        raise InputError(f"--agents must be at least 1, got {agents}")
    if agents > world.free_cells:
        raise InputError(f"{agents} agents but the map has only {world.free_cells} free cells")
    if nests is None:
        return [int(np.flatnonzero(world.free.ravel())[0])] * agents
    cells = parse_cells(nests, "--nests")
    if not cells:
        raise InputError("--nests: no cell given")
    if len(cells) > agents:
        raise InputError(f"--nests: {len(cells)} nests for only {agents} agents")
    for x, y in _checked(world, cells, "--nests"):
        if not world.free[y, x]:
            raise InputError(f"--nests: cell ({x},{y}) is an obstacle")
    return [world.node(*cells[i % len(cells)]) for i in range(agents)]


# ---------------------------------------------------------------------------- output

_AGENT_COLUMNS = (  # per-agent record key, header, the record's total of it
    ("nodes_done", "jobs", "nodes_done_all"),
    ("nodes_traveled", "visits", None),
    ("nodes_without_job", "w/o job", "nodes_without_job_all"),
    ("travel_time", "travel", "travel_time_all"),
    ("job_time", "job", "job_time_all"),
    ("total_time", "total", "total_time_all"),
    ("additional_time", "add'l", "additional_time_all"),
)
MAX_ROWS = 20


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.1f}"
    return "" if v is None else str(v)


def print_summary(record: dict) -> None:
    """Rich table: one row per agent (its nest and seed-000 metrics), then the totals."""
    agents = record.get("agents", [])
    present = {k for a in agents for k in a.get("metrics", {})}
    cols = [c for c in _AGENT_COLUMNS if c[0] in present]
    world = record.get("world", {})
    table = Table(
        title=f"{record.get('mission')} · {record.get('algorithm')} · {world.get('source')}"
        f" · seed {record.get('seed')}",
        title_justify="left",
        caption="times in s; visits = nodes traveled; add'l = takeoff + return + landing",
        caption_justify="left",
    )
    table.add_column("agent", justify="right")
    table.add_column("nest")
    for _, header, _ in cols:
        table.add_column(header, justify="right")
    for a in agents[:MAX_ROWS]:
        traj = a.get("trajectory") or []
        nest = f"({traj[0][1]:g},{traj[0][2]:g})" if traj else ""
        table.add_row(str(a["id"]), nest, *(_fmt(a["metrics"].get(k)) for k, _, _ in cols))
    if len(agents) > MAX_ROWS:
        table.add_row("…", f"{len(agents) - MAX_ROWS} more", *([""] * len(cols)))
    totals = record.get("metrics", {})
    row = []
    for key, _, total in cols:  # the record's own total, else the sum over agents
        value = totals.get(total) if total else None
        if value is None:
            value = sum(a["metrics"].get(key) or 0 for a in agents)
        row.append(_fmt(value))
    table.add_section()
    table.add_row("all", "", *row, style="bold")
    console.print(table)
    complete = "[green]complete[/]" if record.get("complete") else "[red]incomplete[/]"
    extras = [
        f"makespan {_fmt(record.get('makespan'))} {record.get('time_unit', '')}",
        f"total_time_all {_fmt(totals.get('total_time_all'))}",
    ]
    for key in ("duplicate_jobs", "nodes_missed", "messages"):
        if key in totals:
            extras.append(f"{key} {totals[key]}")
    extras.append(f"wall {record.get('wall_seconds', 0.0):.2f} s")
    console.print(f"{complete} · " + " · ".join(extras))


def run_and_report(
    world,
    nests: list[int],
    params: dict,
    json_path: Path | None,
    render: Path | None,
) -> dict:
    """Run the mission described by ``params`` on ``world``, print, write and draw it."""
    from swarmex.comm.channel import Channel
    from swarmex.engine.record import write_record
    from swarmex.missions.traversal import run_traversal, traversal_record, uniform_agents

    p = params
    specs = uniform_agents(
        nests,
        p["travel_time"],
        p["job_time"],
        1.0,
        p["altitude"],
        p["up_speed"],
        p["down_speed"],
    )
    if p["algorithm"] == "optimal":
        record = _optimal(world, specs, p)
    else:
        comm = math.inf if p["comm_range"] is None else p["comm_range"]
        run = run_traversal(
            world,
            specs,
            p["algorithm"],
            p["seed"],
            Channel(p["loss"], p["delay"], comm),
            start_interval=p["start_interval"],
            job_failure=p["job_failure"],
        )
        record = traversal_record(run, params)
    data = record.to_dict()
    print_summary(data)
    if json_path is not None:
        write_record(record, json_path)
        console.print(f"wrote {json_path}")
    if render is not None:
        from swarmex.viz.traversal import render_traversal

        render_traversal(data, world, render)
        console.print(f"wrote {render}")
    return data


def _optimal(world, specs, p: dict):
    """``--algorithm optimal``: the exact MILP (imported lazily: it pulls in the solver)."""
    try:
        from swarmex.missions.traversal.optimal import optimal_record
    except ModuleNotFoundError as exc:
        if exc.name != "swarmex.missions.traversal.optimal":
            raise
        raise InputError("--algorithm optimal is not available in this installation") from None
    return optimal_record(world, specs, p["objective"], p["seed"], p, 1.0)


def where_params(map_file, grid, blocked, world, nest_nodes) -> dict[str, Any]:
    """The first keys of a traversal record's params, the same for ``swarmex traverse`` and
    ``swarmex serve``: the map or grid, the blocked cells, the team size and its nests."""
    return {
        "map": None if map_file is None else str(map_file),
        "grid": grid,
        "obstacles": [list(c) for c in blocked],
        "agents": len(nest_nodes),
        "nests": [list(world.xy(n)) for n in nest_nodes],
    }


# ---------------------------------------------------------------------------- commands


@app.command()
def traverse(
    map_file: Path | None = typer.Option(
        None, "--map", help="MovingAI .map file (or give --grid).", show_default=False
    ),
    grid: str | None = typer.Option(
        None, "--grid", help="Empty WxH grid, e.g. 10x10 (or give --map).", show_default=False
    ),
    obstacles: str | None = typer.Option(
        None, "--obstacles", help='Blocked cells "x,y;x,y;…" (x column, y row).'
    ),
    agents: int = typer.Option(..., "--agents", help="Number of agents (>= 1)."),
    nests: str | None = typer.Option(
        None,
        "--nests",
        help='Start cells "x,y;…", shared round-robin when fewer than agents. '
        "Default: the first free cell in row-major order.",
    ),
    travel_time: float = typer.Option(
        DEFAULTS["travel_time"],
        "--travel-time",
        help="Seconds per grid edge (thesis: 6.67 m at 3 m/s).",
    ),
    job_time: float = typer.Option(DEFAULTS["job_time"], "--job-time", help="Seconds per job."),
    algorithm: str = typer.Option(
        "madgta", "--algorithm", help="madgta | madgta+ | nearest | optimal (exact MILP)."
    ),
    objective: str = typer.Option(
        DEFAULTS["objective"],
        "--objective",
        help="What optimal minimises: sum (thesis §3.1) | makespan.",
    ),
    connectivity: int = typer.Option(
        DEFAULTS["connectivity"], "--connectivity", help="4 or 8 neighbours per cell."
    ),
    start_interval: float = typer.Option(
        DEFAULTS["start_interval"], "--start-interval", help="Seconds between agents' starts."
    ),
    altitude: float = typer.Option(
        DEFAULTS["altitude"], "--altitude", help="Working altitude, metres."
    ),
    up_speed: float = typer.Option(DEFAULTS["up_speed"], "--up-speed", help="Climb speed, m/s."),
    down_speed: float = typer.Option(
        DEFAULTS["down_speed"], "--down-speed", help="Descent speed, m/s."
    ),
    comm_range: float | None = typer.Option(
        None,
        "--comm-range",
        help="Broadcast range in cells (default: unlimited).",
        show_default=False,
    ),
    loss: float = typer.Option(
        DEFAULTS["loss"], "--loss", help="Probability a receiver misses a message."
    ),
    delay: float = typer.Option(DEFAULTS["delay"], "--delay", help="Message delay, seconds."),
    job_failure: float = typer.Option(
        DEFAULTS["job_failure"], "--job-failure", help="Probability a job fails and must be redone."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of every random choice."),
    json_path: Path | None = typer.Option(
        None, "--json", help="Write the result record here.", show_default=False
    ),
    render: Path | None = typer.Option(
        None,
        "--render",
        help="Draw the paths (.png) or animate the run (.gif, .mp4).",
        show_default=False,
    ),
) -> None:
    """Every agent does a job at every free cell (seed 000, MADGTA and baselines)."""
    if objective not in OBJECTIVES:
        raise InputError(f"--objective must be sum or makespan, got {objective!r}")
    check_output(json_path, "--json")
    check_output(render, "--render", RENDER_SUFFIXES)
    blocked = parse_cells(obstacles or "", "--obstacles")
    world = build_world(map_file, grid, blocked, connectivity)
    nest_nodes = resolve_nests(world, nests, agents)
    params = {
        **where_params(map_file, grid, blocked, world, nest_nodes),
        "travel_time": travel_time,
        "job_time": job_time,
        "algorithm": algorithm,
        "objective": objective,
        "connectivity": connectivity,
        "start_interval": start_interval,
        "altitude": altitude,
        "up_speed": up_speed,
        "down_speed": down_speed,
        "comm_range": comm_range,
        "loss": loss,
        "delay": delay,
        "job_failure": job_failure,
        "seed": seed,
    }
    run_and_report(world, nest_nodes, params, json_path, render)


DEMO_AGENTS = 4


@app.command()
def demo(
    out: Path = typer.Option(Path("swarmex-demo.png"), "--out", help="Where to write the PNG."),
    seed: int = typer.Option(0, "--seed", help="Seed of the run's random choices."),
) -> None:
    """Run MADGTA on an embedded generated map, print a summary and draw the paths."""
    from swarmex.worlds import random_obstacles

    out = out.resolve()  # say exactly where the picture went
    check_output(out, "--out", (".png",))
    world = random_obstacles(16, 16, 0.18, seed=7)
    nest_nodes = resolve_nests(world, None, DEMO_AGENTS)
    params = {
        "map": None,
        "grid": None,
        "generated": world.source,
        "obstacles": [],
        "agents": DEMO_AGENTS,
        "nests": [list(world.xy(n)) for n in nest_nodes],
        "algorithm": "madgta",
        "seed": seed,
        **DEFAULTS,
    }
    console.print(
        f"demo: {DEMO_AGENTS} agents from one nest on a generated {world.width}x{world.height}"
        f" map ({world.free_cells} free cells)"
    )
    run_and_report(world, nest_nodes, params, None, out)
