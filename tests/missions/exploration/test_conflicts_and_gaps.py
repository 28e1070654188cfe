"""Message rules a mutation run found guarded only by the fingerprints: when two goals
conflict and who wins, how often a robot asks the origin of missing scans for them, and how
the archive tells a scan that leaves a hole from one that does not."""

from __future__ import annotations

import dataclasses

import numpy as np

from swarmex.missions.exploration.belief import ADDED, ADDED_GAP, HELD, ScanArchive
from swarmex.missions.exploration.messages import ChangeGoal, Goal, ScanRecord
from swarmex.missions.exploration.robot import ExplorerRobot
from swarmex.sensing.occupancy import rasterise
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


def _record(origin: int, seq: int) -> ScanRecord:
    cfg = config()
    local = rasterise(30, 20, np.full(len(cfg.angles), 3.0), cfg.angles, cfg.laser_cells,
                      cfg.shape)
    return ScanRecord(origin, seq, 30, 20, local)


def test_at_most_one_gap_request_per_origin_per_unicast_lifetime_inclusive():
    """Module docstring: "At most one such request per origin per unicast lifetime" (100
    ticks). Robot 0 holds none of robot 1's scans 0 and 1: scan 2 at tick 0 leaves a hole,
    and it asks robot 1; scan 3 at tick 100 is still within the lifetime of that request,
    so no second one; scan 4 at tick 101 is past it, and it asks again."""
    cfg = dataclasses.replace(config(), aodv=True)
    assert cfg.unicast_lifetime == 100
    r = ExplorerRobot(0, cfg, (10, 10))
    r.accept_scan(_record(1, 2), 0)
    assert r.stats.gap_requests == 1 and r.asked == {1: 0}
    r.accept_scan(_record(1, 3), 100)
    assert r.stats.gap_requests == 1 and r.asked == {1: 0}
    r.accept_scan(_record(1, 4), 101)
    assert r.stats.gap_requests == 2 and r.asked == {1: 101}


def test_admit_reports_a_hole_only_while_some_lower_seq_is_missing():
    """ScanArchive.admit: ADDED_GAP when "some seq of that origin below its highest is
    missing" (seqs count from 0), else ADDED; HELD for a key already held."""
    arch = ScanArchive()
    assert arch.admit(_record(4, 0)) == ADDED
    assert arch.admit(_record(4, 1)) == ADDED  # holds 0, 1
    assert arch.admit(_record(4, 1)) == HELD
    assert arch.admit(_record(4, 3)) == ADDED_GAP  # 2 missing
    assert arch.admit(_record(4, 2)) == ADDED  # filled: 0 … 3
    assert arch.admit(_record(4, 4)) == ADDED
    assert arch.admit(_record(5, 1)) == ADDED_GAP  # a new origin from seq 1: 0 missing
    assert arch.admit(_record(5, 2)) == ADDED_GAP
    assert arch.admit(_record(5, 0)) == ADDED
    assert not arch.has_gap(4) and not arch.has_gap(5)
