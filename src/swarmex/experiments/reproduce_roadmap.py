"""``swarmex reproduce roadmap``: seed 004's Tables 1–2, Fig. 6 and Figs. 12–17, with ours.

Protocol (what the paper leaves open is fixed here and stated in the report):

* Environments: drawn after Figs. 8 (coverage) and 11 (goal search) and Figs. 14–17
  (walled-in team), 640 × 480 units; embedded below and shipped as ``examples/roadmap_*.json``
  (a test keeps the two identical).
* Team: 3 agents (Fig. 5), default start cluster in the lower-left corner.
* Sensor range ``r`` = 25 units (:data:`R_BASE`); 2r, 4r, ∞ as in the tables.
* "Number of iterations" = independent runs; run i uses ``--seed i``, so every row of the
  report can be rerun alone with ``swarmex roadmap … --seed i``.
* A third planner, ``wma-rrt-takeover`` (our improvement), runs on the same rows.

Every finished run is appended to ``DIR/roadmap_runs.jsonl`` at once (flushed), and a rerun
skips runs already there, so an interrupted reproduction resumes; delete the file to start
over. The report ``DIR/roadmap.md`` and the figures are rebuilt from that file at the end.
"""

from __future__ import annotations

import csv
import json
import math
import time
from dataclasses import asdict, dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from rich.console import Console

from swarmex import __version__
from swarmex.experiments.progress import read_journal, runs_progress
from swarmex.missions.roadmap.scenario import make_scenario, run_scenario
from swarmex.worlds.polygon import PolygonWorld, parse_polygon_json

R_BASE = 25.0
AGENTS = 3
MULTS = {"r": 1.0, "2r": 2.0, "4r": 4.0, "inf": math.inf}
PLANNERS = ("wma-rrt", "prm", "wma-rrt-takeover")
UNREACH_NODES, UNREACH_STEP = 400, 20

ENVIRONMENTS: dict[str, dict[str, Any]] = {
    "fig8": {
        "bounds": [0, 0, 640, 480],
        "obstacles": [
            [[380, 430], [600, 430], [600, 440], [380, 440]],
            [[590, 260], [600, 260], [600, 440], [590, 440]],
            [[450, 260], [600, 260], [600, 270], [450, 270]],
            [[380, 310], [390, 310], [390, 440], [380, 440]],
            [[470, 330], [520, 330], [520, 380], [470, 380]],
            [[200, 180], [330, 180], [330, 210], [240, 210], [240, 330], [200, 330]],
            [[80, 250], [150, 260], [110, 330]],
            [[60, 380], [160, 380], [160, 410], [60, 410]],
            [[430, 90], [500, 80], [530, 130], [490, 170], [440, 150]],
            [[300, 40], [340, 40], [340, 120], [300, 120]],
            [[250, 400], [330, 400], [330, 410], [250, 410]],
            [[560, 60], [620, 40], [610, 140]],
            [[150, 100], [180, 100], [180, 130], [150, 130]],
        ],
    },
    "fig11": {
        "bounds": [0, 0, 640, 480],
        "obstacles": [
            [[180, 260], [290, 260], [290, 170], [278, 170], [278, 248], [180, 248]],
            [[120, 120], [200, 120], [200, 140], [120, 140]],
            [[60, 300], [140, 280], [160, 340], [90, 370]],
            [[400, 60], [430, 60], [430, 230], [400, 230]],
            [[220, 360], [330, 360], [330, 390], [220, 390]],
            [[480, 150], [550, 120], [580, 200], [510, 230]],
            [[520, 30], [600, 30], [600, 70], [520, 70]],
            [[380, 400], [440, 400], [440, 480], [380, 480]],
            [[300, 20], [340, 20], [340, 60], [300, 60]],
            [[560, 300], [620, 300], [620, 420], [560, 420]],
        ],
        "goal": [250, 230],
    },
    "fig14": {
        "bounds": [0, 0, 640, 480],
        "obstacles": [
            [[0, 200], [250, 200], [250, 212], [0, 212]],
            [[238, 0], [250, 0], [250, 212], [238, 212]],
            [[110, 80], [150, 80], [150, 120], [110, 120]],
            [[330, 280], [430, 280], [430, 300], [330, 300]],
            [[480, 120], [520, 120], [520, 240], [480, 240]],
        ],
        "goal": [520, 400],
    },
}
ENVIRONMENTS["fig17"] = {**ENVIRONMENTS["fig14"], "starts": [[300, 40], [312, 44], [304, 54]]}


def world(name: str) -> PolygonWorld:
    return parse_polygon_json(json.dumps(ENVIRONMENTS[name]), f"examples/roadmap_{name}.json")


def reference(name: str) -> list[dict[str, str]]:
    ref = resources.files("swarmex.experiments") / "reference" / name
    with ref.open(encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


@dataclass(frozen=True)
class Job:
    exp: str  # t1 | t2 | unreach
    env: str
    task: str
    planner: str
    nodes: int
    step: float
    mult: str
    seed: int

    @property
    def key(self) -> str:
        return (f"{self.exp}|{self.env}|{self.planner}|{self.nodes}|{self.step:g}|"
                f"{self.mult}|{self.seed}")

    @property
    def sensor_range(self) -> float:
        return R_BASE * MULTS[self.mult]


def plan(quick: bool) -> list[Job]:
    jobs: list[Job] = []
    for exp, env, task, table in (("t1", "fig8", "coverage", "roadmap_table1.csv"),
                                  ("t2", "fig11", "search", "roadmap_table2.csv")):
        for row in reference(table):
            nodes, step, runs = int(row["nodes"]), float(row["step"]), int(row["runs"])
            runs = 1 if quick else runs
            planners = PLANNERS
            if quick and row["sensor_range"] != "r":
                planners = PLANNERS[:2]  # the improvement is compared on the r rows only
            for planner in planners:
                for seed in range(runs):
                    jobs.append(Job(exp, env, task, planner, nodes, step, row["sensor_range"],
                                    seed))
    runs = 2 if quick else 10
    for env in ("fig14", "fig17"):
        for planner in PLANNERS:
            for seed in range(runs):
                jobs.append(Job("unreach", env, "search", planner, UNREACH_NODES, UNREACH_STEP,
                                "r", seed))
    return jobs


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


def reproduce(out: str | Path, quick: bool = False, console: Console | None = None) -> Path:
    from swarmex.viz.roadmap_report import write_report

    console = console or Console()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    journal = out / "roadmap_runs.jsonl"
    done = read_journal(journal)
    jobs = plan(quick)
    todo = [j for j in jobs if j.key not in done]
    t0 = time.perf_counter()
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
    results = [done[j.key] for j in jobs]
    report = write_report(out, results, quick=quick, seconds=time.perf_counter() - t0,
                          version=__version__, new_runs=len(todo))
    console.print(f"report: {report}")
    return report


__all__ = ["ENVIRONMENTS", "R_BASE", "Job", "plan", "reproduce", "run_job", "world"]
