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
from swarmex.missions.foraging.run import check_inputs
from swarmex.missions.foraging.sim import run_mission
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
