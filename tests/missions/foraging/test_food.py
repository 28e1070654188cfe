"""Separation bands and food placement."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.foraging.food import band_cells, parse_band, sample_food
from swarmex.missions.foraging.params import ForagingParams


def test_bands_of_the_released_code_for_g128():
    for band, (lo, hi) in {
        "0-20": (1, 24),
        "20-40": (25, 50),
        "40-60": (51, 75),
        "60-80": (76, 101),
        "80-100": (102, 128),
    }.items():
        d = np.abs(band_cells(128, band) - 64).sum(axis=1)
        assert d.min() == lo and d.max() == hi


def test_sampling_is_seeded_and_never_the_nest():
    a = sample_food(16, "random", np.random.default_rng(3), 50)
    b = sample_food(16, "random", np.random.default_rng(3), 50)
    assert a == b and (8, 8) not in a


@pytest.mark.parametrize("text", ["1", "a,b", "99,1", "8,8", (16, 0), (8, 8)])
def test_bad_cells(text):
    with pytest.raises(InputError, match="--food"):
        ForagingParams.from_values(grid=16, agents=4, algorithm="strips", food=text)


@pytest.mark.parametrize("text", ["x", "40-20", "0-120"])
def test_bad_bands(text):
    with pytest.raises(InputError):
        parse_band(text)
