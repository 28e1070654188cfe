"""Frontier detection on hand-made grids, and the fast path against scipy's labelling."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from swarmex.sensing.frontiers import (
    chunk_targets,
    detect_frontiers,
    frontier_mask,
    frontiers_of_logodds,
)

# F free, U unknown, # occupied
GRID = [
    "FFFUUU",
    "FFFUUU",
    "F#FFFF",
    "FFFFFF",
    "UFFFF#",
]


def parse(rows):
    a = np.array([list(r) for r in rows])
    return a == "F", a == "U"


def test_frontier_cells_by_hand():
    free, unknown = parse(GRID)
    got = frontier_mask(free, unknown)
    want = np.zeros_like(free)
    for y, x in [(0, 2), (1, 2), (2, 3), (2, 4), (2, 5), (3, 0), (4, 1)]:
        want[y, x] = True
    assert (got == want).all()


def test_regions_and_minimum_size():
    free, unknown = parse(GRID)
    fr = detect_frontiers(free, unknown, min_size=1)
    # 8-connectivity: {(0,2),(1,2),(2,3),(2,4),(2,5)} and {(3,0),(4,1)} (diagonal)
    assert sorted(fr.sizes.tolist()) == [2, 5]
    assert fr.n_regions == 2 and fr.dropped_cells == 0
    big = detect_frontiers(free, unknown, min_size=3)
    assert big.n_regions == 1 and big.n_cells == 5 and big.dropped_cells == 2
    four = detect_frontiers(free, unknown, min_size=1, connectivity=4)
    assert sorted(four.sizes.tolist()) == [1, 1, 2, 3]


def test_no_unknown_no_frontier():
    free = np.ones((4, 4), dtype=bool)
    assert not detect_frontiers(free, np.zeros_like(free))


@pytest.mark.parametrize("seed", range(5))
def test_fast_path_matches_scipy(seed):
    rng = np.random.default_rng(seed)
    lo = rng.choice(np.array([-0.4, 0.0, 0.85], dtype=np.float32), size=(50, 60), p=[.6, .3, .1])
    fast = frontiers_of_logodds(lo, min_size=3)
    mask = frontier_mask(lo < 0, lo == 0)
    labels, _ = ndimage.label(mask, structure=np.ones((3, 3)))
    sizes = np.bincount(labels.ravel())
    keep = (labels > 0) & (sizes[labels] >= 3)
    assert fast.n_cells == int(keep.sum())
    assert keep[fast.ys, fast.xs].all()
    # same partition: two kept cells share a region iff scipy gives them one label
    lab = labels[fast.ys, fast.xs]
    assert (np.equal.outer(lab, lab) == np.equal.outer(fast.region, fast.region)).all()


def test_chunk_targets_one_per_piece():
    free = np.zeros((3, 40), dtype=bool)
    unknown = np.zeros_like(free)
    free[1, :] = True
    unknown[0, :] = True
    fr = detect_frontiers(free, unknown)
    assert fr.n_regions == 1
    t = chunk_targets(fr, np.ones(fr.n_cells, dtype=bool), chunk=10)
    assert len(t) == 4  # a 40-cell line cut into 10-cell squares
    assert sorted(fr.xs[t].tolist()) == [4, 14, 24, 34]  # nearest each piece's mean
