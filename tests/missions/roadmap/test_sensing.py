"""Coverage raster: the compiled sweep (with its shadow shortcuts) against brute force."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmex.sensing.coverage_raster import CoverageRaster


def brute_seen(world, raster, segs, rng_r):
    """Union over segments and viewpoints of free cells in range with a free sight line."""
    h = raster.h
    jj, ii = np.nonzero(raster.free)
    cells = np.column_stack([raster.x0 + (ii + 0.5) * h, raster.y0 + (jj + 0.5) * h])
    seen = np.zeros(len(cells), dtype=bool)
    for a, b in segs:
        m = max(1, math.ceil(np.hypot(*(b - a)) / h))
        for s in range(m + 1):
            p = a + s / m * (b - a)
            near = np.hypot(*(cells - p).T) <= rng_r
            idx = np.flatnonzero(near & ~seen)
            if len(idx):
                ok = world.segments_free(np.repeat(p[None], len(idx), 0), cells[idx])
                seen[idx[ok]] = True
    out = np.zeros_like(raster.free)
    out[jj[seen], ii[seen]] = True
    return out


@pytest.mark.parametrize("rng_r", [12.0, 40.0, math.inf])
def test_sweep_matches_brute_force(clutter, rng_r):
    rng = np.random.default_rng(3)
    pts = clutter.sample_free(rng, 40)
    segs = [(pts[i], pts[i + 1]) for i in range(0, 40, 2)
            if clutter.segment_free(*pts[i], *pts[i + 1])]
    assert len(segs) >= 5
    raster = CoverageRaster(clutter, rng_r, cells=64)
    for t, (a, b) in enumerate(segs, start=1):
        raster.sense_segment(a, b, t)
    want = brute_seen(clutter, CoverageRaster(clutter, rng_r, cells=64), segs, rng_r)
    assert np.array_equal(raster.seen_mask(), want)
    assert raster.coverage() == pytest.approx(want.sum() / raster.free_cells)
    assert (raster.seen_at[want] >= 1).all()


def test_walls_block_sight(enclosed):
    r = CoverageRaster(enclosed, math.inf, cells=80)
    r.sense_segment(np.array([20.0, 20.0]), np.array([60.0, 40.0]), 1)
    # everything seen lies in the walled corner: sight does not pass the walls
    jj, ii = np.nonzero(r.seen_mask())
    x, y = r.x0 + (ii + 0.5) * r.h, r.y0 + (jj + 0.5) * r.h
    assert np.all((x < 74) & (y < 60))
    assert r.sighting(np.array([20.0, 20.0]), np.array([60.0, 40.0]), np.array([170, 130])) < 0
    assert r.sighting(np.array([20.0, 20.0]), np.array([60.0, 40.0]), np.array([50, 50])) == 0


def test_curve_is_monotone(clutter):
    r = CoverageRaster(clutter, 20.0, cells=64)
    r.sense_segment(np.array([10.0, 10.0]), np.array([30.0, 10.0]), 1)
    r.sense_segment(np.array([30.0, 10.0]), np.array([30.0, 25.0]), 3)
    c = r.curve(4)
    assert len(c) == 5 and c[0] == 0 and np.all(np.diff(c) >= 0)
    assert c[-1] == pytest.approx(r.coverage())
