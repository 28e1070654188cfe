"""The seeded generators' component filter: the small-map flood fill is ndimage's answer."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from swarmex.worlds import generators
from swarmex.worlds.generators import _largest_component_small, keep_largest_component


def _by_ndimage(free: np.ndarray) -> np.ndarray:
    labels, count = ndimage.label(free)
    if count <= 1:
        return free.copy()
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return labels == int(np.argmax(sizes))


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 12), st.integers(1, 12), st.floats(0.0, 0.9), st.integers(0, 2**31))
def test_flood_fill_equals_ndimage_label(h, w, density, seed):
    free = np.random.default_rng(seed).random((h, w)) >= density
    got = _largest_component_small(free)
    assert got.dtype == np.bool_ and got.shape == free.shape
    np.testing.assert_array_equal(got, _by_ndimage(free))


def test_ties_keep_the_first_component_in_row_major_order():
    free = np.array([[1, 0, 1], [1, 0, 1], [0, 0, 0]], dtype=bool)  # two columns of 2
    want = np.array([[1, 0, 0], [1, 0, 0], [0, 0, 0]], dtype=bool)
    np.testing.assert_array_equal(_largest_component_small(free), want)
    np.testing.assert_array_equal(_by_ndimage(free), want)


def test_large_maps_use_ndimage(monkeypatch):
    monkeypatch.setattr(generators, "SMALL_LABEL_CELLS", 0)
    free = np.random.default_rng(3).random((40, 50)) >= 0.4
    np.testing.assert_array_equal(keep_largest_component(free), _by_ndimage(free))
