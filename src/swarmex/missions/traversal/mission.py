"""The traversal mission (seed 000) behind the Mission contract.

``prepare`` builds the graph world of ``map`` or ``grid`` with the ``obstacles`` blocked and
resolves one nest per agent (every check that needs the map happens here, before the run);
``execute`` runs MADGTA, a baseline or the exact MILP and builds the record, whose
``params`` are the run's parameters as the user gave them (cells as ``[x, y]`` lists).

Lengths: a grid edge is one length unit of the world. ``unit_length`` is metres per unit
when the run has a metric scale (``edge_length``), else 1 (speeds are then edges per
second). A fleet's ``travel_speed`` is metres per second and needs that scale; its
``travel_time`` (and the ``travel_time`` option) is seconds per grid edge.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from swarmex.engine.record import MetricInfo, ResultRecord
from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, Mission, Outcome, ProgressSpec
from swarmex.missions.traversal.fleet import FleetRow
from swarmex.missions.traversal.params import TraversalParams


@dataclass
class TraversalWorld:
    """A prepared traversal: the grid world, each agent's start vertex, and the length
    scale: ``unit_length`` metres per length unit of the world, ``edge_m`` metres per grid
    edge (None without a metric scale: speeds are then in edges per second)."""

    world: Any  # GridWorld
    nests: list[int]
    unit_length: float = 1.0
    edge_m: float | None = None

    @property
    def per_edge(self) -> float:
        """Length of one grid edge in the speeds' unit (metres, or 1 edge)."""
        return self.unit_length if self.edge_m is None else self.edge_m


def build_world(p: TraversalParams) -> Any:
    """The GridWorld of ``map``, ``grid`` or the GPS grid of ``center``, with the
    ``obstacles`` cells blocked."""
    from swarmex.worlds import GridWorld, load_movingai

    if p.center is not None:
        from swarmex.worlds.geo import gps_grid

        assert p.radius is not None and p.nodes_on_edge is not None
        geo = gps_grid(p.center, p.radius, p.nodes_on_edge, p.connectivity)
        if not p.obstacles:
            return geo
        free = geo.free.copy()
        for x, y in _in_bounds(geo, p.obstacles, "--obstacles"):
            free[y, x] = False
        return geo.with_free(free)
    if isinstance(p.map, GridWorld):  # a world object from Python: its cells, our neighbours
        given = p.map
        base = given if given.connectivity == p.connectivity else GridWorld(
            given.free, p.connectivity, source=given.source, terrain=given.terrain
        )
    elif p.map is not None:
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


def resolve_nests(
    world: Any,
    nests: tuple[tuple[int, int], ...] | None,
    agents: int,
    fleet: tuple[FleetRow, ...] | None = None,
) -> list[int]:
    """One start vertex per agent (round-robin over the given nests; see params' docstring);
    a fleet row's own nest wins for its agent."""
    if agents > world.free_cells:
        raise InputError(f"{agents} agents but the map has only {world.free_cells} free cells")
    if nests is None:
        out = [int(np.flatnonzero(world.free.ravel())[0])] * agents
    else:
        for x, y in _in_bounds(world, nests, "--nests"):
            if not world.free[y, x]:
                raise InputError(f"--nests: cell ({x},{y}) is an obstacle")
        out = [world.node(*nests[i % len(nests)]) for i in range(agents)]
    for row in fleet or ():
        if row.nest is None:
            continue
        where = f"--fleet: agent {row.id}: nest"
        x, y = _in_bounds(world, (row.nest,), where)[0]
        if not world.free[y, x]:
            raise InputError(f"{where} ({x},{y}) is an obstacle")
        out[row.id - 1] = world.node(x, y)
    return out


DEMO_AGENTS = 4


def demo_world() -> TraversalWorld:
    """``swarmex demo``'s embedded scenario: four agents from one nest on a generated 16x16
    map whose cells are obstacles with probability 0.18 (generator seed 7: 43 of 256), so the
    first command needs no file."""
    from swarmex.worlds import random_obstacles

    world = random_obstacles(16, 16, 0.18, seed=7)
    return TraversalWorld(world, resolve_nests(world, None, DEMO_AGENTS))


def record_params(p: TraversalParams, prepared: TraversalWorld) -> dict[str, Any]:
    """The record's ``params``: the map or grid, blocked cells, team and nests, then the
    remaining options in declaration order (the same for ``traverse`` and ``serve``)."""
    world = prepared.world
    from swarmex.worlds import GridWorld

    from_file = p.map is not None and not isinstance(p.map, GridWorld)  # a path
    out: dict[str, Any] = {
        "map": str(p.map) if from_file else None,
        "grid": None if p.grid is None else f"{p.grid[0]}x{p.grid[1]}",
    }
    if not from_file and p.grid is None and p.center is None:  # swarmex demo, a GridWorld
        out["generated"] = world.source
    out["obstacles"] = [list(c) for c in p.obstacles]
    out["agents"] = len(prepared.nests)
    out["nests"] = [list(world.xy(n)) for n in prepared.nests]
    # options that records made before them do not have appear only when given
    late = ("edge_length", "center", "radius", "nodes_on_edge")
    skip = {"map", "grid", "obstacles", "agents", "nests", "seed", "fleet", *late}
    out.update({k: v for k, v in p.values().items() if k not in skip})
    for key in late:
        value = getattr(p, key)
        if value is not None:
            out[key] = list(value) if key == "center" else value
    if p.fleet is not None:
        out["fleet"] = fleet_record(p, prepared)
    out["seed"] = p.seed
    return out


def fleet_record(p: TraversalParams, prepared: TraversalWorld) -> list[dict[str, Any]]:
    """Each agent's parameters by id, missing values filled in from the options: what the
    record's ``params.fleet`` shows. ``travel_time`` is seconds per grid edge,
    ``travel_speed`` metres per second (None without a metric scale)."""
    specs = agent_specs(p, prepared)
    world = prepared.world
    metric = prepared.edge_m is not None
    rows = []
    for i, (spec, nest) in enumerate(zip(specs, prepared.nests, strict=True), start=1):
        row = p.fleet[i - 1] if p.fleet is not None else None
        if row is not None and row.travel_time is not None:
            per_edge = row.travel_time
        elif row is not None and row.travel_speed is not None:
            per_edge = prepared.per_edge / row.travel_speed
        else:
            per_edge = p.travel_time
        rows.append({
            "id": i,
            "nest": list(world.xy(nest)),
            "altitude": spec.altitude,
            "travel_time": per_edge,
            "travel_speed": spec.travel_speed if metric else None,
            "job_time": spec.job_time,
            "up_speed": spec.up_speed,
            "down_speed": spec.down_speed,
        })
    return rows


def agent_specs(p: TraversalParams, prepared: TraversalWorld) -> list[Any]:
    """One AgentSpec per agent: the options' values, or each fleet row's own."""
    from swarmex.missions.traversal.agents import AgentSpec, uniform_agents

    nests = prepared.nests
    if p.fleet is None:
        return uniform_agents(
            nests, p.travel_time, p.job_time, prepared.per_edge, p.altitude, p.up_speed,
            p.down_speed,
        )
    metric = prepared.edge_m is not None
    specs = []
    for row, nest in zip(p.fleet, nests, strict=True):
        if row.travel_speed is not None:
            if not metric:
                raise InputError(
                    f"--fleet: agent {row.id}: travel_speed (m/s) needs a length scale: "
                    "give --edge-length (metres per grid edge), travel_time, or a GPS grid"
                )
            speed = row.travel_speed
        else:
            t = p.travel_time if row.travel_time is None else row.travel_time
            speed = prepared.per_edge / t
        specs.append(AgentSpec(
            nest,
            speed,
            p.job_time if row.job_time is None else row.job_time,
            p.altitude if row.altitude is None else row.altitude,
            p.up_speed if row.up_speed is None else row.up_speed,
            p.down_speed if row.down_speed is None else row.down_speed,
        ))
    return specs


#: The parameters that make the world; overriding one makes the recorded nests stale.
_WORLD_KEYS = ("map", "grid", "center", "radius", "nodes_on_edge", "obstacles")
#: Fleet fields that the record fills in from the option of the same name.
_FLEET_OPTIONS = ("altitude", "travel_time", "job_time", "up_speed", "down_speed")


def _fleet_row_again(
    row: Any, edge_m: float | None, params: Mapping[str, Any], given: Collection[str]
) -> Any:
    """A record's fleet row as a fleet row to run again.

    The record fills in every field, ``travel_time`` (s per edge) and, with a metric scale,
    ``travel_speed`` (m/s) both, and a fleet may give only one: keep the one that gives back
    both recorded numbers exactly (the speed, unless the row's time was given: the speed
    then was edge / time, and edge / speed need not round back to the time). A field filled
    in from an option the caller overrides (its value is the option's recorded one) is left
    out so that it takes the new value, and so is the nest when the world is overridden.
    """
    if not isinstance(row, dict):
        return row
    out = dict(row)
    if set(given) & set(_WORLD_KEYS):
        out.pop("nest", None)
    for key in _FLEET_OPTIONS:
        if key in given and key in out and out[key] == params.get(key):
            out.pop(key)
            if key == "travel_time":
                out.pop("travel_speed", None)
    if out.get("travel_speed") is None or out.get("travel_time") is None or edge_m is None:
        return out
    if edge_m / out["travel_speed"] == out["travel_time"]:
        out.pop("travel_time")
    else:
        out.pop("travel_speed")
    return out


class TraversalMission(Mission[TraversalParams, TraversalWorld]):
    name = "traversal"
    command = "traverse"
    summary = "Every agent does a job at every free cell (seed 000, MADGTA and baselines)."
    params_type = TraversalParams
    time_unit = "s"
    rerun_replaces = {
        "map": ("grid", "center"),
        "grid": ("map", "center"),
        "center": ("map", "grid"),
        "radius": ("map", "grid"),
        "nodes_on_edge": ("map", "grid"),
        "edge_length": ("center",),
        "nests": _WORLD_KEYS,  # the default nest is the world's first free cell
    }
    world_options = ("map", "grid", "center")

    def progress(self, params: TraversalParams, world: TraversalWorld) -> ProgressSpec | None:
        """Vertices with a job started, of the free cells (the exact MILP has no frames)."""
        if params.algorithm == "optimal":
            return None
        return ProgressSpec(world.world.free_cells, "jobs", lambda frame: frame.jobs_done)

    def rerun_values(self, record: ResultRecord, given: Collection[str] = ()) -> dict[str, Any]:
        """A recorded fleet as a fleet to run again (:func:`_fleet_row_again`)."""
        values = super().rerun_values(record, given)
        if isinstance(values.get("fleet"), list):
            # metres per edge of the run: a GPS grid's (its world says it), else edge_length
            edge_m = record.world.get("edge_m", record.params.get("edge_length"))
            values["fleet"] = [
                _fleet_row_again(row, edge_m, record.params, given) for row in values["fleet"]
            ]
        return values

    def team_metrics(self) -> Mapping[str, MetricInfo]:
        from swarmex.missions.traversal.metrics import TEAM_METRICS

        return TEAM_METRICS

    def prepare(self, params: TraversalParams) -> TraversalWorld:
        world = build_world(params)
        nests = resolve_nests(world, params.nests, params.team, params.fleet)
        if params.center is not None:  # edges are metres already
            prepared = TraversalWorld(world, nests, 1.0, world.edge_m)
        else:
            unit = 1.0 if params.edge_length is None else params.edge_length
            prepared = TraversalWorld(world, nests, unit, params.edge_length)
        agent_specs(params, prepared)  # a fleet row that cannot apply fails here, before work
        return prepared

    def execute(
        self,
        params: TraversalParams,
        world: TraversalWorld,
        on_frame: FrameCallback | None = None,
        *,
        trace: bool = True,
    ) -> Outcome:
        from swarmex.engine.record import without_trace
        from swarmex.missions.traversal import traversal_record

        p = params
        specs = agent_specs(p, world)
        rparams = record_params(p, world)
        unit = world.unit_length
        if p.algorithm == "optimal":
            record = _optimal(world.world, specs, p, rparams, unit)
            return Outcome(record if trace else without_trace(record), None, world.world)
        run = simulate(p, world, p.algorithm, on_frame)
        record = traversal_record(run, rparams, unit)
        return Outcome(record if trace else without_trace(record), run, world.world)


def simulate(p: TraversalParams, world: TraversalWorld, policy: Any,
             on_frame: FrameCallback | None = None) -> Any:
    """The simulator's run of ``p`` on the prepared ``world`` with ``policy`` (an algorithm
    spec, or an object that decides like one: the environment's stub): one place that turns
    the parameters into the run, for :meth:`TraversalMission.execute` and ``traversal_v0``."""
    from swarmex.comm.channel import Channel
    from swarmex.missions.traversal import run_traversal

    comm = math.inf if p.comm_range is None else p.comm_range
    return run_traversal(
        world.world,
        agent_specs(p, world),
        policy,
        p.seed,
        Channel(p.loss, p.delay, comm),
        start_interval=p.start_interval,
        unit_length=world.unit_length,
        job_failure=p.job_failure,
        on_frame=on_frame,
    )


def _optimal(
    world: Any, specs: list[Any], p: TraversalParams, rparams: dict[str, Any], unit: float
) -> Any:
    """``algorithm="optimal"``: the exact MILP (imported lazily: it pulls in the solver)."""
    try:
        from swarmex.missions.traversal.optimal import optimal_record
    except ModuleNotFoundError as exc:
        if exc.name != "swarmex.missions.traversal.optimal":
            raise
        raise InputError("--algorithm optimal is not available in this installation") from None
    objective: Literal["sum", "makespan"] = "makespan" if p.objective == "makespan" else "sum"
    return optimal_record(world, specs, objective, p.seed, rparams, unit)
