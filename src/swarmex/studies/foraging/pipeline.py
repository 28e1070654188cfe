"""``swarmex reproduce foraging``: plan, run (or resume), analyse, draw and report."""

from __future__ import annotations

import os
from pathlib import Path

from swarmex.experiments.progress import Journal
from swarmex.studies.foraging.analysis import (
    aggregate,
    exact_exploration,
    single_agent_exploration,
    write_csv,
)
from swarmex.studies.foraging.design import (
    AUTHOR,
    author_rows,
    author_tasks,
    food_cells,
    reference,
    tasks,
)
from swarmex.studies.foraging.runs import describe, run_task, task_key
from swarmex.studies.runner import run_jobs


def reproduce(out: Path, quick: bool = False, workers: int = 2, seed: int = 2015) -> Path:
    from swarmex.studies.foraging.figures import all_figures
    from swarmex.studies.foraging.report import write_report

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    per_band = 1 if quick else 40
    foods = food_cells(seed, per_band)
    author = author_rows()
    todo = tasks(foods) + author_tasks(author)
    workers = max(1, min(workers, os.cpu_count() or 1))
    with Journal(out / "runs.jsonl") as journal:
        done = run_jobs(todo, run_task, task_key, store=journal, workers=workers,
                        label="foraging", describe=describe)
    every = {task_key(t): r for t, r in zip(todo, done.results, strict=True)}
    runs = {k: r for k, r in every.items() if r["band"] != AUTHOR}
    beside_author = [r for r in every.values() if r["band"] == AUTHOR]
    beside_author.sort(key=lambda r: r["i"])
    table = aggregate(runs)
    single = single_agent_exploration(foods)
    write_csv(table, out / "foraging_results.csv")
    figures = all_figures(table, single, out)
    exact = exact_exploration()
    return write_report(
        out, table, single, reference(), figures, quick, seed, per_band, runs, exact,
        author=(author, beside_author),
    )
