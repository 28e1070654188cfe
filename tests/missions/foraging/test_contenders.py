"""Who wins a contested cell (resolve.py, Alg. 1), on hand-made contenders.

The module docstring's rule: "among robots that want the same non-nest cell the
lexicographically larger ``(x, y)`` wins (ties, possible only in the nest, by smaller id);
robots still following their exploration route rank above everyone", and when two robots
move into one cell "the later (lower-priority) one yields". The compiled loop is checked
against the Python rule elsewhere; these pin the Python rule itself, so that a change made
to both is caught.
"""

from __future__ import annotations

import pytest

from swarmex.missions.foraging.resolve import priority, resolve

NEST = (0, 0)
C = (5, 5)  # the contested cell, away from the nest


def _round(cur, route_following=None):
    """Every robot wants C first and else stays put; the new cells after one round."""
    rf = route_following or [False] * len(cur)
    opts = [[C, p] for p in cur]
    order = priority(cur, rf, opts)
    return order, resolve(cur, opts, order, NEST)


@pytest.mark.parametrize(
    ("cur", "winner"),
    [
        ([(4, 5), (6, 5)], 1),  # from the west and from the east: larger x
        ([(6, 5), (4, 5)], 0),  # the same, ids swapped
        ([(5, 4), (5, 6)], 1),  # from below and from above (same x): larger y
        ([(5, 6), (5, 4)], 0),
        ([(5, 6), (6, 5)], 1),  # x first: (6, 5) beats (5, 6)
        ([(6, 5), (5, 6)], 0),
        ([(4, 5), (5, 4), (6, 5), (5, 6)], 2),  # all four sides: (6, 5) is the largest
    ],
)
def test_the_larger_x_then_the_larger_y_takes_the_contested_cell(cur, winner):
    order, new = _round(cur)
    assert order[0] == winner
    assert new[winner] == C
    assert all(new[a] == cur[a] for a in range(len(cur)) if a != winner)  # the rest stay


def test_priority_orders_by_larger_x_then_larger_y():
    cur = [(1, 1), (3, 0), (1, 2), (3, 2), (2, 9)]
    assert priority(cur, [False] * 5) == [3, 1, 4, 2, 0]


def test_a_tie_in_the_nest_goes_to_the_smaller_id():
    """Two robots in the nest cell both want its east neighbour: robot 0 takes it, robot 1
    stays (in the nest, where robots may share a cell); with three, the smallest id."""
    cur = [NEST, NEST]
    opts = [[(1, 0), NEST], [(1, 0), NEST]]
    order = priority(cur, [False, False], opts)
    assert order == [0, 1]
    assert resolve(cur, opts, order, NEST) == [(1, 0), NEST]
    assert priority([NEST] * 3, [False] * 3) == [0, 1, 2]
    # the id breaks the tie only: a robot outside the nest with a larger (x, y) still leads
    assert priority([NEST, NEST, (0, 1)], [False] * 3) == [2, 0, 1]


@pytest.mark.parametrize("follower", [0, 1])
def test_a_robot_following_its_route_takes_the_cell_from_a_larger_one(follower):
    """Route followers rank above everyone: the one at the smaller (4, 5) takes C from the
    one at (6, 5); without the route, (6, 5) would."""
    cur = [(4, 5), (6, 5)]
    rf = [a == follower for a in range(2)]
    order, new = _round(cur, rf)
    assert order[0] == follower
    assert new[follower] == C and new[1 - follower] == cur[1 - follower]


def test_route_followers_among_themselves_go_by_larger_x_y():
    cur = [(4, 5), (6, 5), (5, 6)]
    assert priority(cur, [True, False, True]) == [2, 0, 1]


@pytest.mark.parametrize("order", [[0, 1], [1, 0]])
def test_of_two_robots_moving_into_one_cell_the_later_in_the_order_yields(order):
    """resolve() on its own, with the order given: neither robot is in C (no stayer), so
    the one later in ``order`` is bumped to its next option (here its own cell)."""
    cur = [(4, 5), (6, 5)]
    opts = [[C, cur[0]], [C, cur[1]]]
    first, later = order
    new = resolve(cur, opts, order, NEST)
    assert new[first] == C and new[later] == cur[later]
