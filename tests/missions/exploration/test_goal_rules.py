"""Goal rules a mutation run found unpinned: where hungarian-exclusion heads inside its
assigned target's zone, and how long an announced goal keeps its zone closed."""

from __future__ import annotations

import numpy as np

from swarmex.missions.exploration.strategies import (
    GoalContext,
    greedy_exclusion,
    hungarian_exclusion,
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
