"""Channel: range, loss and validation."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.comm import Channel
from swarmex.errors import InputError


def test_perfect_reaches_everyone_else():
    pos = np.zeros((4, 2))
    got = Channel().receivers(1, pos, np.random.default_rng(0))
    assert got.tolist() == [0, 2, 3]
    assert Channel().perfect


def test_range_is_euclidean():
    pos = np.array([[0, 0], [3, 4], [6, 8]], float)
    got = Channel(range=5.0).receivers(0, pos, np.random.default_rng(0))
    assert got.tolist() == [1]


def test_loss_rate_is_honoured():
    pos = np.zeros((2001, 2))
    got = Channel(loss=0.3).receivers(0, pos, np.random.default_rng(1))
    assert abs(got.size / 2000 - 0.7) < 0.04


@pytest.mark.parametrize("kw", [{"loss": 1.0}, {"loss": -0.1}, {"delay": -1}, {"range": 0}])
def test_invalid(kw):
    with pytest.raises(InputError):
        Channel(**kw)


def test_dead_agents_hear_nothing():
    """``alive`` removes dead agents from the receivers (everyone else in range still hears):
    a public option no simulator path passes, so only this test pins it."""
    pos = np.zeros((4, 2))
    alive = np.array([True, True, False, True])
    got = Channel().receivers(0, pos, np.random.default_rng(0), alive)
    assert got.tolist() == [1, 3]
    # with a range too, the mask is the conjunction: alive, in range and not the sender
    pos = np.array([[0, 0], [1, 0], [2, 0], [9, 0]], float)
    got = Channel(range=5.0).receivers(0, pos, np.random.default_rng(0), alive)
    assert got.tolist() == [1]
