"""The exact optimum's instance: the metric closure of a traversal world, and a solve's outcome.

Every part of the offline optimum (:mod:`swarmex.missions.traversal.optimal`) works on the
same numbers: the free vertices reachable from a nest, their shortest-path distances, each
agent's cost rates and the classes of identical agents. :func:`_prepare` builds them once
from the world; the incumbent and both formulations read them and return an
:class:`_Outcome`. Kept apart so that those modules share one definition and import no
solver they do not use.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.sim import validate_nests
from swarmex.planning.distance import distance_field

if TYPE_CHECKING:
    from swarmex.worlds.graph import GraphWorld
    from swarmex.worlds.grid import GridWorld

    World = GridWorld | GraphWorld

_REL = 1e-9  # relative tolerance when comparing costs computed along different float paths


@dataclass
class _Instance:
    """The closure: n job vertices, their distances, and the agents' cost rates."""

    verts: list[int]
    dist: np.ndarray  # (n, n) shortest-path lengths in world length units
    nest_idx: list[int]  # each agent's nest as an index into verts
    tpu: np.ndarray  # seconds per length unit, per agent
    job: np.ndarray  # seconds per job, per agent
    classes: list[list[int]]  # agents equal in (nest, speed, job time), in index order

    @property
    def n(self) -> int:
        return len(self.verts)

    @property
    def m(self) -> int:
        return len(self.nest_idx)

    def route_cost(self, a: int, route: list[int]) -> float:
        seq = [self.nest_idx[a], *route]
        travel = sum(self.dist[i, j] for i, j in zip(seq, seq[1:], strict=False))
        return float(travel * self.tpu[a] + self.job[a] * len(route))


@dataclass
class _Outcome:
    """What a formulation returns: job orders (indices into verts) and the proof status."""

    routes: list[list[int]]
    bound: float
    proven: bool
    status: str
    secondary: str | None = None
    extra: dict = field(default_factory=dict)


def _prepare(
    world: World, agents: list[AgentSpec], unit_length: float, max_vertices: int, objective: str
) -> tuple[_Instance, dict[int, np.ndarray]]:
    validate_nests(world, agents)
    graph = world.graph
    blocked = np.asarray(world.blocked, dtype=bool)
    nests = [int(s.nest) for s in agents]
    reach = np.isfinite(distance_field(graph, nests, blocked)) & ~blocked
    verts = [int(v) for v in np.nonzero(reach)[0]]
    if len(verts) > max_vertices:
        raise InputError(
            f"optimal: the map has {len(verts)} free vertices reachable from the nests; the "
            f"exact MILP for objective {objective!r} is limited to {max_vertices} "
            "(use madgta or nearest on larger maps)"
        )
    fields = {v: distance_field(graph, v, blocked) for v in verts}
    dist = np.array([[fields[u][v] for v in verts] for u in verts]).reshape(len(verts), -1)
    index = {v: i for i, v in enumerate(verts)}
    tpu = np.array([unit_length / s.travel_speed for s in agents], dtype=float)
    job = np.array([float(s.job_time) for s in agents])
    classes: dict[tuple, list[int]] = {}
    for a, s in enumerate(agents):
        classes.setdefault((s.nest, float(tpu[a]), float(job[a])), []).append(a)
    inst = _Instance(verts, dist, [index[v] for v in nests], tpu, job, list(classes.values()))
    return inst, fields
