"""``swarmex serve``, ``swarmex agent`` and ``swarmex watch``: the networked traversal runtime.

``serve`` takes the mission options of ``swarmex traverse`` (parsed by the same helpers, so a
map, grid, nests or obstacles mean the same thing) plus the network's: ``--port``,
``--time-scale`` (wall seconds per mission second), ``--rng``, heartbeats and timeouts. It
writes the same result record as ``traverse`` (plus ``network`` and ``departed_agents``).
``agent --connect tcp://HOST:PORT`` runs one UAV (or ``--count K`` of them in one process);
``--vehicle LINK`` flies a MAVLink copter instead of the simulated one (docs/uav.md).
``watch --connect tcp://HOST:PORT`` prints the live mission in the terminal, or forwards it
to the web monitor's ingest WebSocket with ``--forward``. The protocol is described in
:mod:`swarmex.net.traversal` and docs/net.md.
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from swarmex.cli.app import app, console
from swarmex.cli.outputs import check_output
from swarmex.cli.shared import _say, _warn, check_connect, parse_kills, run_mesh
from swarmex.errors import InputError, require
from swarmex.missions.traversal.params import ALGORITHMS, TraversalParams, algorithm_name
from swarmex.net.limits import check_ingest_url, check_wall_seconds, check_wire_seed
from swarmex.net.vehicle import Safety

_TRAVERSAL = TraversalParams.options()
#: what the networked runtime serves: every online algorithm, not the whole-mission MILP;
#: madgta-s's team plan rides on its decisions' frames, and the leave of an agent that stops
#: early (madgta-h, madgta-s) on its C09 (the job bit)
SERVED = tuple(a for a in ALGORITHMS if a != "optimal")
_SAFETY = Safety()  # the vehicle limits' defaults (swarmex.net.vehicle)


def _default(name: str):  # the traversal mission owns every default (missions/traversal)
    return _TRAVERSAL[name].default

HOSTS_HELP = "Interface to bind (127.0.0.1 = this machine only; * = all)."


def _address(connect: str) -> str:
    check_connect(connect)  # a port out of range too (it was taken, and failed later)
    return connect


@app.command()
def serve(
    map_file: Path | None = typer.Option(None, "--map", help="MovingAI .map file (or --grid)."),
    grid: str | None = typer.Option(None, "--grid", help="Empty WxH grid (or --map)."),
    obstacles: str | None = typer.Option(None, "--obstacles", help='Blocked cells "x,y;…".'),
    agents: int | None = typer.Option(
        None, "--agents", help="Number of agent ids (>= 1); with --fleet, its rows."
    ),
    nests: str | None = typer.Option(None, "--nests", help='Start cells "x,y;…" (round-robin).'),
    travel_time: float = typer.Option(
        _default("travel_time"), "--travel-time", help="Seconds per grid edge."
    ),
    job_time: float = typer.Option(_default("job_time"), "--job-time", help="Seconds per job."),
    algorithm: str = typer.Option(
        _default("algorithm"), "--algorithm",
        help="madgta | madgta+ | madgta-h | madgta-r | madgta-p | madgta-k | madgta-f | madgta-s"
        " | nearest;"
        " NAME@KEY=VALUE,... sets a policy's options.",
    ),
    connectivity: int = typer.Option(_default("connectivity"), "--connectivity", help="4 or 8."),
    start_interval: float = typer.Option(
        _default("start_interval"), "--start-interval", help="Seconds between agents' starts."
    ),
    altitude: float = typer.Option(_default("altitude"), "--altitude", help="Altitude, m."),
    up_speed: float = typer.Option(_default("up_speed"), "--up-speed", help="Climb, m/s."),
    down_speed: float = typer.Option(_default("down_speed"), "--down-speed", help="Descent, m/s."),
    job_failure: float = typer.Option(
        _default("job_failure"), "--job-failure", help="Probability a job fails."
    ),
    seed: int = typer.Option(_default("seed"), "--seed", help="Seed of every random choice."),
    fleet: Path | None = typer.Option(
        None, "--fleet", metavar="FILE", help="Per-agent values by id (as swarmex traverse)."
    ),
    edge_length: float | None = typer.Option(
        None, "--edge-length", help="Metres per grid edge (for fleet speeds in m/s)."
    ),
    center: str | None = typer.Option(
        None, "--center", metavar="LAT,LON", help="GPS grid centre (or --map / --grid)."
    ),
    radius: float | None = typer.Option(None, "--radius", help="GPS grid: half its side, m."),
    nodes_on_edge: int | None = typer.Option(
        None, "--nodes-on-edge", help="GPS grid: K nodes on an edge."
    ),
    port: int = typer.Option(..., "--port", help="TCP port to listen on (0: a free one)."),
    host: str = typer.Option("127.0.0.1", "--host", help=HOSTS_HELP),
    time_scale: float = typer.Option(
        0.01, "--time-scale", help="Wall seconds per mission second (0: as fast as possible)."
    ),
    rng: str = typer.Option(
        "shared",
        "--rng",
        help="shared: the run's one generator travels with the steps (= swarmex traverse);"
        " own: one generator per agent.",
    ),
    done_lists: bool = typer.Option(
        True, "--done-lists/--no-done-lists", help="Carry Fig. 4.17's done-nodes list."
    ),
    inject_loss: float = typer.Option(
        0.0, "--inject-loss",
        help="Fault injection: probability that an agent's radio loses a relayed broadcast.",
    ),
    heartbeat: float = typer.Option(0.25, "--heartbeat", help="Wall seconds between beats."),
    dead_after: float = typer.Option(
        2.0, "--dead-after", help="Wall seconds of silence before an agent is declared gone."
    ),
    init_timeout: float = typer.Option(
        60.0, "--init-timeout",
        help="Wall seconds an agent not yet started may be silent (it compiles its kernels on"
             " a first start); never less than --dead-after.",
    ),
    spare_wait: float = typer.Option(
        0.0, "--spare-wait", help="Wall seconds to wait for a spare when all agents are gone."
    ),
    timeout: float = typer.Option(600.0, "--timeout", help="Give up after this many seconds."),
    monitor_url: str | None = typer.Option(
        None, "--monitor", help="Also push events to a web monitor: ws://127.0.0.1:PORT/ingest."
    ),
    json_path: Path | None = typer.Option(None, "--json", help="Write the result record here."),
) -> None:
    """Seed 000's mission server: ids, mission data, relay, monitor, result record."""
    import zmq

    from swarmex.net.server import TraversalServer
    from swarmex.net.traversal import Mission

    check_output(json_path, "--json")
    if not 0 <= port <= 65535:
        raise InputError(f"--port must be in 0..65535, got {port}")
    # wall times are bounded above too: 1e307 s overflowed the socket poll's milliseconds
    check_wall_seconds(time_scale, "--time-scale", zero_ok=True,
                       unit="(wall seconds per mission second)")
    for value, option in ((heartbeat, "--heartbeat"), (dead_after, "--dead-after"),
                          (init_timeout, "--init-timeout"), (timeout, "--timeout")):
        check_wall_seconds(value, option)
    check_wall_seconds(spare_wait, "--spare-wait", zero_ok=True)
    if not 0.0 <= inject_loss < 1.0:
        raise InputError(f"--inject-loss must be in [0, 1), got {inject_loss}")
    if dead_after <= heartbeat:
        raise InputError("--dead-after must be longer than --heartbeat")
    check_ingest_url(monitor_url, "--monitor")
    if monitor_url is not None:
        require("websockets", "monitor", "--monitor")
    from swarmex.missions.registry import get
    from swarmex.missions.traversal.mission import agent_specs, record_params

    if algorithm_name(algorithm) not in SERVED:  # before the params' list, which has optimal
        raise InputError(
            f"--algorithm must be {', '.join(SERVED[:-1])} or {SERVED[-1]}, got {algorithm!r}"
        )
    traversal = get("traversal")
    tparams = traversal.params(
        {
            "map": map_file, "grid": grid, "obstacles": obstacles, "agents": agents,
            "nests": nests, "travel_time": travel_time, "job_time": job_time,
            "algorithm": algorithm, "connectivity": connectivity,
            "start_interval": start_interval, "altitude": altitude, "up_speed": up_speed,
            "down_speed": down_speed, "job_failure": job_failure, "seed": seed,
            "fleet": fleet, "edge_length": edge_length, "center": center, "radius": radius,
            "nodes_on_edge": nodes_on_edge,
        }
    )
    check_wire_seed(tparams.seed, "the mission data")
    prepared = traversal.prepare(tparams)
    world = prepared.world
    specs = agent_specs(tparams, prepared)
    from swarmex.missions.traversal.sim import validate_nests

    validate_nests(world, specs)
    params = {  # the keys of swarmex traverse's record, then the network's own
        **record_params(tparams, prepared),
        "network": {"time_scale": time_scale, "rng": rng, "done_lists": done_lists,
                    "heartbeat": heartbeat, "dead_after": dead_after,
                    "init_timeout": init_timeout},
    }
    if inject_loss > 0:
        params["network"]["inject_loss"] = inject_loss
    mission = Mission(world, specs, tparams.algorithm, seed, start_interval, prepared.unit_length,
                      job_failure, time_scale, rng, done_lists, heartbeat, params,
                      edge_length=tparams.edge_length)
    bind = f"tcp://{host}:{port}" if port else f"tcp://{host}:*"
    try:
        server = TraversalServer(mission, bind, json_path, timeout, dead_after,
                                 init_timeout=init_timeout, spare_wait=spare_wait,
                                 monitor_url=monitor_url, say=_say, loss=inject_loss)
    except zmq.ZMQError as exc:  # address in use, bad interface
        raise InputError(f"cannot listen on {bind}: {exc}") from None
    code = server.run()
    raise typer.Exit(code)


@app.command()
def agent(
    connect: str = typer.Option(..., "--connect", help="The server: tcp://HOST:PORT."),
    agent_id: int = typer.Option(0, "--id", help="Ask for this id (0: any vacant one)."),
    count: int = typer.Option(1, "--count", help="Agents run by this process."),
    spare: bool = typer.Option(
        False, "--spare",
        help="Only take an id vacated or handed back (mid-mission, or before the start); wait"
             " for one.",
    ),
    spares: int = typer.Option(
        0, "--spares", help="Also run this many spares in this process (as --spare)."
    ),
    server_timeout: float = typer.Option(
        10.0, "--server-timeout", help="Exit when the server is silent this long (s)."
    ),
    connect_timeout: float = typer.Option(
        30.0, "--connect-timeout",
        help="Keep asking for a vacant id this long (s); a spare waits for the whole mission "
        "while the server answers.",
    ),
    timeout: float = typer.Option(3600.0, "--timeout", help="Give up after this long (s)."),
    corrupt: float = typer.Option(
        0.0, "--inject-corrupt", help="Fault injection: share of frames preceded by a bad copy."
    ),
    die_after: int | None = typer.Option(
        None, "--inject-die-after", help="Fault injection: exit abruptly after K events."
    ),
    fault_seed: int = typer.Option(0, "--fault-seed", help="Seed of the fault injection."),
    vehicle: str | None = typer.Option(
        None, "--vehicle",
        help="Fly a MAVLink copter: udp:HOST:PORT (it listens; swarmex uav-emulator),"
        " udpin:HOST:PORT, tcp:HOST:PORT, serial:DEVICE[:BAUD]. Default: simulated.",
    ),
    edge_length: float | None = typer.Option(
        None, "--edge-length",
        help="Vehicle: metres between grid neighbours (default: serve's --edge-length, else "
        "6.67).",
    ),
    min_altitude: float = typer.Option(
        _SAFETY.min_altitude, "--min-altitude", help="Vehicle: fly at least this high, m."
    ),
    max_altitude: float = typer.Option(
        _SAFETY.max_altitude, "--max-altitude", help="Vehicle: refuse missions above, m."
    ),
    max_speed: float = typer.Option(
        _SAFETY.max_speed, "--max-speed", help="Vehicle: ground speed cap, m/s."
    ),
    max_distance: float = typer.Option(
        _SAFETY.max_distance, "--max-distance",
        help="Vehicle: refuse missions with a node farther from home, m.",
    ),
    min_satellites: int = typer.Option(
        _SAFETY.min_satellites, "--min-satellites", help="Vehicle pre-arm: GPS satellites."
    ),
    max_hdop: float = typer.Option(
        _SAFETY.max_hdop, "--max-hdop", help="Vehicle pre-arm: GPS horizontal DOP."
    ),
    arm_battery: float = typer.Option(
        _SAFETY.arm_battery, "--arm-battery", help="Vehicle pre-arm: battery percent."
    ),
    min_battery: float = typer.Option(
        _SAFETY.min_battery, "--min-battery",
        help="Vehicle: below this percent in flight, hand the id back and land.",
    ),
    link_timeout: float = typer.Option(
        _SAFETY.link_timeout, "--link-timeout",
        help="Vehicle: seconds without telemetry before the link counts as lost.",
    ),
    nest_radius: float = typer.Option(
        _SAFETY.nest_radius, "--nest-radius",
        help="Vehicle pre-arm on a GPS grid: metres it may stand off its nest.",
    ),
) -> None:
    """One traversal UAV as a client of 'swarmex serve' (seed 000's client.py)."""
    from swarmex.net.agent import Faults, run_agents

    address = _address(connect)
    if count < 1:
        raise InputError(f"--count must be >= 1, got {count}")
    if agent_id < 0 or (agent_id and count > 1):
        raise InputError("--id must be >= 0, and only with --count 1")
    if spare and agent_id:
        raise InputError("give --spare or --id, not both")
    if spares < 0:
        raise InputError(f"--spares must be >= 0, got {spares}")
    if not 0.0 <= corrupt < 1.0:
        raise InputError(f"--inject-corrupt must be in [0, 1), got {corrupt}")
    if die_after is not None and die_after < 1:
        raise InputError(f"--inject-die-after must be >= 1, got {die_after}")
    for value, option in ((server_timeout, "--server-timeout"),
                          (connect_timeout, "--connect-timeout"), (timeout, "--timeout")):
        check_wall_seconds(value, option)  # 1e308 s overflowed the wait's milliseconds
    faults = Faults(corrupt, die_after, fault_seed)  # checks --fault-seed >= 0
    # the vehicle limits are checked with or without --vehicle: a typo in them used to pass
    # silently until the day --vehicle was added, then fail
    limits = Safety(
        edge_length=edge_length, min_altitude=min_altitude, max_altitude=max_altitude,
        max_speed=max_speed, max_distance=max_distance, min_satellites=min_satellites,
        max_hdop=max_hdop, arm_battery=arm_battery, min_battery=min_battery,
        link_timeout=link_timeout, nest_radius=nest_radius,
    )
    want = -1 if spare else agent_id
    flown = None
    safety = None
    if vehicle is not None:
        from swarmex.cli.commands_uav import open_agent_vehicle

        if count != 1 or spares:
            raise InputError("--vehicle flies one agent: not with --count or --spares")
        flown, safety = open_agent_vehicle(vehicle, limits)
    code = run_agents(address, count, want, server_timeout, connect_timeout, timeout, faults,
                      _say, spares, flown, safety, warn=_warn)
    raise typer.Exit(code)


@app.command()
def watch(
    connect: str = typer.Option(..., "--connect", help="A mission server: tcp://HOST:PORT."),
    forward: str | None = typer.Option(
        None, "--forward", help="Push the events to ws://127.0.0.1:PORT/ingest instead."
    ),
    timeout: float = typer.Option(10.0, "--timeout", help="Exit after this long without news."),
    json_path: Path | None = typer.Option(None, "--events", help="Also save the events (JSON)."),
) -> None:
    """The live view of a networked mission in the terminal (or fed to the web monitor)."""
    from swarmex.net.events import IngestForwarder, viewer_batches
    from swarmex.net.watch import TerminalView

    address = _address(connect)
    check_wall_seconds(timeout, "--timeout")
    check_output(json_path, "--events")
    check_ingest_url(forward, "--forward")
    if forward is not None:  # before connecting, not as a traceback in the sender's thread
        require("websockets", "monitor", "--forward")
    forwarder = IngestForwarder(forward, warn=_warn) if forward else None
    view = TerminalView(console, live=sys.stdout.isatty(), quiet=forwarder is not None)
    saved: list = []
    try:
        for batch in viewer_batches(address, timeout):
            if json_path is not None:
                saved.extend(batch)
            if forwarder is not None:
                forwarder.send(batch)
            view.update(batch)
    finally:  # what was seen is saved even after Ctrl-C (it used to be lost)
        if forwarder is not None:
            forwarder.close()
        view.close()
        if json_path is not None:
            from swarmex.engine.record import write_json_atomic

            write_json_atomic(saved, json_path)
    short = forwarder.shortfall() if forwarder is not None else None
    if short is not None:
        _warn(f"swarmex watch: {short}")
    if not view.ended:
        _warn("swarmex watch: no mission end seen (server gone or timeout)")
        raise typer.Exit(1)
    if forwarder is not None and forwarder.sent == 0:
        raise typer.Exit(1)  # forwarding was the whole job, and nothing arrived


@app.command(hidden=True)
def mesh(
    map_path: Path = typer.Option(None, "--map", help="MovingAI .map or ROS map."),
    empty: str = typer.Option(None, "--empty", help="Empty walled world WxH in metres."),
    cell: float = typer.Option(None, "--cell", help="Cell size in metres."),
    robots: int = typer.Option(..., "--robots", help="Team size."),
    # the mission's options: None means the exploration mission's own default
    laser_range: float = typer.Option(None, "--laser-range", help="Laser range, metres."),
    comm_range: float = typer.Option(None, "--comm-range", help="Radio range, metres."),
    strategy: str = typer.Option(None, "--strategy"),
    starts: str = typer.Option(None, "--starts", help="Start cells 'x,y;x,y;…'."),
    seed: int = typer.Option(None, "--seed"),
    robot_radius: float = typer.Option(None, "--robot-radius"),
    beams: int = typer.Option(None, "--beams"),
    max_ticks: int = typer.Option(None, "--max-ticks"),
    aodv: bool = typer.Option(None, "--aodv/--no-aodv", help="Route unicasts with AODV."),
    conflict_yield: bool = typer.Option(None, "--conflict-yield/--no-conflict-yield"),
    plan_pause: int = typer.Option(None, "--plan-pause", help="Steps still after a plan."),
    time_scale: float = typer.Option(1.0, "--time-scale", help="Wall s per mission s."),
    loss: float = typer.Option(0.0, "--inject-loss", help="Share of radio frames dropped."),
    kills: str = typer.Option(None, "--inject-kill", help="'ID@TICK;…': robots that die."),
    send_timeout: int = typer.Option(20, "--send-timeout", help="PUSH send timeout, ms."),
    timeout: float = typer.Option(600.0, "--timeout", help="Give up after this long (s)."),
    monitor_url: str = typer.Option(None, "--monitor", help="ws://…/ingest of a monitor."),
    json_path: Path = typer.Option(None, "--json", help="Write the result record here."),
) -> None:
    """'swarmex explore --processes' under another name (one process per robot)."""
    from swarmex.missions.registry import get

    check_ingest_url(monitor_url, "--monitor")  # (run_mesh checks it too: explore's path)
    if monitor_url is not None:  # the display process forwards to it: check here, in one line
        require("websockets", "monitor", "--monitor")

    exploration = get("exploration")
    params = exploration.params(
        {k: v for k, v in {
            "map": map_path, "empty": empty, "cell": cell, "robots": robots,
            "laser_range": laser_range, "comm_range": comm_range, "strategy": strategy,
            "robot_radius": robot_radius, "beams": beams, "starts": starts, "seed": seed,
            "max_ticks": max_ticks, "aodv": aodv, "conflict_yield": conflict_yield,
            "plan_pause": plan_pause,
        }.items() if v is not None}
    )
    record = run_mesh(exploration.prepare(params).grid, params, time_scale, loss,
                      parse_kills(kills), send_timeout, timeout, json_path, monitor_url)
    raise typer.Exit(0 if record["complete"] else 1)
