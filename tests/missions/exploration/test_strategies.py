"""Goal choice: exclusion zones and their fallback, priorities, and the stronger strategies."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.exploration.messages import ChangeGoal, Goal
from swarmex.missions.exploration.strategies import (
    get_strategy,
    greedy,
    greedy_exclusion,
    hungarian,
    hungarian_exclusion,
    minpos,
    pocket_exclusion,
    pocket_regions,
    utility,
)
from swarmex.sensing.frontiers import Frontiers
from tests.missions.exploration.helpers import config, team
from tests.missions.exploration.helpers import goal_context as context

CELLS = [(5, 0), (30, 0), (60, 0)]


def test_greedy_takes_the_nearest_and_keeps_its_goal_on_ties():
    assert greedy(context(CELLS, [5, 30, 60])) == (5, 0)
    assert greedy(context(CELLS, [30, 30, 60], current_goal=(30, 0))) == (30, 0)
    assert greedy(context(CELLS, [30, 30, 60])) == (5, 0)


def test_exclusion_zone_skips_cells_near_a_teammates_goal():
    ctx = context(CELLS, [5, 30, 60], team_goals={7: (8, 0)})
    assert greedy_exclusion(ctx) == (30, 0)  # (5,0) is 3 cells from 7's goal (< laser 10)


def test_exclusion_falls_back_when_every_frontier_is_excluded():
    ctx = context(CELLS, [5, 30, 60], team_goals={7: (8, 0), 8: (31, 0), 9: (55, 0)})
    assert greedy_exclusion(ctx) == (5, 0)  # "prefers" a free zone; none left: nearest


def test_minpos_leaves_a_frontier_to_a_closer_teammate():
    # a teammate stands right at (5,0): its rank there is 1 for us, 0 elsewhere
    fields = {(6, 0): np.full((1, 100), 99)}
    fields[(6, 0)][0, 5] = 1
    ctx = context(CELLS, [5, 30, 60], team_pos={1: (6, 0)}, field_from=lambda c: fields[c])
    assert minpos(ctx) == (30, 0)
    assert hungarian(ctx) == (30, 0)
    assert utility(ctx) == (30, 0)


def test_assignment_strategies_alone_act_like_greedy():
    for f in (minpos, hungarian, utility):
        assert f(context(CELLS, [40, 30, 60])) == (30, 0)
        assert f(context(CELLS, [-1, -1, -1])) is None


def _rival_fields(steps_by_rival):
    """Distance fields (1 × 100 cells) in which each rival is ``steps`` from CELLS."""
    fields = {}
    for pos, steps in steps_by_rival.items():
        f = np.full((1, 100), 99)
        for (x, _), d in zip(CELLS, steps, strict=True):
            f[0, x] = d
        fields[pos] = f
    return fields


def test_hungarian_exclusion_assigns_with_two_rivals_in_view():
    # rival 1 stands by (5,0), rival 2 by (60,0): the minimum-sum assignment sends this robot
    # to (30,0) (30 + 1 + 2 steps) where greedy-exclusion would take the nearest, (5,0)
    fields = _rival_fields({(6, 0): [1, 40, 70], (58, 0): [50, 25, 2]})
    two = {1: (6, 0), 2: (58, 0)}
    ctx = context(CELLS, [5, 30, 60], team_pos=two, field_from=lambda c: fields[c])
    assert greedy_exclusion(ctx) == (5, 0)
    assert hungarian_exclusion(ctx) == (30, 0)
    # one rival in view: nothing to balance, the thesis's rule
    one = context(CELLS, [5, 30, 60], team_pos={1: (6, 0)}, field_from=lambda c: fields[c])
    assert hungarian_exclusion(one) == (5, 0)
    # an announced goal's zone covers (30,0): the assignment runs over the free targets only
    zoned = context(CELLS, [5, 30, 60], team_pos=two, team_goals={7: (31, 0)},
                    field_from=lambda c: fields[c])
    assert hungarian_exclusion(zoned) == (5, 0)
    assert get_strategy("hungarian-exclusion").exclusion  # it announces goals (GOAL messages)


def _long_frontier_and_a_pocket(pocket_steps):
    """Region 0: a frontier 21 cells long (x = 5..25, wider than the 10-cell laser range);
    region 1: one cell at (30, 5), ``pocket_steps`` from the robot at (0, 0)."""
    xs = np.array([*range(5, 26), 30])
    ys = np.array([0] * 21 + [5])
    fr = Frontiers(ys, xs, np.array([0] * 21 + [1]), np.array([21, 1]), 0)
    from swarmex.missions.exploration.strategies import GoalContext

    dist = np.array([*range(5, 26), pocket_steps])
    return GoalContext(me=0, pos=(0, 0), frontiers=fr, eligible=np.ones(22, bool), dist=dist,
                       laser_cells=10.0)


def test_pocket_exclusion_clears_a_near_pocket_before_the_long_frontier():
    assert list(pocket_regions(_long_frontier_and_a_pocket(9).frontiers, 10.0)) == [False, True]
    ctx = _long_frontier_and_a_pocket(9)  # half of 9 steps beats the frontier's 5
    assert greedy_exclusion(ctx) == (5, 0)
    assert pocket_exclusion(ctx) == (30, 5)
    far = _long_frontier_and_a_pocket(12)  # 6 > 5: the nearest cell, as greedy-exclusion
    assert pocket_exclusion(far) == (5, 0)
    # the pocket inside an announced goal's zone is excluded like any candidate
    zoned = _long_frontier_and_a_pocket(9)
    zoned.team_goals = {3: (31, 5)}
    assert pocket_exclusion(zoned) == (5, 0)
    st = get_strategy("pocket-exclusion")
    assert st.exclusion and st.priorities and st.home_when_done


def test_unknown_strategy_is_an_input_error():
    from swarmex.errors import InputError

    with pytest.raises(InputError, match="strategy"):
        get_strategy("random")


def test_priority_conflict_lower_priority_replans_higher_sends_change_goal():
    robots, net, wire = team([(100, 20), (110, 20)], range_m=5.0, cfg=config())
    me = robots[0]
    me.goal = (150, 20)
    me.path = np.array([[101 + i, 20] for i in range(50)])  # 50 steps to go
    # a neighbour announces a goal 3 cells from ours, 10 steps away: it has priority
    assert me.on_message(1, Goal(1, (153, 20), 10.0, 110, 20), t=5) == []
    assert me.request == "conflict"
    me.request = None
    # a neighbour 80 steps from a goal near ours: we keep ours and tell it to change
    out = me.on_message(1, Goal(1, (147, 20), 80.0, 110, 20), t=6)
    assert len(out) == 1 and out[0][0] == 1 and isinstance(out[0][1], ChangeGoal)
    assert me.request is None and me.stats.change_goals_sent == 1
    # equal priorities: the lower id wins
    out = me.on_message(1, Goal(1, (147, 20), 50.0, 110, 20), t=7)
    assert isinstance(out[0][1], ChangeGoal)
    # a far goal is no conflict; CHANGE_GOAL forces a re-plan
    assert me.on_message(1, Goal(1, (300, 20), 1.0, 110, 20), t=8) == []
    assert me.request is None
    me.on_message(1, ChangeGoal(1, (150, 22), 3.0), t=9)
    assert me.request == "change_goal"


def test_zone_test_through_the_sorted_goals_matches_the_pass_per_goal():
    """Many announced goals are tried in a window of columns (goals sorted by column); the
    answer must be the brute-force one, boundary cells (squared distance exactly r²)
    included."""
    from swarmex.missions.exploration.strategies import ZONE_TREE_FROM, _within

    rng = np.random.default_rng(5)
    for trial in range(20):
        cells = [tuple(int(v) for v in c) for c in rng.integers(0, 80, (300, 2))]
        n_goals = int(rng.integers(ZONE_TREE_FROM, 60))
        pts = rng.integers(0, 80, (n_goals, 2))
        goals = {i: (int(g[0]), int(g[1])) for i, g in enumerate(pts)}
        goals[-1] = (cells[0][0] + 6, cells[0][1] + 8)  # exactly 10 cells: on the boundary
        ctx = context(cells, list(range(len(cells))))
        idx = np.arange(len(cells))
        xs, ys = ctx.frontiers.xs, ctx.frontiers.ys
        brute = np.array([any((x - gx) ** 2 + (y - gy) ** 2 <= 100.0
                              for gx, gy in goals.values())
                          for x, y in zip(xs, ys, strict=True)])
        got = _within(ctx, idx, goals)
        assert got[0] and np.array_equal(got, brute), trial
