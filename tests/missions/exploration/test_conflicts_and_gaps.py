"""Message rules a mutation run found guarded only by the fingerprints: when two goals
conflict and who wins."""

from __future__ import annotations

import numpy as np

from swarmex.missions.exploration.messages import ChangeGoal, Goal
from swarmex.missions.exploration.robot import ExplorerRobot
from tests.missions.exploration.helpers import config

MY_GOAL = (20, 10)


def _robot(rid: int = 1, remaining: int = 5, cfg=None) -> ExplorerRobot:
    """A greedy-exclusion robot at (10, 10) heading for MY_GOAL with ``remaining`` steps."""
    r = ExplorerRobot(rid, cfg or config(), (10, 10))
    r.goal = MY_GOAL
    r.path = np.zeros((remaining, 2), dtype=np.int64)
    r.path_i = 0
    return r


def _hear_goal(r: ExplorerRobot, src: int, goal, priority: float):
    return r.on_message(src, Goal(src, goal, priority, 12, 10), 0)


def test_goals_at_exactly_the_laser_range_conflict_and_goals_beyond_it_do_not():
    """docs/exploration.md, choice 4: goals "in the same area" = within the laser range
    (10 cells here). A neighbour's goal exactly 10 cells from this robot's (straight, and
    6² + 8² = 10²) is a conflict, and the neighbour, 3 steps from its goal against this
    robot's 5, wins it: this robot re-plans. 10.05 cells away there is no conflict."""
    assert config().laser_cells == 10.0
    for goal in ((30, 10), (26, 18)):
        r = _robot()
        assert _hear_goal(r, 0, goal, 3.0) == []
        assert r.stats.conflicts == 1, goal
        assert r.beaten_by == {0} and r.request == "conflict", goal
    r = _robot()
    assert _hear_goal(r, 0, (21, 0), 3.0) == []  # math.dist((21, 0), (20, 10)) = 10.05
    assert r.stats.conflicts == 0 and r.beaten_by == set() and r.request is None


def test_a_priority_tie_goes_to_the_lower_id():
    """docs/exploration.md, choice 4: priority = path length, shorter is higher, "ties to the
    lower id". Robot 1, 5 steps from its goal, hears an equal priority (5 steps): from robot
    0 it loses (re-plans, sends nothing); from robot 2 it wins and sends CHANGE_GOAL to 2."""
    r = _robot(rid=1)
    assert _hear_goal(r, 0, (22, 10), 5.0) == []
    assert r.beaten_by == {0} and r.request == "conflict"
    assert r.stats.change_goals_sent == 0
    r = _robot(rid=1)
    out = _hear_goal(r, 2, (22, 10), 5.0)
    assert [(dst, type(m)) for dst, m in out] == [(2, ChangeGoal)]
    assert out[0][1].goal == MY_GOAL and out[0][1].priority == 5.0
    assert r.beaten_by == set() and r.request is None
    assert r.stats.change_goals_sent == 1
    # and a shorter path wins whatever the ids: 4 steps from robot 2 beat robot 1's 5
    r = _robot(rid=1)
    assert _hear_goal(r, 2, (22, 10), 4.0) == []
    assert r.beaten_by == {2}

