"""Keyword arguments to a validated run (and its record): the roadmap mission, called the way
the reproduction and its report call it.

The options, their defaults and checks are :class:`~.params.RoadmapParams`; the world loading
and the checks that need it are :class:`~.mission.RoadmapMission`'s ``prepare``. This module
only keeps the older entry points (``make_scenario``, ``run_scenario``, ``parse_range``) on
top of them, with the keyword ``raster_cells`` for the option ``raster``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.engine.record import ResultRecord
from swarmex.missions.roadmap.mission import (
    RoadmapMission,
    RoadmapWorld,
    record_params,
    simulate,
)
from swarmex.missions.roadmap.params import RASTER_CELLS, RoadmapParams, parse_range
from swarmex.missions.roadmap.sim import RoadmapRun
from swarmex.worlds.polygon import PolygonWorld

MISSION = RoadmapMission()


@dataclass
class Scenario:
    """Validated Params and the world prepared for them."""

    options: RoadmapParams
    prepared: RoadmapWorld

    @property
    def world(self) -> PolygonWorld:
        return self.prepared.world

    @property
    def starts(self) -> np.ndarray:
        return self.prepared.starts

    @property
    def goal(self) -> np.ndarray | None:
        return self.prepared.goal

    @property
    def task(self) -> str:
        return self.options.task

    @property
    def planner(self) -> str:
        return self.options.planner

    @property
    def nodes(self) -> int:
        return self.options.nodes

    @property
    def step(self) -> float:
        return float(self.options.step)

    @property
    def sensor_range(self) -> float:
        return self.options.range_length

    @property
    def seed(self) -> int:
        return self.options.seed

    @property
    def step_budget(self) -> int | None:
        return self.options.step_budget

    @property
    def raster_cells(self) -> int:
        return self.options.raster

    @property
    def env(self) -> str:
        return str(self.world.source)

    def params(self) -> dict[str, Any]:
        return record_params(self.options, self.prepared)

    def run(self) -> RoadmapRun:
        """The run alone (no record), as the mission runs it."""
        return simulate(self.options, self.prepared)


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
    raster_cells: int = RASTER_CELLS,
) -> Scenario:
    """RoadmapParams from these keywords, and the world prepared for them (InputError else)."""
    params = MISSION.params(
        env=env, agents=agents, nodes=nodes, step=step, sensor_range=sensor_range, task=task,
        planner=planner, goal=goal, starts=starts, seed=seed, step_budget=step_budget,
        raster=raster_cells,
    )
    return Scenario(params, MISSION.prepare(params))


def run_scenario(sc: Scenario) -> tuple[RoadmapRun, ResultRecord]:
    """Run a scenario through the mission: the run and its record."""
    outcome = MISSION.execute(sc.options, sc.prepared)
    return outcome.run, outcome.record


__all__ = ["Scenario", "make_scenario", "parse_range", "run_scenario"]
