"""The independent replay finds only legal moves, no shared non-nest cell, only adjacent swaps."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from swarmex.missions.foraging import replay, run_forage, to_record
from swarmex.missions.foraging.resolve import resolve

RUNS = [
    ("strips", 16, 4, (3, 12), "relay-food"),
    ("strips", 16, 8, (15, 1), "end-to-end"),
    ("zigzag", 16, 4, (2, 9), "relay-path"),
    ("zigzag", 16, 16, (9, 9), "relay-food"),
    ("hilbert", 16, 16, (1, 1), "end-to-end"),
    ("sectors", 16, 8, (12, 3), "relay-food"),
    ("sectors", 24, 16, (5, 20), "relay-path"),
    ("spiral", 16, 8, (10, 8), "relay-food"),
    ("spiral", 16, 16, (0, 15), "end-to-end"),
    ("modified-zigzag", 16, 8, (14, 2), "relay-food"),
    ("rings", 16, 16, (7, 7), "relay-path"),
    ("loop-strips", 16, 4, (12, 13), "relay-food"),
    ("loop-strips", 32, 16, (2, 30), "end-to-end"),
    ("sector-loop", 16, 8, (9, 10), "relay-food"),
    ("sector-loop", 32, 16, (30, 1), "relay-path"),
    ("sector-loop", 32, 8, (3, 28), "end-to-end"),
    ("comb", 16, 4, (3, 12), "relay-food"),
    ("comb", 32, 8, (30, 2), "end-to-end"),
    ("comb", 32, 4, (17, 20), "relay-path"),
]


def record_of(name, g, n, food, transport, units=12):
    run = run_forage(name, g, n, food, units, transport)
    return run, to_record(run, 0, {}).to_dict()


@pytest.mark.parametrize(("name", "g", "n", "food", "transport"), RUNS)
def test_replay_accepts_every_run(name, g, n, food, transport):
    run, rec = record_of(name, g, n, food, transport)
    assert rec["complete"] is True
    assert replay(rec) == []
    m = rec["metrics"]
    parts = ("exploration_time", "communication_time", "comm_transport_overlap")
    assert sum(m[k] for k in parts) + m["transport_time"] == rec["makespan"]
    assert m["food_delivered"] == 12


def test_replay_rejects_tampered_records():
    _, rec = record_of("strips", 16, 4, (3, 12), "relay-food")
    bad = copy.deepcopy(rec)
    bad["agents"][0]["trajectory"][5][1] += 2  # a jump
    assert any("illegal move" in e for e in replay(bad))
    bad = copy.deepcopy(rec)
    t = len(bad["agents"][0]["trajectory"]) - 1
    bad["agents"][1]["trajectory"][t] = list(bad["agents"][0]["trajectory"][t])
    x, y = bad["agents"][0]["trajectory"][t][1:]
    if (x, y) != (8, 8):
        assert any("share cell" in e for e in replay(bad))
    bad = copy.deepcopy(rec)
    bad["complete"] = False
    assert any("complete" in e for e in replay(bad))


def test_swaps_between_adjacent_robots_are_legal():
    cur = [(3, 3), (4, 3)]
    new = resolve(cur, [[(4, 3), (3, 3)], [(3, 3), (4, 3)]], [0, 1], (0, 0))
    assert new == [(4, 3), (3, 3)]


def test_two_robots_for_one_cell_larger_xy_wins():
    cur = [(3, 3), (5, 3)]
    order = [1, 0]  # (5,3) > (3,3) lexicographically
    new = resolve(cur, [[(4, 3), (3, 3)], [(4, 3), (5, 3)]], order, (0, 0))
    assert new == [(3, 3), (4, 3)]


def test_nest_holds_many():
    cur = [(4, 4), (4, 4), (4, 5)]
    new = resolve(cur, [[(4, 4)], [(4, 4)], [(4, 4), (4, 5)]], [2, 0, 1], (4, 4))
    assert new == [(4, 4)] * 3


def test_compiled_tail_matches_python_loop():
    from swarmex.missions.foraging.sim import run_mission
    from swarmex.missions.foraging.timed import timed_plan

    for name, g, n, food, transport in RUNS[::3]:
        T = timed_plan(name, g, n)
        a = run_mission(T, food, 15, transport, fast=False)
        b = run_mission(T, food, 15, transport, fast=True)
        assert a.makespan == b.makespan
        assert np.array_equal(a.positions, b.positions)
        assert a.jobs == b.jobs
