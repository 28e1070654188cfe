"""From command-line style arguments to a validated run (and its record).

Everything a user can get wrong is checked here, before any work, with an InputError that
names the parameter: the CLI turns it into exit status 2 and one line on stderr.

Starts: ``--starts`` if given; otherwise the file's ``starts`` when their number matches
``--agents``; otherwise the default cluster (:mod:`.starts`) — centred on the file's starts
when it has some, near the lower-left corner when not. Goal: ``--goal``, else the file's.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from swarmex.engine.record import ResultRecord
from swarmex.errors import InputError
from swarmex.missions.roadmap.record import build_record, range_label
from swarmex.missions.roadmap.sim import PLANNERS, TASKS, RoadmapRun, run_roadmap
from swarmex.missions.roadmap.starts import (
    check_goal,
    check_starts,
    default_starts,
    parse_points,
)
from swarmex.sensing.coverage_raster import DEFAULT_CELLS
from swarmex.worlds.polygon import PolygonWorld, load_polygon_world


def parse_range(text: str | float, step: float | None = None) -> float:
    """A sensor range: a length, ``inf``, or a multiple of the step ε (``1eps``, ``2ε``).

    The ε form exists because seed 004 never gives its base range r, and Table 1 is fitted
    better by r = ε than by any fixed length (see docs/roadmap.md, "Sensor range"): ``1eps``
    lets one run that reading without converting by hand. ``step`` is needed for it.
    """
    if isinstance(text, str):
        low = text.strip().lower().replace("ε", "eps")
        if low in ("inf", "infinite", "infinity", "∞"):
            return math.inf
        if low.endswith("eps"):
            head = low[:-3].rstrip("*· ") or "1"
            if step is None:
                raise InputError(f"--sensor-range {text!r}: a multiple of ε needs the step")
            try:
                return parse_range(head) * float(step)
            except InputError:
                raise InputError(
                    f"--sensor-range {text!r}: the multiple of ε must be a positive number"
                ) from None
    try:
        r = float(text)
    except (TypeError, ValueError):
        raise InputError(
            f"--sensor-range must be a positive number, a multiple of ε like '2eps', or "
            f"'inf', got {text!r}"
        ) from None
    if not r > 0 or math.isnan(r):
        raise InputError(f"--sensor-range must be positive, got {text!r}")
    return r


@dataclass
class Scenario:
    world: PolygonWorld
    starts: np.ndarray
    goal: np.ndarray | None
    task: str
    planner: str
    nodes: int
    step: float
    sensor_range: float
    seed: int
    step_budget: int | None = None
    raster_cells: int = DEFAULT_CELLS
    env: str = ""

    def params(self) -> dict[str, Any]:
        return {
            "env": self.env,
            "task": self.task,
            "planner": self.planner,
            "agents": len(self.starts),
            "nodes": self.nodes,
            "step": self.step,
            "sensor_range": range_label(self.sensor_range),
            "goal": None if self.goal is None else self.goal.tolist(),
            "starts": self.starts.tolist(),
            "seed": self.seed,
            "step_budget": self.step_budget,
            "raster_cells": self.raster_cells,
        }

    def run(self) -> RoadmapRun:
        return run_roadmap(
            self.world, self.starts, task=self.task, planner=self.planner, nodes=self.nodes,
            step=self.step, sensor_range=self.sensor_range, goal=self.goal, seed=self.seed,
            step_budget=self.step_budget, raster_cells=self.raster_cells,
        )

    def record(self, run: RoadmapRun, wall_seconds: float) -> ResultRecord:
        return build_record(run, self.params(), self.seed, wall_seconds)


def make_scenario(
    env: str | Path | PolygonWorld,
    *,
    agents: int,
    nodes: int,
    step: float,
    sensor_range: str | float,
    task: str = "coverage",
    planner: str = "wma-rrt",
    goal: str | None = None,
    starts: str | None = None,
    seed: int = 0,
    step_budget: int | None = None,
    raster_cells: int = DEFAULT_CELLS,
) -> Scenario:
    if task not in TASKS:
        raise InputError(f"--task must be one of {', '.join(TASKS)}, got {task!r}")
    if planner not in PLANNERS:
        raise InputError(f"--planner must be one of {', '.join(PLANNERS)}, got {planner!r}")
    if agents < 1:
        raise InputError(f"--agents must be at least 1, got {agents}")
    if nodes < agents:
        raise InputError(f"--nodes {nodes} is fewer than --agents {agents} (one root each)")
    if not step > 0 or not math.isfinite(step):
        raise InputError(f"--step must be a positive length, got {step:g}")
    if step_budget is not None and step_budget < 1:
        raise InputError(f"--step-budget must be at least 1, got {step_budget}")
    if raster_cells < 8:
        raise InputError(f"--raster must be at least 8 cells, got {raster_cells}")
    r = parse_range(sensor_range, step)
    world = env if isinstance(env, PolygonWorld) else load_polygon_world(env)
    if starts is not None:
        pts = check_starts(world, parse_points(starts, "--starts"), agents)
    elif world.starts is not None and len(world.starts) == agents:
        pts = check_starts(world, world.starts, agents)
    else:
        pts = default_starts(world, agents)
        if world.starts is not None:  # keep the file's cluster location
            pts = pts - pts.mean(axis=0) + world.starts.mean(axis=0)
        pts = check_starts(world, pts, agents)
    g = None
    if goal is not None:
        g = check_goal(world, parse_points(goal, "--goal")[0])
        if len(parse_points(goal, "--goal")) != 1:
            raise InputError(f"--goal takes one 'x,y' point, got {goal!r}")
    elif world.goal is not None:
        g = check_goal(world, np.asarray(world.goal))
    if task == "search" and g is None:
        raise InputError("--task search needs a goal: --goal x,y (or 'goal' in the env file)")
    if shapely.is_empty(world.free_region):
        raise InputError(f"{world.source}: no free space")
    return Scenario(world=world, starts=pts, goal=g, task=task, planner=planner, nodes=nodes,
                    step=float(step), sensor_range=r, seed=seed, step_budget=step_budget,
                    raster_cells=raster_cells, env=str(getattr(world, "source", env)))


def run_scenario(sc: Scenario) -> tuple[RoadmapRun, ResultRecord]:
    t0 = time.perf_counter()
    run = sc.run()
    return run, sc.record(run, time.perf_counter() - t0)
