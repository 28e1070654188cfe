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
