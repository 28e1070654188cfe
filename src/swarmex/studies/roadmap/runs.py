"""One run of ``swarmex reproduce roadmap``: the job function of the study runner.

A job (:class:`~.design.Job`) is exactly a roadmap mission run, so it goes through the
mission contract (``registry.get("roadmap")``: ``params`` then ``run``) on the study's
embedded environment; the journal line keeps the record's metrics the tables read.
:func:`swarmex.studies.runner.run_jobs` runs the jobs and keeps ``DIR/roadmap_runs.jsonl``.
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

import numpy as np

from swarmex.engine.record import ResultRecord
from swarmex.missions.registry import get
from swarmex.studies.roadmap.design import AGENTS, OMPL_PRM, Job, world

KEEP = ("coverage", "steps", "goal_found", "goal_unreachable", "found_step",
        "all_at_goal_step", "edge_revisits", "components", "cycles", "path_length",
        "tree_nodes", "budget_exhausted", "agents_off_roadmap")


def run_job(job: Job) -> dict[str, Any]:
    """Run one job (in a worker process): its journal line."""
    mission = get("roadmap")
    params = mission.params(
        env=world(job.env), agents=AGENTS, nodes=job.nodes, step=job.step,
        sensor_range=job.sensor_range, task=job.task, planner=job.planner, seed=job.seed,
    )
    rec = mission.run(params).record
    m = rec.metrics
    line = {"key": job.key, **asdict(job), "complete": rec.complete,
            **{k: m.get(k) for k in KEEP}, "wall_seconds": round(rec.wall_seconds, 4)}
    if job.planner == OMPL_PRM:  # its walkers' steps are longer: coverage against travel
        line["effort"] = effort_curve(rec)
    return line


def effort_curve(rec: ResultRecord, points: int = 64) -> list[list[float]]:
    """``[team path so far, coverage]`` after ``points`` evenly spaced steps (and the last):
    what the team had seen when it had walked that far, for comparing planners whose steps
    differ in length at equal travel (coverage only grows, so it interpolates)."""
    steps = int(rec.makespan)
    walked = np.zeros(steps + 1)
    for a in rec.agents:
        tr = np.asarray(a.trajectory, dtype=np.float64).reshape(-1, 3)
        if len(tr) > 1:
            seg = np.hypot(*np.diff(tr[:, 1:], axis=0).T)
            np.add.at(walked, np.minimum(tr[1:, 0].astype(np.int64), steps), seg)
    path = np.cumsum(walked)
    cov = np.asarray(rec.extra["coverage_curve"], dtype=np.float64)
    at = np.unique(np.linspace(0, steps, min(points, steps + 1)).round().astype(np.int64))
    return [[round(float(path[t]), 2), round(float(cov[min(t, len(cov) - 1)]), 5)]
            for t in at]


def job_key(job: Job) -> str:
    return job.key


def describe(job: Job) -> str:
    return f"{job.exp} {job.planner} {job.nodes}/{job.step:g}/{job.mult} seed {job.seed}"
