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

from swarmex.cli.app import console, reproduce_app
from swarmex.cli.missions import Surface, mission_command
from swarmex.cli.outputs import check_out_dir, study
from swarmex.errors import InputError
from swarmex.missions.base import Outcome
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


forage = mission_command(get("foraging"), Surface(report))


@reproduce_app.command("foraging")
def reproduce_foraging(
    out: Path = typer.Option(Path("reproduction-foraging"), "--out", help="Output directory."),
    quick: bool = typer.Option(
        False, "--quick", help="One food cell per band: a smoke test, well under a minute."
    ),
    workers: int = typer.Option(2, "--workers", help="Worker processes."),
    seed: int | None = typer.Option(
        None, "--seed", help="Seed of the food positions (default: the study's, 2015)."
    ),
) -> None:
    """Regenerate Figs. 56–79 of seed 002 (128×128 grid) beside the thesis's numbers."""
    from swarmex.studies.foraging import reproduce

    if workers < 1:
        raise InputError(f"--workers must be at least 1 (got {workers})")
    if seed is not None and seed < 0:
        raise InputError(f"--seed must be at least 0, got {seed}")
    check_out_dir(out)
    chosen = {} if seed is None else {"seed": seed}  # the study owns its default seed
    with study(out / "runs.jsonl"):
        report = reproduce(out, quick=quick, workers=workers, **chosen)
    console.print(f"report → {report}")
