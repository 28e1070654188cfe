"""One run of ``swarmex reproduce exploration``: the job function of the study runner.

A job is a plain dict (:mod:`.design`, :func:`~.design.job_key` is its identity). Its run goes
through the exploration mission's contract (``registry.get("exploration")``: ``params``,
``prepare``, ``execute``) with the study's own options (``conflict_yield``, ``plan_pause``);
what the figures need from inside the run comes from the contract's outputs: snapshots are
the run's frames (``on_frame``, asked for every ``snap_every`` ticks through the callback's
``wants``), each robot's plan ticks are read off the Outcome's run object.
:func:`swarmex.studies.runner.run_jobs` runs the jobs and keeps the summary lines in
``OUT/runs.jsonl``; the picture jobs (arrays, snapshots) are run without a store.
"""

from __future__ import annotations

import time
from typing import Any

from swarmex.missions.exploration.record import exploration_metrics
from swarmex.studies.exploration.design import job_key, world_options


class _Every:
    """An ``on_frame`` callback that keeps the snapshots of every ``every``-th tick (its
    ``wants`` spares the mission building the others)."""

    def __init__(self, snaps: list[Any], every: int) -> None:
        self.snaps = snaps
        self.every = every

    def wants(self, t: int) -> bool:
        return t % self.every == 0

    def __call__(self, frame: Any) -> None:
        self.snaps.append(frame)


def run_job(job: dict[str, Any]) -> dict[str, Any]:
    """One run (in a worker process): a summary line, plus pictures' data when asked."""
    from swarmex.missions.exploration.frames import snapshot
    from swarmex.missions.registry import get

    c0 = time.process_time()
    mission = get("exploration")
    params = mission.params(
        **world_options(job["world"]),
        robots=job["robots"],
        laser_range=job["laser"],
        comm_range=job["comm"],
        strategy=job["strategy"],
        seed=job["seed"],
        conflict_yield=bool(job.get("conflict_yield", False)),
        plan_pause=int(job.get("plan_pause", 0)),
    )
    world = mission.prepare(params)
    snaps: list = []
    every = int(job.get("extra", {}).get("snap_every", 0))
    frames = _Every(snaps, every) if every else None
    run = mission.execute(params, world, frames, trace=False).run
    if every and run.makespan % every:  # the last tick's state, as the run ended
        snaps.append(snapshot(run.makespan, run))
    grid = world.grid
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
