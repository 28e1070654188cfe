"""OMPL's planners as roadmaps: its PRM, the standard baseline, and its RRT (build time).

Why this exists: seed 004 compares WMA-RRT with "PRM", and swarmex's own PRM
(:mod:`swarmex.planning.prm`) follows the paper's description of multiple-query planners
(random trees grown and merged). ``--planner ompl-prm`` puts the textbook planner beside it,
as a maintained library implements it: OMPL's ``geometric.PRM`` (Kavraki, Švestka, Latombe &
Overmars 1996) — draw a free milestone, connect it to its ``k`` = 10 nearest milestones (OMPL's
default connection strategy) by free straight segments, repeat — so the comparison does not
rest on a PRM we invented.

As OMPL intends, the planner never knows the geometry; it asks two objects given here:

* a **valid-state sampler** drawing from the run's numpy generator
  (:meth:`PolygonWorld.sample_free`, uniform over the free space): a roadmap is a function of
  the seed, as every roadmap here is. OMPL's own random generator is seeded once per
  process, not per run, so it could not give that;
* a **motion validator** that is the world's exact segment test
  (:meth:`PolygonWorld.segment_free`), the one the agents' moves and the replay checker use;
  OMPL's default checks states a resolution apart along the segment and could cut a corner.

The **node budget** is the roadmap's milestone count: the roadmap grows
(``growRoadmap`` under a termination condition on ``milestoneCount``) until it holds
``n_nodes`` milestones; edges are whatever OMPL's connection strategy makes of them. The
step ε plays no part: OMPL's PRM has no edge length (an edge is as long as a 10-nearest
connection). The ``bindings`` are the ``ompl`` wheel on PyPI (extra ``ompl``).

OMPL's RRT (``geometric.RRT`` with range ε, no goal bias and a goal it never reaches) is grown
to the same budget from one root, for the build-time comparison of the roadmap study.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from swarmex.errors import require
from swarmex.planning.prm import entry_nodes
from swarmex.planning.roadmap import Roadmap
from swarmex.worlds.polygon import PolygonWorld

K_NEIGHBOURS = 10  # OMPL's PRM default (ompl::magic::DEFAULT_NEAREST_NEIGHBORS)


def ompl_modules() -> tuple[Any, Any, Any]:
    """``(ompl.base, ompl.geometric, ompl.util)``, or one line naming the extra to install."""
    require("ompl.base", "ompl", "OMPL's planners (--planner ompl-prm)")
    from ompl import base, geometric, util

    util.setLogLevel(util.LOG_WARN)
    return base, geometric, util


@contextlib.contextmanager
def _space(world: PolygonWorld, draw: Callable[[], np.ndarray]) -> Iterator[tuple[Any, Any]]:
    """OMPL's view of ``world``: ``(SpaceInformation, motion validator)``, set up with our
    sampler (``draw()`` gives the next free point) and our exact segment test. The motion
    validator counts its valid answers (``.valid``). On exit the Python objects that OMPL
    holds are released, so none outlives the build (nanobind reports leaked ones at exit)."""
    ob, _, _ = ompl_modules()
    xmin, ymin, xmax, ymax = world.bounds

    class Sampler(ob.ValidStateSampler):  # type: ignore[name-defined]
        def sample(self, state: Any) -> bool:
            x, y = draw()
            state[0] = float(x)
            state[1] = float(y)
            return True

        def sampleNear(self, state: Any, near: Any, distance: float) -> bool:  # noqa: N802
            return False  # PRM's growth never asks; a refusal is always allowed

    class Segments(ob.MotionValidator):  # type: ignore[name-defined]
        valid = 0

        def checkMotion(self, a: Any, b: Any) -> bool:  # noqa: N802
            ok = world.segment_free(a[0], a[1], b[0], b[1])
            self.valid += ok
            return ok

    space = ob.RealVectorStateSpace(2)
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0, xmin)
    bounds.setHigh(0, xmax)
    bounds.setLow(1, ymin)
    bounds.setHigh(1, ymax)
    space.setBounds(bounds)
    si = ob.SpaceInformation(space)
    si.setStateValidityChecker(lambda s: bool(world.points_free(np.array([[s[0], s[1]]]))[0]))
    si.setValidStateSamplerAllocator(lambda info: Sampler(info))
    mv = Segments(si)
    si.setMotionValidator(mv)
    si.setup()
    try:
        yield si, mv
    finally:
        si.clearValidStateSamplerAllocator()


def _graph(ob: Any, si: Any, planner: Any) -> tuple[np.ndarray, np.ndarray]:
    """The planner's vertices (insertion order) and undirected edges (sorted pairs)."""
    data = ob.PlannerData(si)
    planner.getPlannerData(data)
    n = data.numVertices()
    pos = np.empty((n, 2))
    for i in range(n):
        s = data.getVertex(i).getState()
        pos[i] = (s[0], s[1])
    pairs = {(min(i, j), max(i, j)) for i in range(n) for j in data.getEdges(i) if i != j}
    edges = np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2)
    return pos, edges


class _Draws:
    """Free points from the run's generator, drawn in batches and served one by one."""

    def __init__(self, world: PolygonWorld, rng: np.random.Generator, batch: int) -> None:
        self.world, self.rng, self.batch = world, rng, max(1, batch)
        self.pts = np.empty((0, 2))
        self.i = 0
        self.served: list[np.ndarray] = []

    def __call__(self) -> np.ndarray:
        if self.i >= len(self.pts):
            self.pts = self.world.sample_free(self.rng, self.batch)
            self.i = 0
        self.i += 1
        self.served.append(self.pts[self.i - 1])
        return self.pts[self.i - 1]

    def in_draw_order(self, pos: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(pos, edges)`` renumbered so that the vertices are in the order their points were
        drawn (OMPL's planner data lists vertices as its edges meet them). A state holds the
        drawn doubles exactly, so each vertex is found by its coordinates; draws that did not
        become milestones (OMPL may sample more than it keeps) are skipped."""
        index = {(float(x), float(y)): i for i, (x, y) in enumerate(self.served)}
        drawn = np.array([index[(float(x), float(y))] for x, y in pos], dtype=np.int64)
        order = np.empty(len(drawn), dtype=np.int64)
        order[np.argsort(drawn, kind="stable")] = np.arange(len(drawn))
        out = np.empty_like(pos)
        out[order] = pos
        e = np.sort(order[edges], axis=1) if len(edges) else edges
        e = e[np.lexsort((e[:, 1], e[:, 0]))] if len(e) else e
        return out, e


def build_ompl_prm(world: PolygonWorld, starts: np.ndarray, n_nodes: int,
                   rng: np.random.Generator) -> Roadmap:
    """OMPL's PRM with ``n_nodes`` milestones; agents enter at the nearest visible node."""
    ob, og, _ = ompl_modules()
    starts = np.asarray(starts, dtype=np.float64).reshape(-1, 2)
    draws = _Draws(world, rng, n_nodes)  # one batch: every draw is a milestone
    with _space(world, draws) as (si, _mv):
        prm = og.PRM(si)
        prm.setProblemDefinition(ob.ProblemDefinition(si))  # growRoadmap needs one
        prm.setup()
        prm.growRoadmapPtc(ob.PlannerTerminationCondition(
            lambda: prm.milestoneCount() >= n_nodes))
        k = prm.getMaxNearestNeighbors()
        pos, edges = draws.in_draw_order(*_graph(ob, si, prm))
        prm.clear()
    return Roadmap(
        kind="ompl-prm", pos=pos, edges=edges, starts=starts,
        entry_node=entry_nodes(world, pos, starts), samples=len(draws.served),
        info={"library": "ompl", "neighbours": int(k), "requested_nodes": int(n_nodes)},
    )


def build_ompl_rrt(world: PolygonWorld, root: np.ndarray, n_nodes: int, step: float,
                   rng: np.random.Generator) -> Roadmap:
    """OMPL's RRT from ``root`` (range ``step``) grown to ``n_nodes`` nodes, root included.

    Its goal is a state it never reaches (goal bias 0: never sampled), so growth stops at the
    node budget: every valid motion adds one node, and the validator counts them. OMPL's
    RRT samples with OMPL's own generator (not the run's): for build times only.
    """
    ob, og, _ = ompl_modules()
    root = np.asarray(root, dtype=np.float64).reshape(2)
    draws = _Draws(world, rng, 1)
    with _space(world, draws) as (si, mv):
        pdef = ob.ProblemDefinition(si)
        start = si.allocState()
        start[0], start[1] = float(root[0]), float(root[1])
        pdef.addStartState(start)
        goal = ob.GoalState(si)
        far = si.allocState()
        far[0], far[1] = float(root[0]), float(root[1]) + 1e-7  # reached with probability 0
        goal.setState(far)
        pdef.setGoal(goal)
        rrt = og.RRT(si)
        rrt.setRange(float(step))
        rrt.setGoalBias(0.0)
        rrt.setProblemDefinition(pdef)
        rrt.setup()
        rrt.solve(ob.PlannerTerminationCondition(lambda: mv.valid >= n_nodes - 1))
        pos, edges = _graph(ob, si, rrt)
        rrt.clear()
    return Roadmap(kind="ompl-rrt", pos=pos, edges=edges, starts=root[None],
                   entry_node=np.zeros(1, dtype=np.int64), samples=int(mv.valid),
                   info={"library": "ompl", "range": float(step)})


__all__ = ["K_NEIGHBOURS", "build_ompl_prm", "build_ompl_rrt", "ompl_modules"]
