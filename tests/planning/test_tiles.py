"""Per-tile bounds of hop rows: the lattice kernel against the generic one."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.planning.tiles import NONE_HI, NONE_LO, Tiling, tile_range, tile_range_lattice


@pytest.mark.parametrize("dtype", [np.int16, np.int32])
def test_lattice_tile_range_equals_the_generic_kernel(dtype):
    """Widths and heights that are and are not multiples of the tile side, rows with
    unreached (-1) and blocked (-2) cells, and tiles that are all unreached."""
    rng = np.random.default_rng(0)
    for _ in range(60):
        width, height = (int(v) for v in rng.integers(1, 40, size=2))
        n = width * height
        row = rng.integers(0, 300, size=n).astype(dtype)
        row[rng.random(n) < rng.random()] = -1
        row[rng.random(n) < 0.2] = -2
        tiling = Tiling(n, width)
        assert tiling.width == width
        want_lo = np.empty(tiling.n_tiles, dtype=np.int32)
        want_hi = np.empty_like(want_lo)
        tile_range(row, tiling.tile_of, want_lo, want_hi)
        lo = np.full_like(want_lo, 7)
        hi = np.full_like(want_lo, 7)
        tile_range_lattice(row, width, lo, hi)
        np.testing.assert_array_equal(lo, want_lo)
        np.testing.assert_array_equal(hi, want_hi)
        # an independent route: per tile, the min/max of its reached vertices
        for t in range(tiling.n_tiles):
            vals = row[tiling.verts[tiling.ptr[t]:tiling.ptr[t + 1]]]
            vals = vals[vals >= 0]
            assert lo[t] == (vals.min() if vals.size else NONE_LO)
            assert hi[t] == (vals.max() if vals.size else NONE_HI)
