"""Goal choice: exclusion zones and their fallback, priorities, and the stronger strategies."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.exploration.messages import ChangeGoal, Goal
from swarmex.missions.exploration.strategies import (
    ALONE_TICKS,
    GoalContext,
    adaptive_exclusion,
    excluded,
    get_strategy,
    greedy,
    greedy_exclusion,
    hungarian,
    hungarian_exclusion,
    minpos,
    pocket_cells,
    pocket_exclusion,
    utility,
)
from swarmex.sensing.frontiers import Frontiers
from tests.missions.exploration.helpers import config, heartbeats, scan, team
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


def _wall_sliver_and_open_field():
    """A 20 x 60 map: known free rows 0..15 except a 2-cell unknown sliver at the left wall
    (x 0..1, rows 0..3) and everything below row 15 unknown (the open field). Frontier
    cells: (2, 0..3) beside the sliver, row 15 beside the field. The robot is at (30, 8)."""
    h, w = 40, 60
    lo = np.zeros((h, w), dtype=np.float32)
    lo[:16, :] = -1.0
    lo[0:4, 0:2] = 0.0
    xs = np.array([2, 2, 2, 2, *range(w)])
    ys = np.array([0, 1, 2, 3, *([15] * w)])
    fr = Frontiers(ys, xs, np.array([0] * 4 + [1] * w), np.array([4, w]), 0)
    # steps from the robot at (30, 8): Chebyshev on the open known rows
    dist = np.maximum(np.abs(xs - 30), np.abs(ys - 8))

    def derived(key, make):
        return make(lo)

    return GoalContext(me=0, pos=(30, 8), frontiers=fr, eligible=np.ones(xs.size, bool),
                       dist=dist, laser_cells=10.0, derived=derived)


def test_pockets_are_small_unknown_components_and_come_first():
    ctx = _wall_sliver_and_open_field()
    idx = np.arange(ctx.frontiers.n_cells)
    pocket = pocket_cells(ctx, idx)
    assert pocket[:4].all() and not pocket[4:].any()  # the sliver: 8 cells; the field: 1440
    # greedy-exclusion takes the field (7 steps); the sliver's 28 steps count as 14, so it is
    # still the field; nearer (robot at (15, 8): sliver 13 -> 6.5, field 7) the sliver
    assert greedy_exclusion(ctx) == (23, 15)  # 7 steps from x = 23 to 37: (y, x) order
    assert pocket_exclusion(ctx) == (23, 15)
    near = _wall_sliver_and_open_field()
    near.pos = (15, 8)
    near.dist = np.maximum(np.abs(near.frontiers.xs - 15), np.abs(near.frontiers.ys - 8))
    assert greedy_exclusion(near) == (8, 15)
    assert pocket_exclusion(near) == (2, 0)  # ties: (y, x) order
    zoned = _wall_sliver_and_open_field()
    zoned.pos, zoned.dist = near.pos, near.dist
    zoned.team_goals = {3: (2, 2)}  # another robot's goal covers the sliver: excluded as ever
    assert pocket_exclusion(zoned) == (8, 15)


def test_an_obstacle_inside_is_not_a_pocket():
    """An unknown block whose known rim is mostly occupied (a shelf whose faces the laser
    hit, seen through one free cell) is never a pocket: no visit clears it."""
    ctx = _wall_sliver_and_open_field()
    lo = np.zeros((40, 60), dtype=np.float32)
    lo[:16, :] = -1.0
    lo[0:4, 0:2] = 0.0
    lo[0:5, 2] = 1.0  # the sliver's rim: its right side and the cells below it occupied
    lo[4, 0:2] = 1.0
    lo[3, 2] = -1.0  # one free cell (x 2, y 3) still touches the unknown block
    ctx.derived = lambda key, make: make(lo)
    idx = np.arange(ctx.frontiers.n_cells)
    pocket = pocket_cells(ctx, idx)
    assert not pocket[:4].any() and not pocket[4:].any()
    lo[0:3, 2] = -1.0  # most of the rim free again: an opening, a pocket
    assert pocket_cells(ctx, idx)[:4].all()


def test_adaptive_exclusion_rendezvous_and_team_size():
    ctx = _wall_sliver_and_open_field()
    ctx.start = (30, 2)
    ctx.field_from = lambda c: np.zeros((40, 60), dtype=np.int32) + 6  # start reachable
    ctx.alone = ALONE_TICKS - 1
    assert adaptive_exclusion(ctx) == pocket_exclusion(ctx)  # a small team: the pocket rule
    ctx.alone = ALONE_TICKS
    assert adaptive_exclusion(ctx) == (30, 2)  # alone too long: back to the start
    ctx.field_from = lambda c: np.full((40, 60), -1, dtype=np.int32)  # no known way back
    assert adaptive_exclusion(ctx) == pocket_exclusion(ctx)
    finished = _wall_sliver_and_open_field()
    finished.eligible[:] = False
    finished.alone, finished.start = ALONE_TICKS, (30, 2)
    assert adaptive_exclusion(finished) is None  # a finished robot stays finished
    # a team of 6 or more with two rivals in view: hungarian-exclusion's assignment
    fields = _rival_fields({(6, 0): [1, 40, 70], (58, 0): [50, 25, 2]})
    two = {1: (6, 0), 2: (58, 0)}
    big = context(CELLS, [5, 30, 60], team_pos=two, field_from=lambda c: fields[c])
    big.team_size = 6
    assert adaptive_exclusion(big) == hungarian_exclusion(big) == (30, 0)
    big.team_size = 5
    assert adaptive_exclusion(big) == (5, 0)
    st = get_strategy("adaptive-exclusion")
    assert st.exclusion and st.priorities and st.needs_rivals


def test_robot_counts_its_team_and_the_ticks_alone():
    robots, net, wire = team([(10, 10), (14, 10), (18, 10)], 1.0)
    for r in robots:
        wire.send(r.id, scan(r))
    heartbeats(robots, wire, 0)
    r0 = robots[0]
    ctx = GoalContext(me=0, pos=r0.pos, frontiers=Frontiers(*[np.zeros(0, int)] * 4, 0),
                      eligible=np.zeros(0, bool), dist=np.zeros(0, int), laser_cells=10.0)
    r0._what_it_knows(ctx, 0)
    assert ctx.team_size == 3 and ctx.start == (10, 10) and ctx.alone == 0
    r0.belief.hear_position(1, (14, 10), 5)  # its last contact, at tick 5
    r0.belief.pos = (12, 10)  # it has left its start
    r0._what_it_knows(ctx, 200)
    assert ctx.alone == 195
    r0.belief.pos = (10, 10)  # back at the start: no second rendezvous for that contact
    r0._what_it_knows(ctx, 260)
    assert ctx.alone == 0
    r0.belief.hear_position(2, (18, 10), 300)  # a new contact
    r0.belief.pos = (12, 10)
    r0._what_it_knows(ctx, 320)
    assert ctx.alone == 20


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


def test_adaptive_exclusion_replans_when_its_goal_region_vanishes():
    # a robot re-plans at once ("seen") when no cell of its goal's frontier region is a
    # frontier cell any more, instead of walking on to the goal or waiting for its timer
    robots, net, wire = team([(40, 20)], 1.0, config(strategy="adaptive-exclusion"))
    r = robots[0]
    wire.send(0, scan(r))
    r.maybe_plan(0)
    assert r.goal is not None and r.goal_region is not None
    ys, xs = r.goal_region
    assert r._any_frontier(ys, xs)  # the ring of the scan borders the unknown
    assert not r._any_frontier(np.array([20]), np.array([40]))  # the robot's own cell
    plans = r.stats.plans
    r._any_frontier = lambda ys, xs: False  # as if a scan had seen past the whole ring
    r.maybe_plan(3)
    assert r.stats.plans == plans + 1 and r.stats.reasons.get("seen") == 1
    greedy_robot = team([(40, 20)], 1.0, config(strategy="greedy-exclusion"))[0][0]
    greedy_robot.observe(np.full(len(greedy_robot.cfg.angles), greedy_robot.cfg.laser_cells), 0)
    greedy_robot.maybe_plan(0)
    assert greedy_robot.goal_region is None  # the other strategies keep the thesis's timing


# ------------------------------------------- rules found unpinned by the missions mutation run
def test_a_cell_at_exactly_the_laser_range_of_a_teammates_goal_is_excluded():
    """Module docstring: greedy-exclusion never takes "a cell within the laser range of a
    goal a neighbour has announced" — within, so a cell at exactly the range (10 cells) is
    in the zone: (5, 0) is 10 cells from (15, 0), and so is (5, 0) from (11, 8) (6² + 8²
    = 10²); the nearest free cell is then (30, 0). One cell further is outside."""
    for goal in ((15, 0), (11, 8)):
        ctx = context(CELLS, [5, 30, 60], team_goals={7: goal})
        assert excluded(ctx, np.arange(3)).tolist() == [True, False, False], goal
        assert greedy_exclusion(ctx) == (30, 0), goal
    ctx = context(CELLS, [5, 30, 60], team_goals={7: (16, 0)})
    assert excluded(ctx, np.arange(3)).tolist() == [False, False, False]
    assert greedy_exclusion(ctx) == (5, 0)


def _fields_at(pos_steps):
    """``field_from`` for rivals at the given cells, each ``steps`` (per CELLS) away."""
    fields = _rival_fields(pos_steps)
    return {i + 1: p for i, p in enumerate(pos_steps)}, (lambda c: fields[c])


def test_minpos_rank_counts_only_strictly_nearer_teammates():
    """Bautin et al.: a target's rank is "the number of neighbours nearer to it (by path)
    than the robot". A teammate exactly as far from (5, 0) as this robot (5 steps) is not
    nearer, so every target has rank 0 and the robot takes the nearest, (5, 0); one step
    nearer and (5, 0) has rank 1, so the robot takes (30, 0)."""
    pos, field_from = _fields_at({(9, 0): [5, 99, 99]})
    assert minpos(context(CELLS, [5, 30, 60], team_pos=pos, field_from=field_from)) == (5, 0)
    pos, field_from = _fields_at({(9, 0): [4, 99, 99]})
    assert minpos(context(CELLS, [5, 30, 60], team_pos=pos, field_from=field_from)) == (30, 0)


def test_minpos_takes_the_lowest_rank_first_then_the_nearest():
    """MinPos orders targets by rank, then by this robot's distance. Two teammates are
    nearer to (5, 0) (rank 2), one to (30, 0) (rank 1) and none to (60, 0) (rank 0): the
    robot takes the farthest target, (60, 0), although (5, 0) is 12 times nearer. With the
    robot 60 steps from (30, 0) and 30 from (60, 0), and a teammate 25 steps from (60, 0),
    the ranks are (2, 1, 1) and it takes the nearer of the rank-1 targets, (60, 0) (the
    later of the two in target order, so the distance, not the order, decides)."""
    pos, field_from = _fields_at({(6, 0): [1, 20, 99], (7, 0): [2, 99, 99]})
    ctx = context(CELLS, [5, 30, 60], team_pos=pos, field_from=field_from)
    assert minpos(ctx) == (60, 0)
    pos, field_from = _fields_at({(6, 0): [1, 20, 99], (7, 0): [2, 99, 25]})
    ctx = context(CELLS, [5, 60, 30], team_pos=pos, field_from=field_from)
    assert minpos(ctx) == (60, 0)
    ctx = context(CELLS, [5, 30, 60], team_pos=pos, field_from=field_from)
    assert minpos(ctx) == (30, 0)  # ranks (2, 1, 1) again; the nearer rank-1 is (30, 0)


def test_hungarian_repeats_targets_so_every_robot_is_assigned_when_robots_outnumber_them():
    """Module docstring: "targets are repeated when robots outnumber them". Three robots,
    two targets: each rival stands by one target (1 step), this robot is 50 steps from
    (5, 0) and 40 from (30, 0). With each target available twice, the minimum sum (brute
    force over this robot's choice: 1 + 1 + 40 = 42 against 1 + 1 + 50 = 52) gives this
    robot (30, 0); without repeats only two robots would be assigned, and not this one."""
    cells = [(5, 0), (30, 0)]
    fields = {(6, 0): np.full((1, 100), 99), (29, 0): np.full((1, 100), 99)}
    fields[(6, 0)][0, 5] = 1
    fields[(29, 0)][0, 30] = 1
    ctx = context(cells, [50, 40], team_pos={1: (6, 0), 2: (29, 0)},
                  field_from=lambda c: fields[c])
    assert hungarian(ctx) == (30, 0)
    ctx = context(cells, [40, 50], team_pos={1: (6, 0), 2: (29, 0)},
                  field_from=lambda c: fields[c])
    assert hungarian(ctx) == (5, 0)
