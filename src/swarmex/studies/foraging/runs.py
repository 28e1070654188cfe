"""One run of ``swarmex reproduce foraging``: the job function of the study runner.

A job is a task of :func:`~.design.tasks`: ``(pattern, n, band, i, food, transport)``. Its run
is the foraging mission's own run (:func:`~swarmex.missions.foraging.run_forage`) without the
per-round record, which the study does not read: only its metrics are kept, one line of
``DIR/runs.jsonl`` per run (:func:`swarmex.studies.runner.run_jobs` keeps the journal and
resumes from it).
"""

from __future__ import annotations

from typing import Any

from swarmex.studies.foraging.design import UNITS, G, run_key

Task = tuple[str, int, str, int, tuple[int, int], str]


def task_key(task: Task) -> str:
    pattern, n, band, i, _, transport = task
    return run_key(pattern, n, band, i, transport)


def run_task(task: Task) -> dict[str, Any]:
    """Run one task (in a worker process): its journal line."""
    from swarmex.missions.foraging import run_forage

    pattern, n, band, i, food, transport = task
    run = run_forage(pattern, G, n, food, UNITS, transport, record=False)
    return {
        "key": task_key(task),
        "pattern": pattern,
        "n": n,
        "band": band,
        "i": i,
        "food": list(food),
        "transport": transport,
        **{k: v for k, v in run.metrics.items()},
        "wall": round(run.wall_seconds, 4),
    }


def describe(task: Task) -> str:
    pattern, n, band, i, _, transport = task
    return f"{pattern} n={n} {band} #{i} {transport}"
