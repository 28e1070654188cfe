"""Theorems 5.3.1 and 5.3.7 hold exactly in our transport rules."""

from __future__ import annotations

import pytest

from swarmex.missions.foraging.theory import (
    end_to_end_setting,
    relay_setting,
    theorem_5_3_1,
    theorem_5_3_7,
)


@pytest.mark.parametrize("n", range(1, 8))
@pytest.mark.parametrize("i", range(1, 5))
def test_relay_theorem_5_3_7(n, i):
    m = relay_setting(n, i)
    m.run(record=False)
    assert m.delivered == n
    assert m.t == theorem_5_3_7(n, i)


def test_relay_example_fig53():
    # 4 robots, path 10i + 5, finish at 18i + 3
    for i in (1, 2, 3):
        m = relay_setting(4, i)
        m.run(record=False)
        assert m.t == 18 * i + 3


@pytest.mark.parametrize("n", range(1, 8))
@pytest.mark.parametrize("x", range(1, 6))
def test_end_to_end_theorem_5_3_1(n, x):
    m = end_to_end_setting(n, x)
    m.run(record=False)
    assert m.delivered == n
    assert m.t == theorem_5_3_1(n, x)


def test_relay_saves_two_n_minus_one():
    for n in (2, 5):
        for i in (1, 3):
            assert theorem_5_3_1(n, 2 * i + 1) - theorem_5_3_7(n, i) == 2 * (n - 1)


def test_python_and_compiled_transport_agree_on_the_theorem_settings():
    for n, i in [(3, 2), (6, 1)]:
        a, b = relay_setting(n, i), relay_setting(n, i)
        a.run(record=True, fast=False)
        b.run(record=True, fast=True)
        assert a.t == b.t and a.jobs == b.jobs
