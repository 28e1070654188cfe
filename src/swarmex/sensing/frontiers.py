"""Frontier detection on an occupancy grid (Yamauchi 1997; seed 003 §1.1).

A *frontier cell* is a free cell with at least one unknown 4-neighbour ("a free cell adjacent
to at least one unexplored cell"); 4-neighbours, because a cell touching the unknown only at
a corner borders nothing a robot standing there would fail to see. Frontier cells are grouped
into *regions* by 8-connectivity (a diagonal frontier is one border, not a staircase of
pieces), and "each region with a size comparable to the size of the robot is considered a
frontier": regions with fewer than ``min_size`` cells are dropped (swarmex uses the robot's
diameter in cells, see the mission's docs).

Plain functions of arrays that return plain data, like NetworkX algorithms: no state, so the
same code serves every robot's belief and the tests' hand-made grids. Labelling is a numba
breadth-first search over the frontier cells only (they are few: the border of what is
known), numbered in raster order like ``scipy.ndimage.label``, which the tests compare it
with; :func:`frontiers_of_logodds` finds the cells and labels them in one pass over a map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel


def frontier_mask(free: np.ndarray, unknown: np.ndarray) -> np.ndarray:
    """Free cells with an unknown 4-neighbour (cells outside the map are not unknown)."""
    near = np.zeros_like(unknown)
    near[1:, :] |= unknown[:-1, :]
    near[:-1, :] |= unknown[1:, :]
    near[:, 1:] |= unknown[:, :-1]
    near[:, :-1] |= unknown[:, 1:]
    return free & near


@dataclass(frozen=True)
class Frontiers:
    """The frontier cells of the kept regions, with each cell's region index."""

    ys: np.ndarray  # row of each frontier cell
    xs: np.ndarray  # column of each frontier cell
    region: np.ndarray  # region index (0..n_regions-1) of each cell
    sizes: np.ndarray  # cells per region
    dropped_cells: int  # frontier cells in regions smaller than min_size

    @property
    def n_regions(self) -> int:
        return int(self.sizes.shape[0])

    @property
    def n_cells(self) -> int:
        return int(self.ys.shape[0])

    def __bool__(self) -> bool:
        return self.n_cells > 0


@kernel(cache=True, nogil=True)
def _label(
    ys: NDArray[np.int64], xs: NDArray[np.int64], h: int, w: int, eight: bool
) -> tuple[NDArray[np.int64], int]:  # pragma: no cover - compiled
    """Component index of each listed cell (breadth-first, numbered in list order)."""
    n = ys.shape[0]
    where = np.full((h, w), -1, dtype=np.int64)
    for i in range(n):
        where[ys[i], xs[i]] = i
    lab = np.full(n, -1, dtype=np.int64)
    q = np.empty(n, dtype=np.int64)
    count = 0
    for s in range(n):
        if lab[s] >= 0:
            continue
        lab[s] = count
        q[0] = s
        head = 0
        tail = 1
        while head < tail:
            u = q[head]
            head += 1
            for dy in range(-1, 2):
                for dx in range(-1, 2):
                    if (dy == 0 and dx == 0) or (not eight and dy != 0 and dx != 0):
                        continue
                    yy = ys[u] + dy
                    xx = xs[u] + dx
                    if 0 <= yy < h and 0 <= xx < w:
                        v = where[yy, xx]
                        if v >= 0 and lab[v] < 0:
                            lab[v] = count
                            q[tail] = v
                            tail += 1
        count += 1
    return lab, count


@kernel(cache=True, nogil=True)
def _frontier_cells(
    logodds: NDArray[np.float32],
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:  # pragma: no cover - compiled
    """Rows and columns, in raster order, of free cells (< 0) with an unknown (== 0)
    4-neighbour."""
    h, w = logodds.shape
    ys = np.empty(h * w, dtype=np.int64)
    xs = np.empty(h * w, dtype=np.int64)
    n = 0
    for y in range(h):
        for x in range(w):
            if logodds[y, x] < 0 and (
                (y > 0 and logodds[y - 1, x] == 0)
                or (y < h - 1 and logodds[y + 1, x] == 0)
                or (x > 0 and logodds[y, x - 1] == 0)
                or (x < w - 1 and logodds[y, x + 1] == 0)
            ):
                ys[n] = y
                xs[n] = x
                n += 1
    return ys[:n].copy(), xs[:n].copy()


def _regions(
    ys: NDArray[np.int64], xs: NDArray[np.int64], shape: tuple[int, ...], min_size: int,
    connectivity: int,
) -> Frontiers:
    lab, n = _label(ys, xs, shape[0], shape[1], connectivity == 8)
    sizes = np.bincount(lab, minlength=n)
    keep_region = sizes >= max(1, int(min_size))
    keep = keep_region[lab]
    new_index = np.cumsum(keep_region) - 1  # old label -> compact index
    return Frontiers(
        ys=ys[keep],
        xs=xs[keep],
        region=new_index[lab[keep]],
        sizes=sizes[keep_region],
        dropped_cells=int((~keep).sum()),
    )


def frontier_regions(mask: np.ndarray, min_size: int = 1, connectivity: int = 8) -> Frontiers:
    """Connected components of a frontier mask, keeping those with ``>= min_size`` cells.

    Regions are numbered in raster order of their first cell (as ``scipy.ndimage.label``).
    """
    ys, xs = np.nonzero(mask)
    return _regions(ys.astype(np.int64), xs.astype(np.int64), mask.shape, min_size,
                    connectivity)


def detect_frontiers(
    free: np.ndarray, unknown: np.ndarray, min_size: int = 1, connectivity: int = 8
) -> Frontiers:
    """Frontier cells grouped into regions of at least ``min_size`` cells."""
    return frontier_regions(frontier_mask(free, unknown), min_size, connectivity)


def frontiers_of_logodds(logodds: np.ndarray, min_size: int = 1) -> Frontiers:
    """:func:`detect_frontiers` on a log-odds grid (free < 0, unknown == 0) in one pass."""
    ys, xs = _frontier_cells(logodds)
    return _regions(ys, xs, logodds.shape, min_size, 8)


def chunk_targets(fr: Frontiers, eligible: np.ndarray, chunk: float) -> np.ndarray:
    """One representative cell per piece of each region, for assignment-style strategies.

    A long frontier is one region but several places to go; regions are cut by a square
    lattice of side ``chunk`` cells (the laser range: what one visit can clear) and each
    (region, square) piece is represented by its eligible cell nearest the piece's mean.
    Returns indices into ``fr``'s cell arrays, in a deterministic order.
    """
    idx = np.nonzero(eligible)[0]
    if idx.size == 0:
        return idx
    side = max(1.0, float(chunk))
    by = (fr.ys[idx] // side).astype(np.int64)
    bx = (fr.xs[idx] // side).astype(np.int64)
    key = (fr.region[idx].astype(np.int64) * 1_000_003 + by) * 1_000_003 + bx
    uniq, inv = np.unique(key, return_inverse=True)
    cnt = np.bincount(inv).astype(np.float64)
    my = np.bincount(inv, weights=fr.ys[idx]) / cnt
    mx = np.bincount(inv, weights=fr.xs[idx]) / cnt
    d2 = (fr.ys[idx] - my[inv]) ** 2 + (fr.xs[idx] - mx[inv]) ** 2
    order = np.lexsort((idx, d2, inv))  # by piece, then distance to its mean, then index
    first = np.ones(order.size, dtype=bool)
    first[1:] = inv[order][1:] != inv[order][:-1]
    return idx[order[first]]
