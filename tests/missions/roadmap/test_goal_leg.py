"""The straight leg a finder leaves beside the anchor (§3.2): from the anchor node to the
point on its last edge where it saw the goal, then to the goal, so that followers walk only
along the finder's line of sight; when it saw the goal from the anchor itself, the leg is the
goal alone (no zero-length step). The same for a WMA-RRT agent and a PRM walker."""

from __future__ import annotations

import numpy as np

from swarmex.missions.roadmap.blackboard import PRMBoard, WMABoard
from swarmex.missions.roadmap.prm_policy import PRMWalker
from swarmex.missions.roadmap.wma_policy import WMAAgent
from swarmex.planning.prm import build_prm
from swarmex.planning.rrt_wma import build_wma_rrt

from .conftest import cluster


def _legs(board):
    return [np.asarray(p).tolist() for p in board.leg]


def _wma_finder_at_a_node(clutter):
    """A WMA-RRT agent that has walked its first edge and stands on node 1."""
    rm = build_wma_rrt(clutter, cluster(2), 200, 10, np.random.default_rng(5))
    board = WMABoard(rm, 2)
    a0 = WMAAgent(0, cluster(2)[0], board)
    a0.node, a0.state = 0, "explore"
    src = np.array(rm.pos[0], dtype=np.float64)
    mv = a0._edge_move(int(board.first_edge[0]))
    a0.arrive(mv, 1)
    return rm, board, a0, src


def test_wma_finder_that_saw_the_goal_from_its_node_leaves_the_goal_alone(clutter):
    rm, board, a0, _ = _wma_finder_at_a_node(clutter)
    goal = a0.xy + np.array([3.0, 4.0])
    a0.found_goal(a0.xy.copy(), goal, 1)
    assert board.anchor == a0.node
    assert _legs(board) == [goal.tolist()]  # one step from the anchor straight to the goal


def test_wma_finder_that_saw_the_goal_mid_edge_leaves_the_sighting_point_first(clutter):
    rm, board, a0, src = _wma_finder_at_a_node(clutter)
    p = (src + a0.xy) / 2  # seen halfway along its last edge
    goal = p + np.array([3.0, 4.0])
    a0.found_goal(p, goal, 1)
    assert _legs(board) == [p.tolist(), goal.tolist()]
    # a follower at the anchor walks the two legs, one a step, and is at the goal
    a0.state = "explore"
    rng = np.random.default_rng(0)
    steps = []
    for t in range(2, 10):
        mv = a0.decide(t, rng)
        if mv is None:
            break
        a0.arrive(mv, t)
        steps.append(a0.xy.tolist())
    assert steps == [p.tolist(), goal.tolist()] and a0.state == "at-goal"


def _prm_walker_after_one_edge(clutter):
    rng = np.random.default_rng(3)
    starts = cluster(2)
    rm = build_prm(clutter, starts, 150, 10, rng)
    while rm.entry_node.min() < 0:
        rm = build_prm(clutter, starts, 150, 10, rng)
    board = PRMBoard(rm)
    w = PRMWalker(0, starts[0], int(rm.entry_node[0]), board)
    draw = np.random.default_rng(0)
    w.arrive(w.decide(0, draw), 0)  # the entry leg onto the roadmap
    src = w.xy.copy()
    w.arrive(w.decide(1, draw), 1)  # one edge
    assert not np.allclose(src, w.xy)
    return board, w, src


def test_prm_finder_that_saw_the_goal_from_its_node_leaves_the_goal_alone(clutter):
    board, w, _ = _prm_walker_after_one_edge(clutter)
    goal = w.xy + np.array([3.0, 4.0])
    w.found_goal(w.xy.copy(), goal, 1)
    assert board.anchor == w.node
    assert _legs(board) == [goal.tolist()]


def test_prm_finder_that_saw_the_goal_mid_edge_leaves_the_sighting_point_first(clutter):
    board, w, src = _prm_walker_after_one_edge(clutter)
    p = (src + w.xy) / 2
    goal = p + np.array([3.0, 4.0])
    w.found_goal(p, goal, 1)
    assert _legs(board) == [p.tolist(), goal.tolist()]
