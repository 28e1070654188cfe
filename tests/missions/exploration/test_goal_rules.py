"""Goal rules a mutation run found unpinned: where hungarian-exclusion heads inside its
assigned target's zone, and how long an announced goal keeps its zone closed."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.exploration.strategies import (
    GoalContext,
    greedy_exclusion,
    hungarian_exclusion,
    pocket_cells,
)
from swarmex.sensing.frontiers import Frontiers
from tests.missions.exploration.helpers import config, team


def _field(steps_by_x):
    f = np.full((1, 100), 99)
    for x, d in steps_by_x.items():
        f[0, x] = d
    return f


def test_hungarian_exclusion_heads_for_the_nearest_cell_in_its_targets_zone():
    """Module docstring: "the robot heads for the nearest frontier cell within laser range of
    its assigned target (the target is a region's representative ...)". A region of three
    cells (31..33, 0) is one target, represented by its middle cell (32, 0); the rivals by
    (5, 0) and (60, 0) take those, so this robot is assigned (32, 0) and goes to (31, 0),
    one step nearer and 1 cell from the target."""
    xs = np.array([5, 60, 31, 32, 33])
    ys = np.zeros(5, dtype=int)
    fr = Frontiers(ys, xs, np.array([0, 1, 2, 2, 2]), np.array([1, 1, 3]), 0)
    fields = {(6, 0): _field({5: 1, 60: 54, 31: 40, 32: 41, 33: 42}),
              (58, 0): _field({5: 53, 60: 2, 31: 27, 32: 26, 33: 25})}
    ctx = GoalContext(me=0, pos=(0, 0), frontiers=fr, eligible=np.ones(5, bool),
                      dist=xs.copy(), laser_cells=10.0, team_pos={1: (6, 0), 2: (58, 0)},
                      field_from=lambda c: fields[c])
    assert greedy_exclusion(ctx) == (5, 0)  # the thesis's rule would take the nearest
    assert hungarian_exclusion(ctx) == (31, 0)


def test_an_announced_goal_counts_for_exactly_goal_ttl_ticks():
    """docs/exploration.md, rule 3: a neighbour's goal counts "for at most two planning
    periods" (``goal_ttl`` = 40 ticks): heard at tick 10, it still closes its zone at tick
    50 and no longer at tick 51."""
    cfg = config()
    assert cfg.goal_ttl == 2 * cfg.plan_period == 40
    robots, _, _ = team([(10, 10), (14, 10)], 1.0, cfg)
    b = robots[0].belief
    b.hear_goal(1, (30, 12), 5.0, 10)
    assert b.team_goals(50, cfg.goal_ttl) == {1: (30, 12)}
    assert b.team_goals(51, cfg.goal_ttl) == {}


def test_an_unknown_cell_half_of_whose_known_rim_is_free_is_a_pocket():
    """Module docstring: a pocket's known surroundings are "at least half ... free (an
    opening, not an obstacle's inside)". One unknown cell at (5, 5): its four side cells
    free, its four corner cells occupied, exactly half free: a pocket, so the frontier cell
    beside it, (4, 5), borders a pocket; with one more corner free it still does, and with
    one side cell occupied (3 of 8 free) it does not."""
    def frontier_beside_a_pocket(lo):
        fr = Frontiers(np.array([5]), np.array([4]), np.array([0]), np.array([1]), 0)
        ctx = GoalContext(me=0, pos=(0, 0), frontiers=fr, eligible=np.ones(1, bool),
                          dist=np.array([4]), laser_cells=3.0,
                          derived=lambda key, make: make(lo))
        return bool(pocket_cells(ctx, np.array([0]))[0])

    lo = np.full((11, 11), -1.0, dtype=np.float32)  # known free
    lo[5, 5] = 0.0  # unknown
    for dx, dy in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
        lo[5 + dy, 5 + dx] = 1.0  # occupied corners
    assert frontier_beside_a_pocket(lo)
    lo[6, 6] = -1.0
    assert frontier_beside_a_pocket(lo)
    lo[6, 6] = 1.0
    lo[4, 5] = 1.0
    assert not frontier_beside_a_pocket(lo)


@pytest.mark.parametrize("strategy", ["greedy", "hungarian"])
def test_a_robot_standing_on_a_frontier_cell_does_not_take_its_own_cell(strategy):
    """A goal is a frontier cell the robot must walk to: its own cell is never one, whether
    the planner searches the whole field (``hungarian``: reachable means more than 0 steps)
    or only up to the nearest candidate (``greedy``, which leaves the cell out by name).
    Known free block x 30..60, y 10..28 of an unknown map; the robot stands on the block's
    east edge at (60, 24), the middle of its laser-sized chunk (y 20..28) of that frontier,
    so the chunk's representative would be its own cell."""
    robots, _, _ = team([(60, 24)], 1.0, config(strategy=strategy))
    r = robots[0]
    lo = r.belief.grid.logodds
    lo[10:29, 30:61] = -1.0
    r.plan(0)
    assert r.goal is not None and r.goal != (60, 24)
