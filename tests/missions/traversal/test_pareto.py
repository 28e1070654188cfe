"""The proven floor on two mean gaps at once (issue 17's mixed-agent targets)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.traversal.pareto import least_mean_sum_gap, staircase


def test_staircase_charges_each_band_the_next_caps_floor() -> None:
    # plans within 1.0x have sum gap >= 0.3; within (1.0, 1.5] >= 0.1; beyond, >= 0
    assert staircase([1.0, 1.5], [0.3, 0.1]) == [(0.0, 0.3), (0.0, 0.1), (0.5, 0.0)]
    # a negative floor (a dual bound below the optimum) is no information: clamped to 0
    assert staircase([1.1], [-0.2]) == [(0.0, 0.0), pytest.approx((0.1, 0.0))]


def test_hand_computed_mix() -> None:
    """Instance A: (0, .1) or (.5, 0); instance B reaches 0 for free. A mean makespan gap of
    0.1 lets A spend 0.2: weight 0.4 on (.5, 0), so A's sum gap is 0.6 * 0.1 = 0.06 and
    the mean over both instances 0.03."""
    a = staircase([1.0, 1.5], [0.3, 0.1])
    b = staircase([1.0], [0.2])
    assert least_mean_sum_gap([a, b], 0.1) == pytest.approx(0.03)
    assert least_mean_sum_gap([a, b], 0.0) == pytest.approx(0.05)
    assert least_mean_sum_gap([a, b], 1.0) == pytest.approx(0.0)


def test_never_above_any_mix_of_pure_choices() -> None:
    """Brute force over every choice of one point per instance and every 0.1-step mix of two
    such choices: none that meets the budget has a lower mean than the LP's floor, and the
    best pure choice is matched when it is optimal."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        pts = []
        for _i in range(3):
            caps = np.cumsum(rng.uniform(0.01, 0.2, 3)) + 1.0
            floors = np.sort(rng.uniform(0.0, 0.4, 3))[::-1]
            pts.append(staircase(caps.tolist(), floors.tolist()))
        budget = float(rng.uniform(0.0, 0.3))
        lp = least_mean_sum_gap(pts, budget)
        pure = np.array([np.mean(c, axis=0) for c in itertools.product(*pts)])  # (mk, sum)
        w = np.linspace(0, 1, 11)[None, None, :]
        mk = w * pure[:, None, None, 0] + (1 - w) * pure[None, :, None, 0]
        sm = w * pure[:, None, None, 1] + (1 - w) * pure[None, :, None, 1]
        best = sm[mk <= budget + 1e-12].min()
        assert lp <= best + 1e-9
        # the LP has one coupling row, so an optimum mixes two pure choices: the 0.1-step
        # brute force is within one step of it
        assert best - lp <= 0.1 * pure[:, 1].max() + 1e-9


def test_bad_input_is_a_clear_error() -> None:
    with pytest.raises(InputError, match="ascend"):
        staircase([1.1, 1.0], [0.1, 0.2])
    with pytest.raises(InputError, match="one floor per cap"):
        staircase([1.0], [])
    with pytest.raises(InputError, match="no mix"):
        least_mean_sum_gap([[(0.1, 0.0)]], 0.05)
