"""Two roadmap rules a mutation run found unpinned: the free agent's fair share weighs the
agents already in a branch as ``busy + 1`` (takeover and fair-share), and the PRM finder's
trail is the *loop-erased* walk (a revisited node keeps its first visit's place)."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.roadmap.blackboard import HALF, PRMBoard, WMABoard
from swarmex.missions.roadmap.sim import build_roadmap
from swarmex.missions.roadmap.wma_policy import WMAAgent
from swarmex.planning.prm import build_prm

from .conftest import cluster


@pytest.mark.parametrize("rule", ["takeover", "fairshare"])
def test_a_free_agent_picks_the_largest_rem_sub_over_busy_plus_one(clutter, rule):
    """Module docstring: "A free agent picks the branch of largest share", the share being
    ``rem_sub / (busy + 1)``. Branch 0: 12 edges left, 1 agent in it: 12 / 2 = 6. Branch 1:
    5 left, nobody: 5 / 1 = 5. Branch 2: nothing left. Branch 0 wins (with busy + 0.5 it
    would be 8 against 10, branch 1)."""
    rm = build_roadmap(clutter, "wma-rrt", cluster(3), 60, 10, np.random.default_rng(0))
    board = WMABoard(rm, 3)
    agent = WMAAgent(0, cluster(3)[0], board, rule=rule)
    fe = board.first_edge
    board.rem_sub[fe] = [12, 5, 0]
    board.busy[fe] = [1, 0, 0]
    assert {agent._pick_branch(np.random.default_rng(s)) for s in range(10)} == {0}


def test_the_prm_trail_is_the_loop_erased_walk(clutter):
    """A walk a - b - c - b - d leaves the trail a -> b -> d: the loop b - c - b is erased,
    b keeps its place, and only the trail's edges are marked 1/2."""
    rng = np.random.default_rng(3)
    rm = build_prm(clutter, cluster(2), 150, 10, rng)
    adj = rm.adjacency
    a = next(v for v in range(rm.n_nodes) if len(adj[v]) >= 1
             and any(len(adj[b]) >= 3 for b, _ in adj[v]))
    b, e_ab = next((b, e) for b, e in adj[a] if len(adj[b]) >= 3)
    (c, e_bc), (d, e_bd) = [(v, e) for v, e in adj[b] if v != a][:2]
    board = PRMBoard(rm)
    walk = [(a, -1), (b, e_ab), (c, e_bc), (b, e_bc), (d, e_bd)]
    board.flag_goal(walk, d, [np.array([0.0, 0.0])], 0, 5)
    assert board.trail_next == {a: (b, e_ab), b: (d, e_bd)}
    assert sorted(e for e, w in enumerate(board.w_g) if w == HALF) == sorted([e_ab, e_bd])
