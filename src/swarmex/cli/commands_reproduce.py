"""Commands of the reproduce surface (registered on import).

This module holds ``swarmex reproduce traversal`` only; other studies register their own
commands on the same ``reproduce_app`` from their own modules.
"""

from __future__ import annotations

from pathlib import Path

import typer

from swarmex.cli.app import console, reproduce_app
from swarmex.cli.outputs import check_out_dir, study
from swarmex.errors import InputError


@reproduce_app.command("traversal")
def reproduce_traversal(
    out: Path = typer.Option(Path("reproduction/traversal"), "--out", help="Output directory."),
    quick: bool = typer.Option(
        False, "--quick", help="Reduced plan (3 bars per figure, a few runs each): < 1 min."
    ),
    workers: int | None = typer.Option(
        None, "--workers", help="Worker processes (default 2, or 1 with --quick)."
    ),
    runs: int | None = typer.Option(
        None, "--runs", help="Runs per table group / figure bar (default 108, quick 2–6)."
    ),
) -> None:
    """Rerun seed 000's chapter-5 simulations (Tables 5.1–5.2, Figs. 5.1–5.14).

    Writes OUT/traversal.json (every run, resumable), OUT/fig_5_*.png and OUT/traversal.md
    (the thesis's numbers and ours side by side).
    """
    from swarmex.experiments.pool import check_workers
    from swarmex.studies.traversal import reproduce

    check_workers(workers)  # 100,000 workers forked until the OOM killer came
    if runs is not None and runs < 1:
        raise InputError(f"--runs must be >= 1, got {runs}")
    check_out_dir(out)  # a folder that cannot be made was a mkdir traceback
    with study(out / "traversal.json"):  # Ctrl-C was a bare "interrupted"; compiles silent
        result = reproduce(out, quick=quick, workers=workers, reps=runs, console=console)
    console.print(
        f"{result['runs']} runs ({result['executed']} executed now, {result['workers']} "
        f"worker(s), {result['elapsed_s']:.1f} s); report: {result['report']}; "
        f"{len(result['figures'])} figures; raw runs: {result['json']}"
    )
