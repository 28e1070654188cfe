"""``swarmex roadmap`` and ``swarmex reproduce roadmap`` (seed 004: WMA-RRT against PRM).

The options, their defaults and checks are the mission's (missions/roadmap/params.py); this
module only prints the summary line and draws the run.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import console, reproduce_app
from swarmex.cli.missions import Surface, mission_command, progress_bar
from swarmex.cli.outputs import study
from swarmex.errors import InputError
from swarmex.missions.base import Outcome
from swarmex.missions.registry import get


def summary_line(record: dict[str, Any]) -> str:
    """One line: planner, task, the end and the seed-004 metrics of a roadmap record."""
    m = record["metrics"]
    task = record["params"]["task"]
    line = (
        f"{record['algorithm']} {task}: complete={record['complete']} steps={m['steps']} "
        f"coverage={100 * m['coverage']:.1f}% nodes={m['tree_nodes']} "
        f"components={m['components']} cycles={m['cycles']} "
        f"edge_revisits={m['edge_revisits']} path={m['path_length']:.0f}"
    )
    if task == "search":
        line += f" goal_found={m['goal_found']} goal_unreachable={m['goal_unreachable']}"
    return line


def report(outcome: Outcome, params: Any) -> None:
    # soft_wrap: one line whatever the width, so that `grep steps= | cut` works on a log
    # (Rich folded it over two or three lines at a pipe's 80 columns)
    console.print(summary_line(outcome.record.to_dict()), highlight=False, soft_wrap=True)


roadmap = mission_command(
    get("roadmap"),
    Surface(report, watch=progress_bar(get("roadmap")),
            render_help="Write a .png, .gif or .mp4 of the run."),
)


@reproduce_app.command("roadmap")
def reproduce_roadmap(
    out: Path = typer.Option(Path("reproduction/roadmap"), "--out", help="Output directory."),
    quick: bool = typer.Option(False, "--quick", help="A few runs per row (under a minute)."),
    workers: int = typer.Option(2, "--workers", help="Worker processes."),
) -> None:
    """Tables 1–2, Fig. 6 and Figs. 14–17 of seed 004, beside the paper's numbers."""
    from swarmex.experiments.pool import check_workers
    from swarmex.studies.roadmap import reproduce

    check_workers(workers)  # 100,000 workers forked until the OOM killer came
    if out.exists() and not out.is_dir():  # was a FileExistsError traceback from mkdir
        raise InputError(f"--out {out} exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out: cannot create {out}: {exc.strerror}") from None
    with study(out):  # every finished run is in the journal already
        reproduce(out, quick=quick, console=console, workers=workers)
