"""Running the jobs of ``swarmex reproduce roadmap``, one journal line each, resumable."""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path
from typing import Any

from rich.console import Console

from swarmex.experiments.progress import read_journal, runs_progress
from swarmex.missions.roadmap.scenario import make_scenario, run_scenario
from swarmex.studies.roadmap.design import AGENTS, Job, world


def run_job(job: Job) -> dict[str, Any]:
    sc = make_scenario(world(job.env), agents=AGENTS, nodes=job.nodes, step=job.step,
                       sensor_range=job.sensor_range, task=job.task, planner=job.planner,
                       seed=job.seed)
    _, rec = run_scenario(sc)
    m = rec.metrics
    keep = ("coverage", "steps", "goal_found", "goal_unreachable", "found_step",
            "all_at_goal_step", "edge_revisits", "components", "cycles", "path_length",
            "tree_nodes", "budget_exhausted", "agents_off_roadmap")
    return {"key": job.key, **asdict(job), "complete": rec.complete,
            **{k: m.get(k) for k in keep}, "wall_seconds": round(rec.wall_seconds, 4)}


def execute(jobs: list[Job], journal: Path, console: Console) -> tuple[list[dict[str, Any]], int]:
    """Run the jobs not yet in ``journal``, appending each result at once (flushed).

    Returns every job's result in plan order and how many were run now.
    """
    done = read_journal(journal)
    todo = [j for j in jobs if j.key not in done]
    with runs_progress("roadmap", console, detail=True) as bar, \
            journal.open("a", encoding="utf-8") as fh:
        task = bar.add_task("", total=len(jobs), completed=len(jobs) - len(todo))
        for job in todo:
            bar.update(task, description=f"{job.exp} {job.planner} {job.nodes}/{job.step:g}/"
                                         f"{job.mult} seed {job.seed}")
            res = run_job(job)
            done[job.key] = res
            fh.write(json.dumps(res) + "\n")
            fh.flush()
            bar.advance(task)
    return [done[j.key] for j in jobs], len(todo)
