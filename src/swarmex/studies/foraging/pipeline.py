"""``swarmex reproduce foraging``: plan, run (or resume), analyse, draw and report."""

from __future__ import annotations

import os
from pathlib import Path

from swarmex.experiments.progress import read_journal
from swarmex.studies.foraging.analysis import (
    aggregate,
    exact_exploration,
    single_agent_exploration,
    write_csv,
)
from swarmex.studies.foraging.design import food_cells, reference, run_key, tasks
from swarmex.studies.foraging.runs import execute


def reproduce(out: Path, quick: bool = False, workers: int = 2, seed: int = 2015) -> Path:
    from swarmex.studies.foraging.figures import all_figures
    from swarmex.studies.foraging.report import write_report

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    per_band = 1 if quick else 40
    foods = food_cells(seed, per_band)
    todo = tasks(foods)
    workers = max(1, min(workers, os.cpu_count() or 1))
    execute(todo, out / "runs.jsonl", workers)
    runs = read_journal(out / "runs.jsonl")
    keys = {run_key(t[0], t[1], t[2], t[3], t[5]) for t in todo}
    runs = {k: v for k, v in runs.items() if k in keys}
    table = aggregate(runs)
    single = single_agent_exploration(foods)
    write_csv(table, out / "foraging_results.csv")
    figures = all_figures(table, single, out)
    exact = exact_exploration()
    return write_report(
        out, table, single, reference(), figures, quick, seed, per_band, runs, exact
    )
