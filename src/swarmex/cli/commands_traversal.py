"""``swarmex traverse`` and ``swarmex demo`` (seed 000's traversal mission).

The options, their defaults and checks are the mission's (missions/traversal/params.py);
this module only prints the summary table and draws the run.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.table import Table

from swarmex.cli.app import app, console, err_console
from swarmex.cli.compiling import compile_notice
from swarmex.cli.missions import Surface, mission_command, progress_bar
from swarmex.cli.outputs import check_output
from swarmex.missions.base import FrameList, Outcome
from swarmex.missions.registry import get
from swarmex.missions.traversal.mission import TraversalWorld
from swarmex.missions.traversal.params import algorithm_name
from swarmex.missions.traversal.policies import POLICIES

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
    free = record.get("world", {}).get("free_cells")
    reachable = totals.get("reachable_nodes")
    if isinstance(free, int) and isinstance(reachable, int) and reachable < free:
        # walls that cut the nests off: "complete, nodes_missed 0" said nothing of the rest
        err_console.print(
            f"note: {free - reachable:,} of the {free:,} free cells cannot be reached from the"
            " nests; the run covers the other ones", highlight=False, soft_wrap=True,
        )


def report(outcome: Outcome, params: Any) -> None:
    print_summary(outcome.record.to_dict())


#: one-shot runs on at most this many vertices run their kernels interpreted while numba is
#: not loaded (swarmex._kernels): 16x16 with 4 agents costs 0.23 s of CPU so against 0.65 s
#: compiled, most of it numba's loading; the two break even near 24x24 (576 vertices), and
#: interpreted cost grows faster than the map. Same records either way. Policies that
#: simulate the mission (madgta-r, madgta-p, madgta-k) always run compiled: interpreted,
#: madgta-p took 85 s on a 12x12 grid with 4 agents, against 0.3 s compiled.
INTERPRETED_VERTICES = 400


def small(params: Any, prepared: TraversalWorld) -> bool:
    """Whether a run on ``prepared`` is cheaper with the kernels interpreted."""
    policy = POLICIES.get(algorithm_name(params.algorithm))
    if policy is not None and policy.simulates:
        return False
    return prepared.world.graph.n_nodes <= INTERPRETED_VERTICES


traverse = mission_command(
    get("traversal"),
    Surface(report, interpreted=small, watch=progress_bar(get("traversal")),
            render_help="Draw the paths (.png) or animate the run (.gif, .mp4)."),
)

@app.command()
def demo(
    out: Path = typer.Option(Path("swarmex-demo.png"), "--out", help="Where to write the PNG."),
    seed: int = typer.Option(0, "--seed", help="Seed of the run's random choices."),
) -> None:
    """Run MADGTA on an embedded generated map, print a summary and draw the paths."""
    from swarmex._kernels import interpreted_while_cold
    from swarmex.missions.traversal.mission import demo_world
    from swarmex.missions.traversal.params import TraversalParams

    out = out.resolve()  # say exactly where the picture went
    check_output(out, "--out", (".png",))
    # the Params are built directly below, so the seed goes through its parser here
    seed = TraversalParams.options()["seed"].parse(seed, "--seed")
    with compile_notice(err_console):
        prepared = demo_world()  # 16x16: interpreted, as small() says (no kernel runs here)
        world, agents = prepared.world, len(prepared.nests)
        # a generated world has neither map nor grid, so the Params are built directly
        params = TraversalParams(agents=agents, seed=seed)
        console.print(
            f"demo: {agents} agents from one nest on a generated {world.width}x{world.height}"
            f" map ({world.free_cells} free cells)"
        )
        frames = FrameList()
        with interpreted_while_cold(small(params, prepared)):
            outcome = get("traversal").execute(params, prepared, frames)
    report(outcome, params)
    from swarmex.viz.render import draw

    draw("traversal", outcome, out, frames)
    console.print(f"wrote {out}")
