"""The thesis's worst-case exploration times (Thm. 3.1.1, 3.3.1, 3.4.1) as property tests."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmex.missions.foraging import run_forage
from swarmex.missions.foraging.grid import nest_of
from swarmex.missions.foraging.theory import deployment_offset, worst_case_exploration
from swarmex.missions.foraging.timed import timed_plan

CONFIGS = [
    ("strips", 32, 1),
    ("strips", 32, 2),
    ("strips", 32, 4),
    ("strips", 32, 8),
    ("strips", 30, 3),
    ("zigzag", 32, 4),
    ("zigzag", 32, 16),
    ("hilbert", 32, 4),
    ("hilbert", 32, 16),
    ("sectors", 32, 4),
    ("sectors", 32, 8),
    ("sectors", 32, 16),
]


@st.composite
def case(draw):
    name, g, n = draw(st.sampled_from(CONFIGS))
    x = draw(st.integers(0, g - 1))
    y = draw(st.integers(0, g - 1))
    if (x, y) == nest_of(g):
        x = (x + 1) % g
    return name, g, n, (x, y)


@settings(max_examples=120, deadline=None)
@given(case())
def test_exploration_never_exceeds_the_proven_worst_case(c):
    name, g, n, food = c
    run = run_forage(name, g, n, food, units=1, record=False)
    offset = deployment_offset(name, g, n)
    assert 0 <= offset <= 2  # our nest is one step off the thesis's ideal centre
    assert run.metrics["exploration_time"] <= worst_case_exploration(name, g, n) + offset


def first_visits(name, g, n):
    pos = timed_plan(name, g, n).pos
    first = np.full((g, g), -1)
    for t in range(len(pos) - 1, -1, -1):
        first[pos[t, :, 0], pos[t, :, 1]] = t
    return first


@pytest.mark.parametrize(("name", "g", "n"), [c for c in CONFIGS if c[0] != "sectors"])
def test_the_bound_is_tight(name, g, n):
    # the latest-found cell takes exactly the thesis's worst-case time (+ our offset, ≤ 2)
    bound = worst_case_exploration(name, g, n) + deployment_offset(name, g, n)
    worst = first_visits(name, g, n).max()
    assert bound - 1 <= worst <= bound
