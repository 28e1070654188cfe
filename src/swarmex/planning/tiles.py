"""Tiles of a graph and per-tile bounds of hop fields, for searches that skip whole regions.

A search for the best vertex of a map under some score (MADGTA's branch 3: the max over
vacant vertices of a min over rivals) does not need to read every vertex when it can bound
the score over a region: regions whose bound is below the best value found so far are
skipped. The bounds come from the hop fields themselves: per tile, the least and the
largest hop count of the reachable vertices (:func:`tile_range`). They are kept loosely up
to date instead of recomputed: a field shifted to a neighbouring source moves every value
by exactly one (so a bound widened by one stays valid), and a repair after new obstacles
only raises values (so the least stays a lower bound, and the largest is raised from the
re-derived vertices, :func:`raise_tile_max`). A bound that has drifted too far is
recomputed in one pass over the row.

Tiles are ``TILE_SIDE``-square blocks of cells on a 4-connected lattice (a grid world), and
runs of ``TILE_RUN`` consecutive vertex ids on other graphs. :class:`Tiling` lists each
tile's vertices in ascending id order, so a search that scans tiles and then sorts what it
found gets the same vertices in the same order as a scan of the whole id range.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.planning.kernel_arrays import Hops

#: side of a lattice tile (cells)
TILE_SIDE = 8
#: vertices per tile on graphs that are not lattices
TILE_RUN = 256
#: a tile's least hop count when the field reaches none of its vertices
NONE_LO = np.int32(2**30)
#: a tile's largest hop count when the field reaches none of its vertices
NONE_HI = np.int32(-1)


class Tiling:
    """The tiles of an ``n``-vertex graph: ``tile_of[v]``, and each tile's vertices
    ``verts[ptr[t]:ptr[t + 1]]`` in ascending order."""

    __slots__ = ("n_tiles", "tile_of", "ptr", "verts", "width")

    def __init__(self, n: int, width: int) -> None:
        self.width = width  # > 0: square tiles of a lattice (tile_range_lattice applies)
        ids = np.arange(n, dtype=np.int64)
        if width > 0:  # lattice: square blocks
            ys, xs = np.divmod(ids, width)
            per_row = -(-width // TILE_SIDE)
            tile = (ys // TILE_SIDE) * per_row + xs // TILE_SIDE
        else:
            tile = ids // TILE_RUN
        self.tile_of = tile.astype(np.int32)
        self.n_tiles = int(tile.max()) + 1 if n else 0
        order = np.argsort(tile, kind="stable")  # stable: ascending ids within a tile
        self.verts = order.astype(np.int32)
        counts = np.bincount(tile, minlength=self.n_tiles)
        self.ptr = np.zeros(self.n_tiles + 1, dtype=np.int64)
        np.cumsum(counts, out=self.ptr[1:])


@kernel(cache=True, nogil=True)
def tile_range(
    row: Hops, tile_of: NDArray[np.int32], lo: NDArray[np.int32], hi: NDArray[np.int32]
) -> None:  # pragma: no cover - compiled
    """Per tile, the least (``lo``) and largest (``hi``) hop count of the vertices ``row``
    reaches (negative entries: unreached or blocked); NONE_LO / NONE_HI for a tile with
    none."""
    for t in range(lo.shape[0]):
        lo[t] = NONE_LO
        hi[t] = NONE_HI
    for v in range(row.shape[0]):
        h = row[v]
        if h < 0:
            continue
        t = tile_of[v]
        if h < lo[t]:
            lo[t] = h
        if h > hi[t]:
            hi[t] = h


@kernel(cache=True, nogil=True)
def tile_range_lattice(
    row: Hops, width: int, lo: NDArray[np.int32], hi: NDArray[np.int32]
) -> None:  # pragma: no cover - compiled
    """:func:`tile_range` for the square tiles of a ``width``-wide lattice, the same
    values, computed so that the compiler vectorises it: per band of ``TILE_SIDE`` grid
    rows, a column-wise least and largest value over the band's rows (long branch-free
    loops; an unreached cell counts as NONE_LO for the least value and as its own negative
    value, below NONE_HI, for the largest), then each tile reduces its ``TILE_SIDE``
    columns. The generic kernel updates ``lo``/``hi`` in memory per cell instead."""
    n = row.shape[0]
    height = n // width
    per_row = (width + TILE_SIDE - 1) // TILE_SIDE
    none_lo = np.int32(NONE_LO)
    none_hi = np.int32(NONE_HI)
    cmin = np.empty(width, dtype=np.int32)
    cmax = np.empty(width, dtype=np.int32)
    for band in range((height + TILE_SIDE - 1) // TILE_SIDE):
        for x in range(width):
            cmin[x] = none_lo
            cmax[x] = none_hi
        for y in range(band * TILE_SIDE, min(height, band * TILE_SIDE + TILE_SIDE)):
            r = row[y * width:(y + 1) * width]
            for x in range(width):
                h = np.int32(r[x])
                cmin[x] = min(cmin[x], h if h >= 0 else none_lo)
                cmax[x] = max(cmax[x], h)
        for tx in range(per_row):
            mn = none_lo
            mx = none_hi
            for x in range(tx * TILE_SIDE, min(width, tx * TILE_SIDE + TILE_SIDE)):
                mn = min(mn, cmin[x])
                mx = max(mx, cmax[x])
            t = band * per_row + tx
            lo[t] = mn
            hi[t] = mx


@kernel(cache=True, nogil=True)
def raise_tile_max(
    row: Hops, changed: NDArray[np.int32], count: int, tile_of: NDArray[np.int32],
    hi: NDArray[np.int32],
) -> None:  # pragma: no cover - compiled
    """Raise ``hi`` to cover the new values of the vertices ``changed[:count]`` (a repair
    only raises hop counts, so the tiles' least values stay lower bounds)."""
    for j in range(count):
        v = changed[j]
        h = row[v]
        if h >= 0:
            t = tile_of[v]
            if h > hi[t]:
                hi[t] = h
