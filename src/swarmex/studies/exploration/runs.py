"""One run of ``swarmex reproduce exploration``: the job function of the study runner.

A job is a plain dict (:mod:`.design`, :func:`~.design.job_key` is its identity). Its run is
the exploration simulator with the study's own options (``conflict_yield``, ``plan_pause``)
and what the figures need from inside the run (each robot's plan ticks, snapshots every few
steps), so it calls :func:`~swarmex.missions.exploration.run_exploration` rather than the
mission's record. :func:`swarmex.studies.runner.run_jobs` runs the jobs and keeps the summary
lines in ``OUT/runs.jsonl``; the picture jobs (arrays, snapshots) are run without a store.
"""

from __future__ import annotations

import time
from typing import Any

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


def describe(job: dict[str, Any]) -> str:
    return (
        f"{job['kind']} n={job['robots']} laser={job['laser']:g} comm={job['comm']:g} "
        f"{job['strategy']} seed={job['seed']}"
    )
