"""The roadmap mission (seed 004, WMA-RRT against PRM) behind the Mission contract.

``prepare`` loads the environment (or takes the PolygonWorld given as ``env``) and resolves
the starts and the goal against it (see params' docstring for the rules): every check that
needs the world happens there, before the roadmap is built. ``execute`` builds the roadmap,
runs the team and builds the record, whose ``params`` hold the resolved values (the
environment's source, the sensor range as a length, the starts and goal actually used).

Frames: ``on_frame`` receives a :class:`~swarmex.missions.roadmap.sim.RoadmapFrame` after
the initial sensing and after every step; raising StopRun from it ends the run there.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmex.engine.record import MetricInfo, ResultRecord
from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, Mission, Outcome, ProgressSpec
from swarmex.missions.roadmap.params import GRAPH_PLANNERS, RoadmapParams

if TYPE_CHECKING:
    from collections.abc import Callable, Collection, Mapping

    import numpy as np

    from swarmex.missions.roadmap.sim import RoadmapRun
    from swarmex.missions.roadmap.wma_policy import Move
    from swarmex.sensing.coverage_raster import CoverageRaster
    from swarmex.worlds.polygon import PolygonWorld


@dataclass
class RoadmapWorld:
    """A prepared roadmap run: the environment, each agent's start and the goal (if any)."""

    world: PolygonWorld
    starts: np.ndarray  # (agents, 2)
    goal: np.ndarray | None  # (2,)


def load_environment(env: str | Path | PolygonWorld) -> PolygonWorld:
    """The PolygonWorld of an ``env`` value: loaded from its file (JSON polygons, MovingAI
    ``.map`` or image, by suffix), or the world itself. The monitor rebuilds records' worlds
    with this too."""
    from swarmex.worlds.polygon import PolygonWorld, load_polygon_world

    return env if isinstance(env, PolygonWorld) else load_polygon_world(env)


def resolve_starts(world: PolygonWorld, p: RoadmapParams) -> np.ndarray:
    """``starts``, else the file's when their number matches, else the default cluster."""
    import numpy as np

    from swarmex.missions.roadmap.starts import check_starts, default_starts

    if p.starts is not None:
        return check_starts(world, np.array(p.starts, dtype=np.float64), p.agents)
    if world.starts is not None and len(world.starts) == p.agents:
        return check_starts(world, world.starts, p.agents)
    pts = default_starts(world, p.agents)
    if world.starts is not None:  # keep the file's cluster location
        pts = pts - pts.mean(axis=0) + world.starts.mean(axis=0)
    return check_starts(world, pts, p.agents)


def resolve_goal(world: PolygonWorld, p: RoadmapParams) -> np.ndarray | None:
    """``goal``, else the file's; ``task="search"`` without either is an error."""
    import numpy as np

    from swarmex.missions.roadmap.starts import check_goal

    g = None
    if p.goal is not None:
        g = check_goal(world, np.array(p.goal, dtype=np.float64))
    elif world.goal is not None:
        g = check_goal(world, np.asarray(world.goal))
    if p.task == "search" and g is None:
        raise InputError("--task search needs a goal: --goal x,y (or 'goal' in the env file)")
    return g


def record_params(p: RoadmapParams, prepared: RoadmapWorld) -> dict[str, Any]:
    """The record's ``params``: the options as the run used them (resolved starts and goal,
    the sensor range as a length or "inf", the environment's source)."""
    from swarmex.missions.roadmap.record import range_label

    return {
        "env": str(prepared.world.source),
        "task": p.task,
        "planner": p.planner,
        "agents": len(prepared.starts),
        "nodes": p.nodes,
        "step": float(p.step),
        "sensor_range": range_label(p.range_length),
        "goal": None if prepared.goal is None else prepared.goal.tolist(),
        "starts": prepared.starts.tolist(),
        "seed": p.seed,
        "step_budget": p.step_budget,
        "raster_cells": p.raster,
    }


def simulate(
    p: RoadmapParams,
    prepared: RoadmapWorld,
    on_frame: FrameCallback | None = None,
    *,
    raster: CoverageRaster | None = None,
    decide: Callable[[Any, int, np.random.Generator], Move | None] | None = None,
) -> RoadmapRun:
    """Build the roadmap and run the team on a prepared world (no record).

    ``raster`` and ``decide`` go to :func:`~swarmex.missions.roadmap.sim.run_roadmap` as they
    are: the PettingZoo environment (:mod:`swarmex.envs.roadmap_v0`) drives a run through them.
    """
    from swarmex.missions.roadmap.sim import run_roadmap

    return run_roadmap(
        prepared.world,
        prepared.starts,
        task=p.task,
        planner=p.planner,
        nodes=p.nodes,
        step=float(p.step),
        sensor_range=p.range_length,
        goal=prepared.goal,
        seed=p.seed,
        step_budget=p.step_budget,
        raster_cells=p.raster,
        on_frame=on_frame,
        raster=raster,
        decide=decide,
    )


class RoadmapMission(Mission[RoadmapParams, RoadmapWorld]):
    name = "roadmap"
    command = "roadmap"
    summary = "Coverage or goal search by a team on a WMA-RRT (or PRM) roadmap."
    params_type = RoadmapParams
    time_unit = "step"
    # one start per agent, and an environment's own goal, belong to the recorded env
    rerun_replaces = {"starts": ("agents", "env"), "goal": ("env",)}

    def rerun_values(self, record: ResultRecord, given: Collection[str] = ()) -> dict[str, Any]:
        """The raster's size back under its option's name (the record says raster_cells)."""
        values = super().rerun_values(record, given)
        if "raster" not in given and "raster_cells" in record.params:
            values["raster"] = record.params["raster_cells"]
        return values

    def team_metrics(self) -> Mapping[str, MetricInfo]:
        from swarmex.missions.roadmap.record import TEAM_METRICS

        return TEAM_METRICS

    def progress(self, params: RoadmapParams, world: RoadmapWorld) -> ProgressSpec | None:
        """WMA-RRT: edges travelled of the tree's K (coverage ends when all are); a PRM's
        walkers have no end but the step budget, so its steps."""
        import numpy as np

        if params.planner in GRAPH_PLANNERS:
            budget = params.step_budget or 2 * params.nodes
            return ProgressSpec(int(budget), "steps", lambda f: min(int(f.step), budget))
        return ProgressSpec(int(params.nodes), "edges travelled",
                            lambda f: int(np.count_nonzero(f.edge_traversals)))

    def prepare(self, params: RoadmapParams) -> RoadmapWorld:
        import shapely

        world = load_environment(params.env)
        # before the starts: a world without free space would otherwise be reported as a
        # start inside an obstacle, or as no room for the default start cluster
        if shapely.is_empty(world.free_region):
            raise InputError(f"{world.source}: no free space")
        starts = resolve_starts(world, params)
        goal = resolve_goal(world, params)
        return RoadmapWorld(world, starts, goal)

    def execute(
        self,
        params: RoadmapParams,
        world: RoadmapWorld,
        on_frame: FrameCallback | None = None,
        *,
        trace: bool = True,
    ) -> Outcome:
        from swarmex.engine.record import without_trace
        from swarmex.missions.roadmap.record import build_record

        t0 = time.perf_counter()
        run = simulate(params, world, on_frame)
        wall = time.perf_counter() - t0
        record = build_record(run, record_params(params, world), params.seed, wall)
        return Outcome(record if trace else without_trace(record), run, world.world)


__all__ = [
    "RoadmapMission",
    "RoadmapWorld",
    "load_environment",
    "record_params",
    "resolve_goal",
    "resolve_starts",
    "simulate",
]
