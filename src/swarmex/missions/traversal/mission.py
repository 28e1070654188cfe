"""The traversal mission (seed 000) behind the Mission contract.

``prepare`` builds the graph world of ``map`` or ``grid`` with the ``obstacles`` blocked and
resolves one nest per agent (every check that needs the map happens here, before the run);
``execute`` runs MADGTA, a baseline or the exact MILP and builds the record, whose
``params`` are the run's parameters as the user gave them (cells as ``[x, y]`` lists).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, Mission, Outcome
from swarmex.missions.traversal.params import TraversalParams


@dataclass
class TraversalWorld:
    """A prepared traversal: the grid world and each agent's start vertex."""

    world: Any  # GridWorld
    nests: list[int]


def build_world(p: TraversalParams) -> Any:
    """The GridWorld of ``map`` or ``grid``, with the ``obstacles`` cells blocked."""
    from swarmex.worlds import GridWorld, load_movingai

    if p.map is not None:
        base = load_movingai(p.map, connectivity=p.connectivity)
    else:
        assert p.grid is not None
        w, h = p.grid
        base = GridWorld(np.ones((h, w), dtype=bool), p.connectivity, source=f"grid {w}x{h}")
    if not p.obstacles:
        return base
    free = base.free.copy()
    for x, y in _in_bounds(base, p.obstacles, "--obstacles"):
        free[y, x] = False
    return GridWorld(free, p.connectivity, source=base.source, terrain=base.terrain)


def _in_bounds(world: Any, cells: tuple[tuple[int, int], ...], option: str) -> tuple:
    for x, y in cells:
        if not world.in_bounds(x, y):
            raise InputError(
                f"{option}: cell ({x},{y}) is outside the {world.width}x{world.height} map"
            )
    return cells


def resolve_nests(world: Any, nests: tuple[tuple[int, int], ...] | None, agents: int) -> list[int]:
    """One start vertex per agent (round-robin over the given nests; see params' docstring)."""
    if agents > world.free_cells:
        raise InputError(f"{agents} agents but the map has only {world.free_cells} free cells")
    if nests is None:
        return [int(np.flatnonzero(world.free.ravel())[0])] * agents
    for x, y in _in_bounds(world, nests, "--nests"):
        if not world.free[y, x]:
            raise InputError(f"--nests: cell ({x},{y}) is an obstacle")
    return [world.node(*nests[i % len(nests)]) for i in range(agents)]


DEMO_AGENTS = 4


def demo_world() -> TraversalWorld:
    """``swarmex demo``'s embedded scenario: four agents from one nest on a generated 16x16
    map with 18 % obstacles (generator seed 7), so the first command needs no file."""
    from swarmex.worlds import random_obstacles

    world = random_obstacles(16, 16, 0.18, seed=7)
    return TraversalWorld(world, resolve_nests(world, None, DEMO_AGENTS))


def record_params(p: TraversalParams, prepared: TraversalWorld) -> dict[str, Any]:
    """The record's ``params``: the map or grid, blocked cells, team and nests, then the
    remaining options in declaration order (the same for ``traverse`` and ``serve``)."""
    world = prepared.world
    out: dict[str, Any] = {
        "map": None if p.map is None else str(p.map),
        "grid": None if p.grid is None else f"{p.grid[0]}x{p.grid[1]}",
    }
    if p.map is None and p.grid is None:  # a generated world (swarmex demo)
        out["generated"] = world.source
    out["obstacles"] = [list(c) for c in p.obstacles]
    out["agents"] = len(prepared.nests)
    out["nests"] = [list(world.xy(n)) for n in prepared.nests]
    skip = {"map", "grid", "obstacles", "agents", "nests", "seed"}
    out.update({k: v for k, v in p.values().items() if k not in skip})
    out["seed"] = p.seed
    return out


def agent_specs(p: TraversalParams, nests: list[int]) -> list[Any]:
    from swarmex.missions.traversal.agents import uniform_agents

    return uniform_agents(
        nests, p.travel_time, p.job_time, 1.0, p.altitude, p.up_speed, p.down_speed
    )


class TraversalMission(Mission[TraversalParams, TraversalWorld]):
    name = "traversal"
    command = "traverse"
    summary = "Every agent does a job at every free cell (seed 000, MADGTA and baselines)."
    params_type = TraversalParams
    time_unit = "s"

    def prepare(self, params: TraversalParams) -> TraversalWorld:
        world = build_world(params)
        return TraversalWorld(world, resolve_nests(world, params.nests, params.agents))

    def execute(
        self,
        params: TraversalParams,
        world: TraversalWorld,
        on_frame: FrameCallback | None = None,
    ) -> Outcome:
        from swarmex.comm.channel import Channel
        from swarmex.missions.traversal import run_traversal, traversal_record

        p = params
        specs = agent_specs(p, world.nests)
        rparams = record_params(p, world)
        if p.algorithm == "optimal":
            return Outcome(_optimal(world.world, specs, p, rparams), None, world.world)
        comm = math.inf if p.comm_range is None else p.comm_range
        run = run_traversal(
            world.world,
            specs,
            p.algorithm,
            p.seed,
            Channel(p.loss, p.delay, comm),
            start_interval=p.start_interval,
            job_failure=p.job_failure,
            on_frame=on_frame,
        )
        return Outcome(traversal_record(run, rparams), run, world.world)


def _optimal(world: Any, specs: list[Any], p: TraversalParams, rparams: dict[str, Any]) -> Any:
    """``algorithm="optimal"``: the exact MILP (imported lazily: it pulls in the solver)."""
    try:
        from swarmex.missions.traversal.optimal import optimal_record
    except ModuleNotFoundError as exc:
        if exc.name != "swarmex.missions.traversal.optimal":
            raise
        raise InputError("--algorithm optimal is not available in this installation") from None
    objective: Literal["sum", "makespan"] = "makespan" if p.objective == "makespan" else "sum"
    return optimal_record(world, specs, objective, p.seed, rparams, 1.0)
