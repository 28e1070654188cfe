"""Ray casting against an independent route: exact ray–box intersection with every wall cell."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmex.sensing.laser import Laser, cast_rays_cells
from swarmex.sensing.occupancy import rasterise


def brute_force_range(free: np.ndarray, x0: int, y0: int, angle: float, max_cells: float):
    """Distance to the first wall cell (or the map's edge) by slab tests on every cell."""
    h, w = free.shape
    ox, oy = x0 + 0.5, y0 + 0.5
    dx, dy = math.cos(angle), math.sin(angle)
    best = max_cells
    # leaving the map counts as hitting a wall at the edge
    for lo, hi, o, d in ((0.0, w, ox, dx), (0.0, h, oy, dy)):
        if d > 0:
            best = min(best, (hi - o) / d)
        elif d < 0:
            best = min(best, (lo - o) / d)
    for cy, cx in zip(*np.nonzero(~free), strict=True):
        tn, tf = -math.inf, math.inf
        for lo, o, d in ((cx, ox, dx), (cy, oy, dy)):
            if d == 0:
                if not lo <= o <= lo + 1:
                    tn, tf = 1.0, 0.0
                continue
            a, b = (lo - o) / d, (lo + 1 - o) / d
            tn, tf = max(tn, min(a, b)), min(tf, max(a, b))
        if tn <= tf and tf > 0:
            best = min(best, max(tn, 0.0))
    return best


@pytest.mark.parametrize("seed", range(6))
def test_ranges_match_exact_intersection(seed):
    rng = np.random.default_rng(seed)
    h, w = 24, 31
    free = rng.random((h, w)) > 0.12
    ys, xs = np.nonzero(free)
    i = rng.integers(len(ys))
    x0, y0 = int(xs[i]), int(ys[i])
    laser = Laser(range_m=0.6, beams=90, cell=0.05)  # 12 cells
    got = laser.cast(free, x0, y0)
    want = [brute_force_range(free, x0, y0, a, laser.range_cells) for a in laser.angles]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)


def test_empty_room_ranges_reach_the_walls():
    free = np.zeros((11, 11), dtype=bool)
    free[1:-1, 1:-1] = True
    out = np.empty(4)
    # along the axes from the centre (5, 5) the wall cells 0 and 10 start 4.5 cells away
    cast_rays_cells(free, 5, 5, np.array([0.0, math.pi / 2, math.pi, 3 * math.pi / 2]), 100.0,
                    out)
    np.testing.assert_allclose(out, 4.5, atol=1e-12)
    cast_rays_cells(free, 5, 5, np.array([0.0]), 3.0, out[:1])
    assert out[0] == 3.0  # nothing within range: the range is the maximum


@pytest.mark.parametrize("seed", range(4))
def test_local_map_is_true_and_hits_are_the_first_walls(seed):
    rng = np.random.default_rng(100 + seed)
    free = rng.random((40, 40)) > 0.1
    free[20, 20] = True
    laser = Laser(range_m=0.5, beams=180, cell=0.05)
    ranges = laser.cast(free, 20, 20)
    lm = rasterise(20, 20, ranges, laser.angles, laser.range_cells, free.shape)
    h, w = lm.free.shape
    truth = free[lm.y0 : lm.y0 + h, lm.x0 : lm.x0 + w]
    assert not (lm.free & ~truth).any()  # nothing passed is a wall
    assert not (lm.occ & truth).any()  # nothing hit is free
    assert lm.free[20 - lm.y0, 20 - lm.x0]
    # each beam that returned something hit the cell containing a point just past its range
    for a, r in zip(laser.angles, ranges, strict=True):
        if r < laser.range_cells:
            px, py = 20.5 + (r + 1e-7) * math.cos(a), 20.5 + (r + 1e-7) * math.sin(a)
            cx, cy = int(math.floor(px)), int(math.floor(py))
            if 0 <= cx < 40 and 0 <= cy < 40:
                assert lm.occ[cy - lm.y0, cx - lm.x0]


def test_laser_validates_its_geometry():
    from swarmex.errors import InputError

    with pytest.raises(InputError, match="laser-range"):
        Laser(range_m=-1.0)
    with pytest.raises(InputError, match="beams"):
        Laser(beams=2)
