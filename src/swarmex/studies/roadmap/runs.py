"""One run of ``swarmex reproduce roadmap``: the job function of the study runner.

A job (:class:`~.design.Job`) is exactly a roadmap mission run, so it goes through the
mission contract (``registry.get("roadmap")``: ``params`` then ``run``) on the study's
embedded environment; the journal line keeps the record's metrics the tables read.
:func:`swarmex.studies.runner.run_jobs` runs the jobs and keeps ``DIR/roadmap_runs.jsonl``.
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

from swarmex.missions.registry import get
from swarmex.studies.roadmap.design import AGENTS, Job, world

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
    return {"key": job.key, **asdict(job), "complete": rec.complete,
            **{k: m.get(k) for k in KEEP}, "wall_seconds": round(rec.wall_seconds, 4)}


def job_key(job: Job) -> str:
    return job.key


def describe(job: Job) -> str:
    return f"{job.exp} {job.planner} {job.nodes}/{job.step:g}/{job.mult} seed {job.seed}"
