"""Running the plan of ``swarmex reproduce foraging``: one run per task, journaled at once."""

from __future__ import annotations

import json
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from swarmex.experiments.progress import read_journal, runs_progress
from swarmex.studies.foraging.design import UNITS, G, run_key


def _one(task: tuple[str, int, str, int, tuple[int, int], str]) -> dict[str, Any]:
    from swarmex.missions.foraging import run_forage

    pattern, n, band, i, food, transport = task
    run = run_forage(pattern, G, n, food, UNITS, transport, record=False)
    return {
        "key": run_key(pattern, n, band, i, transport),
        "pattern": pattern,
        "n": n,
        "band": band,
        "i": i,
        "food": list(food),
        "transport": transport,
        **{k: v for k, v in run.metrics.items()},
        "wall": round(run.wall_seconds, 4),
    }


def execute(todo: list, runs_path: Path, workers: int) -> None:
    done = read_journal(runs_path)
    todo = [t for t in todo if run_key(t[0], t[1], t[2], t[3], t[5]) not in done]
    if not todo:
        return
    with (
        runs_path.open("a", encoding="utf-8") as fh,
        runs_progress("foraging") as bar,
    ):
        job = bar.add_task("runs", total=len(todo))
        if workers <= 1:
            for t in todo:
                fh.write(json.dumps(_one(t)) + "\n")
                fh.flush()
                bar.advance(job)
            return
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(_one, t) for t in todo]
            for fut in as_completed(futures):
                fh.write(json.dumps(fut.result()) + "\n")
                fh.flush()
                bar.advance(job)
