"""The transport floors of issue 17.3 (:mod:`swarmex.missions.foraging.floor`): start states,
hand-worked transport times, and the proven floor against the searched start states and
against real runs of every kind of pattern."""

from __future__ import annotations

import pytest

import swarmex
from swarmex.missions.foraging.floor import (
    Start,
    candidates,
    least_transport,
    proven_floor,
    transport_start,
    transport_time,
)
from swarmex.missions.foraging.grid import manhattan, nest_of
from swarmex.missions.foraging.sim import IDLE, JOIN, RELAY, TRANSPORT


def test_start_state_has_everyone_transporting():
    # 8×8, nest (4, 4), food (7, 4): path L0 … L3 along the nest's row
    m = transport_start(8, (7, 4), 4, 5, Start((3, 1), joining=1))
    assert m.pos[:2] == [(7, 4), (5, 4)]
    assert manhattan(m.pos[2], (7, 4)) == 1 and m.pos[2] not in m.pos[:2]
    assert m.pos[3] == nest_of(8)
    assert all(mode == TRANSPORT for mode in m.mode) and all(m.informed)
    assert m.tmode == [RELAY, RELAY, JOIN, IDLE]
    assert m.pidx[:2] == [3, 1] and m.join_at[2] == 3
    assert m.t == 0 and m.units == 5 and not any(m.carrying)


@pytest.mark.parametrize("bad", [Start((2, 1)), Start((3, 3)), Start((3, 4)), Start((3,), 4)])
def test_start_state_is_checked(bad):
    # the finder must be on the food, cells distinct on the path, at most n robots
    with pytest.raises(ValueError):
        transport_start(8, (7, 4), 4, 5, bad)


def test_two_robots_worked_by_hand():
    # 8×8, food 3 East of the nest, A on the food (L3), B on L2, k = 2.
    # t0: A picks unit 1. Round 1: A (carrying) wants L2, B (empty) wants L3: they swap,
    # so no hand-over. t1: B picks unit 2 on the food. A walks L1, L0 (drops at t3); B walks
    # L2, L1, and swaps with A (who leaves the nest empty) into the nest: drop at t4.
    m = transport_start(8, (7, 4), 2, 2, Start((3, 2)))
    m.run(record=True, fast=False)
    assert m.t == 4
    assert m.jobs == [[(0, 7, 4, "pickup"), (3, 4, 4, "drop")],
                      [(1, 7, 4, "pickup"), (4, 4, 4, "drop")]]
    assert transport_time(8, (7, 4), 2, 2, Start((3, 2))) == 4  # the compiled tail agrees
    assert proven_floor(3, 2, 2) == 3 <= 4


@pytest.mark.parametrize("d", [1, 2, 3, 5])
@pytest.mark.parametrize("k", [1, 2, 7])
def test_one_robot_is_the_proven_floor(d, k):
    # one robot on the food: k trips of d there and d back, less the last walk back
    assert transport_time(16, (8 + d, 8), 1, k, Start((d,))) == (2 * k - 1) * d
    assert proven_floor(d, 1, k) == (2 * k - 1) * d
    assert least_transport(16, (8 + d, 8), 1, k)[0] == (2 * k - 1) * d


def test_proven_floor_values():
    # flow bound ⌊d/2⌋ + k near the nest, work bound 2k(d − n + 1)/n − d far from it
    assert proven_floor(13, 16, 100) == 6 + 100
    assert proven_floor(2, 2, 1) == 2  # pick at t0, L1 at t1 (no hand-over from L1), nest t2
    assert proven_floor(110, 16, 100) == 1078  # ⌈200·95/16 − 110⌉
    assert proven_floor(60, 8, 100) == 1265


@pytest.mark.parametrize("food", [(9, 8), (12, 5), (2, 3), (15, 15), (8, 1)])
@pytest.mark.parametrize("n", [2, 3, 5])
def test_searched_states_never_beat_the_proven_floor(food, n):
    g, k = 16, 12
    d = manhattan(nest_of(g), food)
    floor = proven_floor(d, n, k)
    for start in candidates(d, n):
        t = transport_time(g, food, n, k, start)
        assert t is None or t >= floor
    q, start = least_transport(g, food, n, k, budget=20)
    assert floor <= q == transport_time(g, food, n, k, start)


@pytest.mark.parametrize("algorithm,n", [("strips", 4), ("sectors", 8), ("spiral", 4),
                                         ("zigzag", 4), ("loop-strips", 4)])
def test_real_runs_never_beat_the_proven_floor(algorithm, n):
    g, k = 16, 20
    for food in [(9, 8), (14, 2), (3, 12), (0, 0), (8, 3), (11, 13)]:
        rec = swarmex.run("foraging", grid=g, agents=n, algorithm=algorithm, food=food,
                          food_units=k, transport="relay-food")
        q = rec.metrics["total_time"] - rec.metrics["exploration_time"]
        assert q >= proven_floor(manhattan(nest_of(g), food), n, k)


def test_joining_robots_on_a_ray():
    # N ray, 2 apart, from 2 cells off the food; a ray off the grid is no start state
    m = transport_start(16, (11, 8), 5, 10, Start((3, 2), 3, (1, 2)))
    assert m.pos == [(11, 8), (10, 8), (11, 6), (11, 4), (11, 2)]
    assert m.tmode == [RELAY, RELAY, JOIN, JOIN, JOIN]
    assert transport_time(16, (11, 8), 5, 10, Start((3, 2), 3, (0, 2))) is None


def test_short_path_many_robots_reaches_the_flow_floor():
    # d = 4 < n = 8: the path full and the rest queued next to the food deliver one unit a
    # round once the first is home, the flow bound ⌊d/2⌋ + k exactly
    q, start = least_transport(16, (12, 8), 8, 20, budget=20)
    assert q == proven_floor(4, 8, 20) == 22
    assert start.relay == (4, 3, 2, 1)
