"""``madgta-h``'s insertion-cost test on a hand-computed corridor (the module docstring's
formula): a rival's insertion cost for ``v`` is ``J_r + tpu_r · (step + g_r(v) / K(v))``,
its detour to ``v``'s cell split over the ``K(v)`` vacant vertices of that cell."""

from __future__ import annotations

import numpy as np

from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.missions.traversal.madgta_h import MadgtaH
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import GridWorld


def test_the_rivals_detour_is_shared_by_the_vacant_vertices_of_the_cell():
    """A 1 x 13 corridor, unit edges (step = 1). Me (id 1): 1 s per unit, 10 s per job (11 s
    per vertex), at vertex 0. Rival (id 2, cheaper): 1 s per unit, 5 s per job (6 s), at
    vertex 12. Vertices 0 and 12 are done, 1..11 vacant.

    Arrival plus job: mine v + 10, the rival's 17 - v, so my cell is {1, 2, 3} (K = 3) and the
    rival's {4 .. 11}. The rival's detour to v = 1, 2, 3 is 3, 2, 1, so its insertion cost is
    5 + 1 + detour / 3 = 7, 6.67, 6.33 (6 beyond). With rho = 0.6 I keep v only when
    v + 10 <= 1.6 x that: 11 <= 11.2 for v = 1; 12 > 10.67 for v = 2; nothing further out.
    (Without the split over K, v = 2 would cost the rival 8 and be kept too.)"""
    world = GridWorld(np.ones((1, 13), dtype=bool))
    tpu = np.array([0.0, 1.0, 1.0])
    jt = np.array([0.0, 10.0, 5.0])
    b = TraversalBelief(1, 2, KnownGraph(world.graph), tpu, jt)
    b.loc[1], b.loc[2] = 0, 12
    b.mark_done(0, 1)
    b.mark_done(12, 2)
    policy = MadgtaH(rho=0.6)
    assert policy.cheaper_rivals(b).tolist() == [2]
    c = policy.claims(b)
    assert c.vacant.tolist() == list(range(1, 12))
    assert c.vacant[c.keep].tolist() == [1]
    assert not c.retire


def test_a_vertex_that_costs_me_exactly_the_rivals_insertion_cost_is_kept():
    """The docstring's test is ``my cost(v) <= (1 + rho) · min insertion cost``: a tie keeps
    the vertex. Corridor as above, rho = 0; me 1 s per unit and 6 s per job (7 s per vertex,
    the rival 6 s). My cell is {1 .. 5} (v + 6 <= 17 - v), K = 5; the rival's detour to v = 1
    is 5, so its insertion cost is 5 + 1 + 5 / 5 = 7 = my cost 1 + 6: kept; v = 2 costs me 8
    against 6.8, and so on: not kept."""
    world = GridWorld(np.ones((1, 13), dtype=bool))
    b = TraversalBelief(1, 2, KnownGraph(world.graph), np.array([0.0, 1.0, 1.0]),
                        np.array([0.0, 6.0, 5.0]))
    b.loc[1], b.loc[2] = 0, 12
    b.mark_done(0, 1)
    b.mark_done(12, 2)
    c = MadgtaH(rho=0.0).claims(b)
    assert c.vacant[c.keep].tolist() == [1]
