"""Branch 2's W (:func:`~swarmex.missions.traversal.selection.vacant_neighbours`) is the
neighbours of ``here`` not in Algorithm 1's KM, as :meth:`TraversalBelief.km_mask` defines
it: done, obstacle, or reserved by a *rival*; a vertex reserved by the agent itself stays a
candidate."""

from __future__ import annotations

import numpy as np

from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.missions.traversal.selection import vacant_neighbours
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import GridWorld


def test_w_keeps_a_neighbour_the_agent_reserved_itself_and_drops_a_rivals():
    world = GridWorld(np.ones((3, 3), dtype=bool))
    g = world.graph
    b = TraversalBelief(1, 3, KnownGraph(g), np.ones(4), np.ones(4))
    here = world.node(1, 1)
    nbrs = sorted(int(v) for v in g.neighbors(here))
    assert len(nbrs) == 4
    mine, rivals, done, free = nbrs
    b.reserved[mine] = 1  # me
    b.reserved[rivals] = 2
    b.status[done] = 3
    w = vacant_neighbours(g.indptr, g.indices, here, b.status, b.reserved, b.me)
    brute = [v for v in nbrs if not b.km_mask()[v]]
    assert w.tolist() == brute == [mine, free]
