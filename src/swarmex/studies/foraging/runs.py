"""One run of ``swarmex reproduce foraging``: the job function of the study runner.

A job is a task of :func:`~.design.tasks`: ``(pattern, n, band, i, food, transport)``. Its run
goes through the mission contract (``registry.get("foraging")``: ``params`` then ``run``) with
``trace=False``: the study reads only the record's metrics, and a run without its per-round
positions costs less memory and time over the study's thousands of runs. One line of
``DIR/runs.jsonl`` per run (:func:`swarmex.studies.runner.run_jobs` keeps the journal and
resumes from it).
"""

from __future__ import annotations

from typing import Any

from swarmex.studies.foraging.design import UNITS, G, run_key

Task = tuple[str, int, str, int, tuple[int, int], str]


def task_key(task: Task) -> str:
    pattern, n, band, i, food, transport = task
    return run_key(pattern, n, band, i, food, transport)


def run_task(task: Task) -> dict[str, Any]:
    """Run one task (in a worker process): its journal line."""
    from swarmex.missions.registry import get

    pattern, n, band, i, food, transport = task
    mission = get("foraging")
    params = mission.params(
        algorithm=pattern, grid=G, agents=n, food=food, food_units=UNITS, transport=transport
    )
    record = mission.run(params, trace=False).record
    return {
        "key": task_key(task),
        "pattern": pattern,
        "n": n,
        "band": band,
        "i": i,
        "food": list(food),
        "transport": transport,
        **record.metrics,
        "wall": round(record.wall_seconds, 4),
    }


def describe(task: Task) -> str:
    pattern, n, band, i, _, transport = task
    return f"{pattern} n={n} {band} #{i} {transport}"
