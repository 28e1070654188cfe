"""The Python loop and the compiled transport loop play the same run, on random small runs.

Drawn across every pattern and transport, small and crowded grids, food anywhere (corners
included) and few units, so the rare crowded rounds near the food come up: that is where
the compiled loop once read past a robot's options (test_hemmed_in.py); before that fix, 2
of these 200 draws (seeds 123 and 176) failed. Every run must also finish, and every move
must be legal.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.base import StopRun
from swarmex.missions.foraging import recall
from swarmex.missions.foraging.comm import COMM_RULES
from swarmex.missions.foraging.run import check_inputs
from swarmex.missions.foraging.sim import TRANSPORT, Frame, Mission, round_limit, run_mission
from swarmex.missions.foraging.timed import timed_plan

PATTERNS = (
    "strips", "zigzag", "hilbert", "sectors", "spiral", "modified-zigzag", "rings",
    "loop-strips", "sector-loop", "comb",
)  # fmt: skip
TRANSPORTS = ("relay-food", "relay-path", "end-to-end")


def _draw(rng: np.random.Generator):
    """A valid random run: (pattern, g, n, food, k, transport)."""
    while True:
        g = int(rng.choice([4, 6, 8, 10, 12, 16]))
        n = int(rng.choice([1, 2, 4, 8, 16]))
        pattern, transport = str(rng.choice(PATTERNS)), str(rng.choice(TRANSPORTS))
        k = int(rng.choice([1, 2, 3, n, 2 * n]))
        try:
            check_inputs(pattern, g, n, k, transport, "seed")
            timed_plan(pattern, g, n)
        except InputError:
            continue
        corners = [(0, 0), (0, g - 1), (g - 1, 0), (g - 1, g - 1)]
        food = corners[int(rng.integers(4))] if rng.random() < 0.4 else (
            int(rng.integers(g)), int(rng.integers(g)))
        if food != (g // 2, g // 2):
            return pattern, g, n, food, k, transport


@pytest.mark.parametrize("seed", range(200))
def test_random_small_runs_agree_in_both_loops(seed):
    pattern, g, n, food, k, transport = _draw(np.random.default_rng(seed))
    plan = timed_plan(pattern, g, n)
    slow = run_mission(plan, food, k, transport, fast=False)
    fast = run_mission(plan, food, k, transport, fast=True)
    assert slow.complete and slow.delivered == k
    assert slow.makespan == fast.makespan
    assert np.array_equal(slow.positions, fast.positions)
    assert slow.jobs == fast.jobs
    steps = np.abs(np.diff(slow.positions, axis=0)).sum(axis=2)
    assert steps.max() <= 1  # one cell or a stay per round
    nest = tuple(plan.plan.nest)
    for row in slow.positions:
        cells = [tuple(c) for c in row.tolist() if tuple(c) != nest]
        assert len(cells) == len(set(cells))  # never two robots in one non-nest cell


# ---------------------------------------------------------------- the communication phase
# fastloop.comm_rounds plays a plain run from the discovery until everyone transports; these
# draws compare it with the Python loop on every pattern (recall's annulus too), transport
# and communication rule, teams that do not divide the grid, food near, far and anywhere.
COMM_PATTERNS = (*PATTERNS, "annulus")


def _same_outcome(slow, fast):
    assert slow.makespan == fast.makespan
    assert np.array_equal(slow.positions, fast.positions)
    for name in ("jobs", "handovers", "discovery", "finders", "informed_at", "comm_done",
                 "delivered", "complete", "extra"):  # fmt: skip
        assert getattr(slow, name) == getattr(fast, name), name


def _comm_draw(rng: np.random.Generator):
    """A valid random run: (timed, food, k, transport, comm)."""
    while True:
        g = int(rng.choice([5, 6, 8, 10, 12, 16, 20, 24, 32]))
        n = int(rng.choice([1, 2, 3, 4, 5, 7, 8, 12, 16, 32]))
        pattern, transport = str(rng.choice(COMM_PATTERNS)), str(rng.choice(TRANSPORTS))
        rule = str(rng.choice(COMM_RULES))
        k = int(rng.choice([1, 3, n, 2 * n, 20]))
        try:
            if pattern == "annulus":
                lo = int(rng.integers(1, g))
                timed = recall.annulus_timed(g, n, lo, int(rng.integers(lo, g + 2)))
            else:
                check_inputs(pattern, g, n, k, transport, rule)
                timed = timed_plan(pattern, g, n)
        except InputError:
            continue
        c = g // 2
        where = rng.random()
        if where < 0.3:  # a corner: the farthest cells
            food = ((g - 1) * int(rng.integers(2)), (g - 1) * int(rng.integers(2)))
        elif where < 0.5:  # next to the nest
            dx, dy = rng.integers(-2, 3, size=2)
            food = (min(g - 1, c + int(dx)), min(g - 1, c + int(dy)))
        else:
            food = (int(rng.integers(g)), int(rng.integers(g)))
        if food != (c, c):
            return timed, food, k, transport, rule


@pytest.mark.parametrize("seed", range(300))
def test_compiled_communication_phase_is_the_python_loop(seed, monkeypatch):
    timed, food, k, transport, rule = _comm_draw(np.random.default_rng([7, seed]))
    slow = run_mission(timed, food, k, transport, fast=False, comm=rule)
    played = []
    compiled = Mission._comm_phase
    monkeypatch.setattr(Mission, "_comm_phase", lambda m, *a: played.append(compiled(m, *a)))
    fast = run_mission(timed, food, k, transport, fast=True, comm=rule)
    assert played  # the compiled phase ran
    _same_outcome(slow, fast)
    quiet = run_mission(timed, food, k, transport, record=False, comm=rule)
    assert (quiet.makespan, quiet.jobs) == (fast.makespan, fast.jobs)


def _python_until_transport(m: Mission) -> None:
    """The Python rounds of Mission.rounds up to where the compiled phase stops."""
    limit = round_limit(m.t, m.g, m.k)
    while not all(mode == TRANSPORT for mode in m.mode):
        m.look()
        m.history.append(list(m.pos))
        if m.delivered >= m.k or m.t >= limit:
            return
        m.step()


@pytest.mark.parametrize(
    ("pattern", "g", "n", "food", "transport", "rule"),
    [("zigzag", 16, 16, (2, 13), "relay-path", "seed"),
     ("sectors", 20, 16, (19, 0), "relay-food", "seed"),
     ("spiral", 12, 8, (7, 4), "end-to-end", "seed"),
     ("hilbert", 16, 16, (12, 3), "relay-food", "omniscient"),
     ("comb", 32, 8, (0, 31), "relay-path", "omniscient")],
)  # fmt: skip
def test_compiled_communication_phase_leaves_the_python_state(pattern, g, n, food, transport, rule):
    """After the compiled phase the Mission's lists, the word and the transport memory are
    what the Python rounds leave (the tail and any later reader start from them)."""
    timed = timed_plan(pattern, g, n)
    t0 = int(np.flatnonzero(((timed.pos == food).all(axis=2)).any(axis=1))[0])
    start = [tuple(c) for c in timed.pos[t0].tolist()]
    made = [Mission(g, timed.plan.nest, food, 3, transport, start, t=t0, timed=timed, comm=rule)
            for _ in range(2)]  # fmt: skip
    slow, fast = made
    _python_until_transport(slow)
    fast._comm_phase(True, round_limit(fast.t, g, fast.k))
    for name in ("t", "pos", "mode", "delay", "displaced", "informed", "informed_at", "targets",
                 "carrying", "tmode", "pidx", "comm_done", "jobs", "handovers", "units",
                 "delivered", "join_at", "_last_key"):  # fmt: skip
        assert getattr(slow, name) == getattr(fast, name), name
    if rule == "seed":
        assert slow.word.know == fast.word.know
        assert slow.word.rank == fast.word.rank
        assert slow.word.holders == fast.word.holders
    rows = np.concatenate(fast.tail_chunks)
    assert np.array_equal(np.asarray(slow.history, dtype=np.int32), rows)


def _frames_and_stop(timed, food, k, transport, rule, fast, t_stop):
    """The run's frames, and the run stopped by StopRun at round ``t_stop``."""
    frames: list[Frame] = []
    whole = run_mission(timed, food, k, transport, fast=fast, comm=rule, on_frame=frames.append)

    def stop(frame: Frame) -> None:
        if frame.t == t_stop:
            raise StopRun

    stopped = run_mission(timed, food, k, transport, fast=fast, comm=rule, on_frame=stop)
    return whole, frames, stopped


@pytest.mark.parametrize("seed", range(40))
def test_compiled_communication_phase_gives_the_python_frames_and_stops(seed):
    """With ``on_frame`` the compiled phase plays a round per call: the same frames, and a
    StopRun in the communication phase ends the run where the Python loop ends it."""
    timed, food, k, transport, rule = _comm_draw(np.random.default_rng([11, seed]))
    ref = run_mission(timed, food, k, transport, fast=False, comm=rule)
    told = [t for t in ref.comm_done if t is not None]
    assert ref.discovery is not None
    t_stop = (ref.discovery + max(told or [ref.discovery])) // 2 + seed % 2
    slow = _frames_and_stop(timed, food, k, transport, rule, False, t_stop)
    fast = _frames_and_stop(timed, food, k, transport, rule, True, t_stop)
    _same_outcome(slow[0], fast[0])
    _same_outcome(slow[2], fast[2])
    assert len(slow[1]) == len(fast[1]) == ref.makespan + 1
    for x, y in zip(slow[1], fast[1], strict=True):
        assert (x.t, x.delivered, x.food_left) == (y.t, y.delivered, y.food_left)
        for name in ("positions", "carrying", "informed"):
            a, b = getattr(x, name), getattr(y, name)
            assert a.dtype == b.dtype and np.array_equal(a, b), (x.t, name)


# runs whose mixed phase froze before the frozen-crowd rule covered it (test_frozen_crowd.py):
# the compiled communication phase must break the freeze on the same rounds as the Python loop
FROZE_MIXED = [
    ("sectors", 14, 48, "seed", (8, 4), 20),
    ("sectors", 14, 48, "omniscient", (8, 5), 20),
    ("rings", 10, 24, "seed", (7, 9), 20),
    ("sectors", 32, 64, "omniscient", (15, 19), 100),
]


@pytest.mark.parametrize(("pattern", "g", "n", "rule", "food", "k"), FROZE_MIXED)
def test_compiled_communication_phase_breaks_a_frozen_crowd_as_the_python_loop(
    pattern, g, n, rule, food, k, monkeypatch
):
    timed = timed_plan(pattern, g, n)
    frozen = []
    compute = Mission._compute

    def spy(m):
        out = compute(m)
        frozen.append(m._frozen and not all(mode == TRANSPORT for mode in m.mode))
        return out

    monkeypatch.setattr(Mission, "_compute", spy)
    slow = run_mission(timed, food, k, "end-to-end", fast=False, comm=rule)
    assert any(frozen)  # the mixed-phase rule fired in the Python loop
    monkeypatch.undo()
    assert slow.complete
    fast = run_mission(timed, food, k, "end-to-end", fast=True, comm=rule)
    _same_outcome(slow, fast)
    t_stop = (slow.discovery + slow.makespan) // 2
    play = (timed, food, k, "end-to-end", rule)
    whole_s, frames_s, stopped_s = _frames_and_stop(*play, False, t_stop)
    whole_f, frames_f, stopped_f = _frames_and_stop(*play, True, t_stop)
    _same_outcome(whole_s, whole_f)
    _same_outcome(stopped_s, stopped_f)
    _same_outcome(slow, whole_f)
    assert len(frames_s) == len(frames_f) == slow.makespan + 1
    for x, y in zip(frames_s, frames_f, strict=True):
        assert x.t == y.t and np.array_equal(x.positions, y.positions)
