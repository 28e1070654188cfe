"""Running the jobs of ``swarmex reproduce exploration`` in worker processes, with a cache."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from swarmex.experiments.progress import read_journal
from swarmex.missions.exploration import ExplorationParams, run_exploration
from swarmex.missions.exploration.record import exploration_metrics
from swarmex.studies.exploration.design import job_key, make_world


def run_job(job: dict[str, Any]) -> dict[str, Any]:
    """One run (in a worker process): a summary line, plus pictures' data when asked."""
    from swarmex.viz.exploration import snapshot

    c0 = time.process_time()
    grid = make_world(job["world"])
    params = ExplorationParams(
        robots=job["robots"],
        laser_range=job["laser"],
        comm_range=job["comm"],
        strategy=job["strategy"],
        seed=job["seed"],
        conflict_yield=bool(job.get("conflict_yield", False)),
        plan_pause=int(job.get("plan_pause", 0)),
    )
    snaps: list = []
    every = int(job.get("extra", {}).get("snap_every", 0))

    def hook(t: int, run) -> None:
        snaps.append(snapshot(t, run))

    run = run_exploration(grid, params, on_frame=hook if every else None, frame_every=every)
    team, _ = exploration_metrics(run)
    out = {
        "key": job_key(job),
        "job": {k: v for k, v in job.items() if k != "extra"},
        "complete": run.complete,
        "makespan": run.makespan,
        "mean_steps": team["mean_steps"],
        "steps": team["steps"],
        "explored_fraction": team["explored_fraction"],
        "plans": team["plans"],
        "replans": team["replans"],
        "conflicts": team["conflicts"],
        "messages_sent": team["messages_sent"],
        "bytes_sent": team["bytes_sent"],
        "plan_ticks": [r.stats.plan_ticks for r in run.robots],
        "cpu_seconds": time.process_time() - c0,
    }
    if job.get("extra", {}).get("pictures"):
        out["pictures"] = {
            "final": snapshot(run.makespan, run),
            "trajectories": run.trajectories,
            "truth": grid.free,
            "laser_cells": grid.cells(job["laser"]),
            "snaps": snaps,
        }
    return out


def execute(jobs, workers: int, store: Path | None, progress: Callable[[str], None]):
    """Run jobs (cached ones skipped when ``store`` is given); returns results by key."""
    done = read_journal(store) if store else {}
    todo = [j for j in jobs if job_key(j) not in done]
    results = {job_key(j): done[job_key(j)] for j in jobs if job_key(j) in done}
    if not todo:
        return results
    t0 = time.perf_counter()
    fh = store.open("a", encoding="utf-8") if store else None
    try:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futs = {pool.submit(run_job, j): j for j in todo}
            for k, fut in enumerate(as_completed(futs), 1):
                res = fut.result()
                results[res["key"]] = res
                if fh is not None:
                    fh.write(json.dumps(res) + "\n")
                    fh.flush()
                j = futs[fut]
                progress(
                    f"[{k}/{len(todo)}] {j['kind']} n={j['robots']} laser={j['laser']:g} "
                    f"comm={j['comm']:g} {j['strategy']} seed={j['seed']}: "
                    f"{res['makespan']} steps, {res['cpu_seconds']:.1f} s cpu "
                    f"({time.perf_counter() - t0:.0f} s)"
                )
    finally:
        if fh is not None:
            fh.close()
    return results
