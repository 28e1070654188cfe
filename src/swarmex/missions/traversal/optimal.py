"""The exact offline optimum of the traversal mission: a yardstick for MADGTA's gap.

MADGTA (seed 000) is online and greedy, and the thesis never compares it with an optimum.
When the thesis says "optimal" (spec §5) it only means "no extra travel". This module
computes the true optimum on small maps, with *full knowledge* (obstacles known in advance)
and central planning, so that MADGTA's distance to it is a measured number. It is a
baseline, not a policy: it reads the true world, which no mission policy may do.

Problem (seed 000 §3.1, with obstacles)
---------------------------------------
Agents start at their nests. Every free vertex reachable from a nest must get exactly one
job. Agent a's walk costs ``Σ_{v∈V'_a} J(a,v) + Σ_edges T(a,e)``, with ``J(a,v) = job_time_a``
and ``T(a,e) = length(e) · unit_length / travel_speed_a``. A walk may pass through a vertex
without doing its job there. A walk does not return: §3.1 has no return leg, and RTL is
``additional_time``. So a walk is fully described by the *order* of the agent's jobs,
joined by shortest paths. The problem is an **open, multi-depot, heterogeneous-fleet mTSP**
on the metric closure ``τ_a(i,j) = d(i,j) · unit_length / speed_a``, where ``d`` is the true
shortest-path length (:func:`swarmex.planning.distance.distance_field`, obstacles never
entered). Agents may share a nest, and an agent may do no job at all. With
``c_a(S) = τ_a · L(nest_a, S) + J_a · |S|`` the cheapest cost for agent a to do exactly the
jobs S (L is the shortest open path from the nest through S in the closure):

* ``"sum"`` minimises ``Σ_a c_a(S_a)`` over partitions ``(S_a)`` of the vertices. This is
  the thesis's objective, ``total_time_all``.
* ``"makespan"`` minimises ``max_a c_a(S_a)``. Among the plans with that makespan it then
  takes one of least sum, so the reported plan has no gratuitous detours.

The solve has its parts in their own modules: the instance (the metric closure) in
:mod:`~swarmex.missions.traversal.optimal_instance`, the greedy incumbent in
:mod:`~swarmex.missions.traversal.optimal_incumbent`, the two MILP formulations, "flow" (the
default for "sum") in :mod:`~swarmex.missions.traversal.optimal_flow` and "partition" (the
default for "makespan") in :mod:`~swarmex.missions.traversal.optimal_partition`, and the HiGHS
glue in :mod:`~swarmex.missions.traversal.optimal_highs`. This module checks the request,
reads the solution into walks and builds the record.

Both formulations solve both objectives (``formulation=``). The tests check that they
agree with each other and with a brute force.

Size limit
----------
:data:`MAX_FREE_VERTICES` was measured on this machine (2 shared cores) with
``bench/gap_traversal_optimal.py --scaling``. The full table is in docs/traversal-optimal.md.

* "sum": 36. Every 6×6 grid fits, which is the thesis's smallest simulation grid. Among 76
  measured solves with n ≤ 36 (2–4 agents, with and without obstacles) the slowest took
  22 s. The first ones that were not proven within 60 s came at n = 44–56.
* "makespan": 16. Every 4×4 grid fits. At n = 16 the slowest solve took 9.5 s; one
  n = 18 instance was not proven within 60 s. The 2ⁿ tables and the column count double
  with each vertex.

Above the limit, :func:`solve_optimal` refuses with :class:`~swarmex.errors.InputError`,
which the CLI turns into exit status 2. Within it, a time-out still returns the best plan
found (the improved greedy one at worst), with ``proven_optimal`` false and the remaining
gap.

Timing
------
The offline optimum starts every agent at ``t = 0`` at its nest, with no takeoff and no
staggered start (the simulator starts clients 0.5 s apart, plus takeoff). Neither enters
``total_time``, which is travel + job time only.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from swarmex.engine.record import AgentRecord, ResultRecord
from swarmex.errors import InputError
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.optimal_flow import _solve_flow
from swarmex.missions.traversal.optimal_highs import _highs
from swarmex.missions.traversal.optimal_instance import _prepare
from swarmex.missions.traversal.optimal_partition import _solve_partition
from swarmex.planning.distance import distance_field, steps_towards

if TYPE_CHECKING:
    from swarmex.worlds.graph import GraphWorld
    from swarmex.worlds.grid import GridWorld
    from swarmex.worlds.nodegraph import NodeGraph

    World = GridWorld | GraphWorld

Objective = Literal["sum", "makespan"]
Formulation = Literal["auto", "partition", "flow"]

#: Most vertices needing a job that :func:`solve_optimal` accepts by default, per objective
#: (measured: docs/traversal-optimal.md). ``max_vertices`` overrides it knowingly.
MAX_FREE_VERTICES: dict[str, int] = {"sum": 36, "makespan": 16}


#: Hard ceiling of the partition formulation: its tables hold 2ⁿ·n floats.
_PARTITION_CEILING = 20


@dataclass(frozen=True)
class AgentPlan:
    """One agent's share of the optimum: its job order, the walk doing them, and its times."""

    id: int  # 1-based, as in the simulator's logs
    spec: AgentSpec
    jobs: list[int]  # vertices where this agent does a job, in order
    walk: list[int]  # every vertex held, from the nest, along shortest paths
    travel_time: float
    job_time: float

    @property
    def total_time(self) -> float:
        return self.travel_time + self.job_time

    @property
    def moves(self) -> int:
        return len(self.walk) - 1


@dataclass(frozen=True)
class OptimalPlan:
    """Result of :func:`solve_optimal`.

    ``value`` is the objective of the returned plan, recomputed from the plan itself rather
    than taken from the solver's floating-point objective. ``bound`` is a proven lower bound
    on the optimum, and ``gap = (value − bound) / value``. ``proven_optimal`` is true only when
    the solver closed the primary objective.
    """

    objective: str
    formulation: str
    agents: list[AgentPlan]
    vertices: list[int]  # the vertices that needed a job (free, reachable from a nest)
    value: float
    bound: float
    gap: float
    proven_optimal: bool
    status: str
    solve_seconds: float
    secondary_status: str | None = None  # makespan: the least-sum pass at that makespan
    extra: dict = field(default_factory=dict)

    @property
    def total_time_all(self) -> float:
        return float(sum(a.total_time for a in self.agents))

    @property
    def makespan(self) -> float:
        return float(max(a.total_time for a in self.agents))


def _walk(
    graph: NodeGraph, blocked: np.ndarray, field_to_dst: np.ndarray, src: int, dst: int
) -> list[int]:
    """Vertices after ``src`` up to ``dst`` on a shortest path; lowest-index next hop."""
    path = []
    cur = src
    while cur != dst:
        hops = steps_towards(graph, field_to_dst, cur)
        cur = int(hops[~blocked[hops]].min())
        path.append(cur)
    return path


def solve_optimal(
    world: World,
    agents: list[AgentSpec],
    objective: Objective = "sum",
    unit_length: float = 1.0,
    time_limit: float = 60.0,
    *,
    formulation: Formulation = "auto",
    max_vertices: int | None = None,
) -> OptimalPlan:
    """Exact open multi-depot mTSP optimum of the traversal mission (see the module docstring).

    ``world`` is a :class:`~swarmex.worlds.GridWorld` or :class:`~swarmex.worlds.GraphWorld`.
    The vertices needing a job are the free vertices reachable from some nest.
    ``formulation="auto"`` uses the flow model for "sum" and the partition model for
    "makespan", the faster of the two in each case as measured. ``max_vertices`` defaults to
    :data:`MAX_FREE_VERTICES` for the objective.

    Raises :class:`InputError` for a bad objective or formulation, bad nests, or more than
    ``max_vertices`` such vertices. ``time_limit`` (seconds) bounds all solver calls
    together. If it runs out, the best plan found is returned with ``proven_optimal`` false.
    """
    if objective not in ("sum", "makespan"):
        raise InputError(f"optimal: objective must be 'sum' or 'makespan', got {objective!r}")
    if formulation not in ("auto", "partition", "flow"):
        raise InputError(
            f"optimal: formulation must be 'auto', 'partition' or 'flow', got {formulation!r}"
        )
    if not unit_length > 0:
        raise InputError(f"optimal: unit length must be > 0, got {unit_length}")
    if not time_limit > 0:
        raise InputError(f"optimal: time limit must be > 0, got {time_limit}")
    if formulation == "auto":
        formulation = "flow" if objective == "sum" else "partition"
    limit = MAX_FREE_VERTICES[objective] if max_vertices is None else int(max_vertices)
    if formulation == "partition":
        limit = min(limit, _PARTITION_CEILING)  # its 2ⁿ·n tables would not fit in memory
    t0 = time.perf_counter()
    inst, fields = _prepare(world, agents, unit_length, limit, objective)
    deadline = t0 + time_limit
    if formulation == "partition":
        out = _solve_partition(inst, objective, deadline)
    else:
        out = _solve_flow(inst, objective, deadline)

    graph = world.graph
    blocked = np.asarray(world.blocked, dtype=bool)
    plans = []
    for a, (spec, route) in enumerate(zip(agents, out.routes, strict=True)):
        jobs = [inst.verts[i] for i in route]
        walk = [int(spec.nest)]
        for v in jobs:
            walk += _walk(graph, blocked, fields[v], walk[-1], v)
        length = sum(graph.edge_length(u, v) for u, v in zip(walk, walk[1:], strict=False))
        plans.append(
            AgentPlan(a + 1, spec, jobs, walk, float(length * inst.tpu[a]),
                      float(inst.job[a] * len(jobs)))
        )
    totals = [p.total_time for p in plans]
    value = float(sum(totals)) if objective == "sum" else float(max(totals))
    bound = min(out.bound, value)
    if out.proven:
        bound = value  # the solver's bound equals the value up to its tolerances
    gap = 0.0 if value <= 0 else max(0.0, (value - bound) / value)
    return OptimalPlan(
        objective=objective,
        formulation=formulation,
        agents=plans,
        vertices=inst.verts,
        value=value,
        bound=float(bound),
        gap=float(gap),
        proven_optimal=out.proven,
        status=out.status,
        solve_seconds=time.perf_counter() - t0,
        secondary_status=out.secondary,
        extra=out.extra,
    )


def plan_metrics(
    plan: OptimalPlan, world: World, unit_length: float = 1.0
) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """The traversal record's metrics for a plan, under MADGTA's names (metrics.py).

    ``nodes_traveled`` counts edge moves plus one when the agent's first job is at its nest,
    as :func:`~swarmex.missions.traversal.metrics.agent_metrics` does, so the two records
    compare column by column. ``additional_time`` is takeoff + RTL from the last vertex +
    landing. ``messages`` are 0 because a central offline plan sends none.
    """
    per_agent = []
    for p in plan.agents:
        spec = p.spec
        home = distance_field(world.graph, spec.nest, world.blocked)[p.walk[-1]]
        rtl = float(home) * unit_length / spec.travel_speed
        traveled = p.moves + (1 if p.jobs and p.jobs[0] == spec.nest else 0)
        per_agent.append({
            "nodes_done": len(p.jobs),
            "nodes_traveled": traveled,
            "nodes_without_job": traveled - len(p.jobs),
            "travel_time": p.travel_time,
            "job_time": p.job_time,
            "total_time": p.total_time,
            "additional_time": spec.takeoff_time + rtl + spec.landing_time,
            "failed_jobs": 0,
            "finished_at": p.total_time,
        })
    total_times = [m["total_time"] for m in per_agent]
    done = [v for p in plan.agents for v in p.jobs]
    totals = {
        "total_time_all": float(sum(total_times)),
        "nodes_without_job_all": int(sum(m["nodes_without_job"] for m in per_agent)),
        "nodes_done_all": len(done),
        "travel_time_all": float(sum(m["travel_time"] for m in per_agent)),
        "job_time_all": float(sum(m["job_time"] for m in per_agent)),
        "additional_time_all": float(sum(m["additional_time"] for m in per_agent)),
        "max_total_time": float(max(total_times)),
        "mission_end": float(max(total_times)),
        "reachable_nodes": len(plan.vertices),
        "nodes_missed": len(set(plan.vertices) - set(done)),
        "duplicate_jobs": len(done) - len(set(done)),
        "messages": 0,
        "message_bytes": 0,
        "objective_value": plan.value,
        "lower_bound": plan.bound,
        "mip_gap": plan.gap,
        "proven_optimal": plan.proven_optimal,
    }
    return totals, per_agent


def optimal_record(
    world: World,
    agents: list[AgentSpec],
    objective: Objective,
    seed: int,
    params: dict,
    unit_length: float = 1.0,
    time_limit: float = 60.0,
) -> ResultRecord:
    """Solve, then build the traversal :class:`ResultRecord` with algorithm ``"optimal"``.

    The schema and metric names are those of MADGTA's :func:`traversal_record`, so a sweep can
    set the two side by side. All agents start at ``t = 0``, with no staggered starts and no
    takeoff. Each trajectory lists every vertex held along the shortest-path walk with its
    arrival time, and each job its start time. ``seed`` is only recorded: the optimum uses no
    randomness.
    """
    plan = solve_optimal(world, agents, objective, unit_length, time_limit)
    totals, per_agent = plan_metrics(plan, world, unit_length)
    pos = world.graph.pos
    records = []
    for p, met in zip(plan.agents, per_agent, strict=True):
        tpu = unit_length / p.spec.travel_speed
        t = 0.0
        traj = [[t, *pos[p.walk[0]].tolist()]]
        jobs: list[list[float]] = []
        pending = list(p.jobs)
        if pending and pending[0] == p.walk[0]:
            jobs.append([t, *pos[p.walk[0]].tolist()])
            t += p.spec.job_time
            pending.pop(0)
        for u, v in zip(p.walk, p.walk[1:], strict=False):
            t += world.graph.edge_length(u, v) * tpu
            traj.append([t, *pos[v].tolist()])
            if pending and v == pending[0]:
                jobs.append([t, *pos[v].tolist()])
                t += p.spec.job_time
                pending.pop(0)
        records.append(AgentRecord(p.id, met, traj, jobs))
    return ResultRecord(
        mission="traversal",
        algorithm="optimal",
        params={**params, "objective": objective},
        seed=seed,
        world=world.describe(),
        complete=totals["nodes_missed"] == 0 and totals["duplicate_jobs"] == 0,
        makespan=totals["max_total_time"],
        time_unit="s",
        metrics=totals,
        agents=records,
        wall_seconds=plan.solve_seconds,
        extra={
            "solver": {
                "name": "HiGHS",
                "version": _highs().version(),
                "formulation": plan.formulation,
                "status": plan.status,
                "secondary_status": plan.secondary_status,
                "time_limit": time_limit,
                **plan.extra,
            }
        },
    )
