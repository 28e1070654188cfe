"""``swarmex forage`` and ``swarmex reproduce foraging`` (seed 002's foraging mission).

The options of ``forage``, their defaults and checks (food placement, bands, team-size rules
of each pattern, the grid's size limit) are the mission's (missions/foraging/params.py); this
module only prints the summary table and draws the run.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.table import Table

from swarmex.cli.app import console, err_console, reproduce_app
from swarmex.cli.missions import Surface, mission_command, progress_bar
from swarmex.cli.outputs import check_out_dir, study
from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, Outcome
from swarmex.missions.registry import get


def report(outcome: Outcome, params: Any) -> None:
    """Rich table: the phase times of seed 002's Figs. 78–79 and the units delivered."""
    run = outcome.run
    m = run.metrics
    # recall plays the pattern it chose: name it
    played = run.algorithm if run.pattern == run.algorithm else f"{run.algorithm} ({run.pattern})"
    table = Table(title=f"foraging · {played} · n={run.n} · g={run.g} · food {run.food}")
    # the phases' short names (the thesis's COMM+TRANS): the long metric names were cut to
    # "communicati…" and wrapped over three lines in an 80-column terminal or a pipe
    for name in ("exploration", "communication", "COMM+TRANS", "transport", "total",
                 "delivered"):
        table.add_column(name, no_wrap=True)
    table.add_row(
        str(m["exploration_time"]),
        str(m["communication_time"]),
        str(m["comm_transport_overlap"]),
        str(m["transport_time"]),
        str(m["total_time"]),
        f"{m['food_delivered']}/{run.units}",
    )
    console.print(table)
    stalled = outcome.record.extra.get("stalled")
    if stalled is not None:
        console.print(
            f"stalled: the team locked with {m['food_delivered']} of {run.units} units home; "
            f"the run stopped at its round limit, {stalled} (a crowded End-to-End team, see "
            "docs/foraging.md)",
            soft_wrap=True,
        )


def recall_status(params: Any, world: Any, on_frame: FrameCallback | None) -> FrameCallback | None:
    """Recall replays the patterns on the remembered distances before the run (seconds on
    128 × 128, minutes on the largest grids): a bar on a terminal. The run's own choice then
    reads the cached replays. Then the run's own bar (robots told, units home)."""
    if params.algorithm == "recall" and err_console.is_terminal:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

        from swarmex.missions.foraging.recall import choose

        columns = ("{task.description}", BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
        with Progress(*columns, console=err_console, transient=True) as bar:
            task = bar.add_task("recall: replaying the patterns", total=None)

            def tick(done: int, total: int) -> None:
                bar.update(task, completed=done, total=total)

            choose(params.grid, params.agents, params.found, params.food_units,
                   params.transport, params.comm, on_replay=tick)  # fmt: skip
    return _run_bar(params, world, on_frame)


_run_bar = progress_bar(get("foraging"))
forage = mission_command(get("foraging"), Surface(report, watch=recall_status))


@reproduce_app.command("foraging")
def reproduce_foraging(
    out: Path = typer.Option(Path("reproduction/foraging"), "--out", help="Output directory."),
    quick: bool = typer.Option(
        False, "--quick", help="One food cell per band: a smoke test, well under a minute."
    ),
    workers: int = typer.Option(2, "--workers", help="Worker processes."),
    seed: int | None = typer.Option(
        None, "--seed", help="Seed of the food positions (default: the study's, 2015)."
    ),
) -> None:
    """Regenerate Figs. 56–79 of seed 002 (128×128 grid) beside the thesis's numbers."""
    from swarmex.experiments.pool import check_workers
    from swarmex.studies.foraging import reproduce

    check_workers(workers)  # 100,000 workers forked until the OOM killer came
    if seed is not None and seed < 0:
        raise InputError(f"--seed must be at least 0, got {seed}")
    check_out_dir(out)
    chosen = {} if seed is None else {"seed": seed}  # the study owns its default seed
    with study(out / "runs.jsonl"):
        report = reproduce(out, quick=quick, workers=workers, **chosen)
    console.print(f"report → {report}")
