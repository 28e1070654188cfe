"""Which runs ``swarmex reproduce roadmap`` makes: seed 004's Tables 1–2 and Figs. 12–17.

Protocol (what the paper leaves open is fixed here and stated in the report):

* Environments: drawn after Figs. 8 (coverage) and 11 (goal search) and Figs. 14–17
  (walled-in team), 640 × 480 units; embedded below and shipped as ``examples/roadmap_*.json``
  (a test keeps the two identical).
* Team: 3 agents (Fig. 5), default start cluster in the lower-left corner.
* Sensor range ``r`` = 25 units (:data:`R_BASE`); 2r, 4r, ∞ as in the tables. The finite
  rows are run a second time with r = ε (:data:`C_EPS` · ε; experiments ``t1eps``/``t2eps``),
  the other reading of the unstated r, which fits Table 1 better.
* A study of the readings (:func:`readings_study`): Table 1's trees grown under each reading
  of ε and N, the sensor range fitted as a fixed length and as a multiple of ε, and coverage
  against ε at a fixed node budget. A complete WMA-RRT run traverses every edge, so its
  coverage is what the tree's edges (and the entry legs) see: the study sweeps them directly.
* "Number of iterations" = independent runs; run i uses ``--seed i``, so every row of the
  report can be rerun alone with ``swarmex roadmap … --seed i``.
* A third planner, ``wma-rrt-takeover`` (our improvement), runs on the same rows.
* A standard PRM, OMPL's (``ompl-prm``, extra ``ompl``), runs on the rows of both tables
  and on the unreachable-goal runs, beside the project's own PRM; without the extra it is
  left out of the plan and the report says so.

The jobs (:class:`Job`, :func:`plan`) are run (:mod:`.runs`) by the study runner
(:mod:`swarmex.studies.runner`): every finished run is appended
to ``DIR/roadmap_runs.jsonl`` at once (flushed), and a rerun skips runs already there, so an
interrupted reproduction resumes; delete the file to start over. :mod:`.readings` is the study
of readings, :mod:`.analysis` the tables, :mod:`.figures` and :mod:`.report` the figures and
``DIR/roadmap.md``, rebuilt from the journal at the end.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import math
from dataclasses import dataclass
from typing import Any

from swarmex.studies import reference_file
from swarmex.worlds.polygon import PolygonWorld, parse_polygon_json

R_BASE = 25.0
C_EPS = 1.0  # r = C_EPS · ε in the t1eps / t2eps rows (the best c of the study's grid)
AGENTS = 3
MULTS = {"r": 1.0, "2r": 2.0, "4r": 4.0, "inf": math.inf}
PLANNERS = ("wma-rrt", "prm", "wma-rrt-takeover")
OMPL_PRM = "ompl-prm"  # the standard PRM, run where the ompl extra is installed
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
    with reference_file(name).open(encoding="utf-8") as fh:
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
        base = C_EPS * self.step if self.exp.endswith("eps") else R_BASE
        return base * MULTS[self.mult]


def ompl_available() -> bool:
    """Whether OMPL's Python bindings are installed (extra ``ompl``)."""
    return importlib.util.find_spec("ompl") is not None


def plan(quick: bool, ompl: bool | None = None) -> list[Job]:
    """The study's runs; ``ompl`` (default: whether it is installed) adds OMPL's PRM."""
    ompl = ompl_available() if ompl is None else ompl
    extra: tuple[str, ...] = (OMPL_PRM,) if ompl else ()
    jobs: list[Job] = []
    for exp, env, task, table in (("t1", "fig8", "coverage", "roadmap_table1.csv"),
                                  ("t2", "fig11", "search", "roadmap_table2.csv")):
        for row in reference(table):
            nodes, step, runs = int(row["nodes"]), float(row["step"]), int(row["runs"])
            runs = 1 if quick else runs
            planners: tuple[str, ...] = PLANNERS
            if quick and row["sensor_range"] != "r":
                planners = PLANNERS[:2]  # the improvement is compared on the r rows only
            for planner in planners + extra:
                for seed in range(runs):
                    jobs.append(Job(exp, env, task, planner, nodes, step, row["sensor_range"],
                                    seed))
            if row["sensor_range"] == "inf" or (quick and row["sensor_range"] != "r"):
                continue  # r = ε changes nothing at infinite range
            for planner in PLANNERS[:2]:  # the second reading of r: WMA-RRT and PRM
                for seed in range(runs):
                    jobs.append(Job(exp + "eps", env, task, planner, nodes, step,
                                    row["sensor_range"], seed))
    runs = 2 if quick else 10
    for env in ("fig14", "fig17"):
        for planner in PLANNERS + extra:
            for seed in range(runs):
                jobs.append(Job("unreach", env, "search", planner, UNREACH_NODES, UNREACH_STEP,
                                "r", seed))
    return jobs


__all__ = ["AGENTS", "C_EPS", "ENVIRONMENTS", "MULTS", "OMPL_PRM", "PLANNERS", "R_BASE", "Job",
           "ompl_available", "plan", "reference", "world"]
