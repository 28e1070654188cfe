"""Log-odds occupancy grids (seed 003 §1.3) and local maps made from laser scans.

The thesis's update is Bayes' rule for independent cells: *new p = current p × sensor
probability × normalisation constant*, with unknown cells at p = 0.5, free below and
occupied above. With the inverse sensor model ``s`` (the probability the cell is occupied
given this scan) and a uniform prior, that product becomes an addition in log-odds,
``l' = l + log(s / (1 - s))``, which is what is stored (float32, one per cell): unknown is
exactly ``l = 0``.

Sensor model (the thesis leaves it open, spec §6.10): a passed cell has ``s = P_MISS = 0.4``,
the cell a beam stops in ``s = P_HIT = 0.7``; log-odds are clamped to the probabilities
[0.12, 0.97] so a cell can change its mind after repeated evidence. These are OctoMap's
defaults. A scan updates each cell once (its *local map*: the set of cells passed by some
beam, and the set of cells hit, hits winning), so the number of beams does not change how
fast a cell converges. With the noise-free laser an occupied cell is never passed and a free
cell never hit, so no sum of updates can return a cell to exactly 0: "unknown" stays exact.

Scans become local maps here, once, by the robot that took them (:func:`rasterise`); that is
what is archived and flooded (the thesis calls scans "local maps" too). Merging is then
adding the local map's log-odds patch into the receiver's grid: received and own scans go
through the same update, as in the thesis.

Cost at scale (issue 14): in a team of n every robot merges every scan, n² merges per tick.
A local map is therefore kept, once and shared by every grid that merges it, as *row runs*
(row, first column, end column, hit?) — a few hundred short contiguous spans instead of one
index per cell, which the update kernel walks at memory speed — and a grid only queues the
local maps it is given: they are added, in arrival order, when the grid is next read
(:attr:`OccupancyGrid.logodds`), all of them in one compiled call. The arithmetic, cell by
cell and scan by scan, is the same as adding them one at a time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numba as nb
import numpy as np
from numpy.typing import NDArray

P_HIT = 0.7
P_MISS = 0.4
P_MIN = 0.12
P_MAX = 0.97


def logit(p: float) -> float:
    return math.log(p / (1.0 - p))


L_HIT = np.float32(logit(P_HIT))
L_MISS = np.float32(logit(P_MISS))
L_MIN = np.float32(logit(P_MIN))
L_MAX = np.float32(logit(P_MAX))


def probability(logodds: np.ndarray) -> np.ndarray:
    """Occupancy probability of each cell (0.5 where unknown)."""
    return 1.0 - 1.0 / (1.0 + np.exp(np.asarray(logodds, dtype=np.float64)))


@nb.njit(cache=True, nogil=True)
def _rasterise(
    x0: int, y0: int, angles: NDArray[np.float64], ranges: NDArray[np.float64],
    max_cells: float, bx: int, by: int, free_p: NDArray[np.bool_], occ_p: NDArray[np.bool_],
) -> None:  # pragma: no cover
    ph, pw = free_p.shape
    for b in range(angles.shape[0]):
        r = ranges[b]
        dx = math.cos(angles[b])
        dy = math.sin(angles[b])
        if dx > 0.0:
            sx, ddx = 1, 1.0 / dx
        elif dx < 0.0:
            sx, ddx = -1, -1.0 / dx
        else:
            sx, ddx = 0, np.inf
        if dy > 0.0:
            sy, ddy = 1, 1.0 / dy
        elif dy < 0.0:
            sy, ddy = -1, -1.0 / dy
        else:
            sy, ddy = 0, np.inf
        kx = 0
        ky = 0
        cx = x0
        cy = y0
        free_p[cy - by, cx - bx] = True
        while True:
            tx = (kx + 0.5) * ddx
            ty = (ky + 0.5) * ddy
            if tx < ty:
                t = tx
                kx += 1
                cx += sx
            else:
                t = ty
                ky += 1
                cy += sy
            inside = 0 <= cx - bx < pw and 0 <= cy - by < ph
            if t >= r:
                if r < max_cells and inside:
                    occ_p[cy - by, cx - bx] = True
                break
            if inside:
                free_p[cy - by, cx - bx] = True


@nb.njit(cache=True, nogil=True)
def _row_runs(
    x0: int, y0: int, free: NDArray[np.bool_], occ: NDArray[np.bool_]
) -> NDArray[np.int32]:  # pragma: no cover - compiled
    """Maximal horizontal runs of passed cells, then of hit cells: (row, x, x_end, hit)."""
    h, w = free.shape
    out = np.empty((h * w, 4), dtype=np.int32)
    n = 0
    for hit in range(2):
        m = occ if hit else free
        for y in range(h):
            x = 0
            while x < w:
                if not m[y, x]:
                    x += 1
                    continue
                a = x
                while x < w and m[y, x]:
                    x += 1
                out[n, 0] = y0 + y
                out[n, 1] = x0 + a
                out[n, 2] = x0 + x
                out[n, 3] = hit
                n += 1
    return out[:n].copy()


@nb.njit(cache=True, nogil=True)
def _add_runs(
    grid: NDArray[np.float32], runs: NDArray[np.int32], miss: np.float32, hit: np.float32,
    lo: np.float32, hi: np.float32,
) -> None:  # pragma: no cover - compiled
    """Add ``hit`` or ``miss`` to every cell of every run, in order, clamped to [lo, hi]."""
    for k in range(runs.shape[0]):
        row = grid[runs[k, 0]]
        d = hit if runs[k, 3] else miss
        for x in range(runs[k, 1], runs[k, 2]):
            v = row[x] + d
            row[x] = lo if v < lo else (hi if v > hi else v)


@dataclass(eq=False)
class LocalMap:
    """What one scan saw: a box of the grid with the cells it passed and the cells it hit."""

    x0: int  # column of the box's first cell
    y0: int  # row of the box's first cell
    free: np.ndarray  # bool (rows, cols)
    occ: np.ndarray  # bool (rows, cols), disjoint from ``free``
    _runs: np.ndarray | None = field(default=None, repr=False)

    def runs(self) -> np.ndarray:
        """Row runs in grid coordinates, int32 (k, 4): row, first column, end column, and 1
        for hit cells (0 for passed ones); computed once, shared by every grid."""
        if self._runs is None:
            self._runs = _row_runs(
                int(self.x0), int(self.y0), np.ascontiguousarray(self.free, dtype=np.bool_),
                np.ascontiguousarray(self.occ, dtype=np.bool_),
            )
        return self._runs

    def to_wire(self) -> dict[str, Any]:
        """msgpack-friendly form: box plus two bit-packed masks."""
        h, w = self.free.shape
        return {
            "box": [int(self.x0), int(self.y0), int(w), int(h)],
            "free": np.packbits(self.free, axis=None).tobytes(),
            "occ": np.packbits(self.occ, axis=None).tobytes(),
        }

    @classmethod
    def from_wire(cls, d: dict[str, Any]) -> LocalMap:
        x0, y0, w, h = (int(v) for v in d["box"])
        n = w * h

        def unpack(b: bytes) -> np.ndarray:
            bits = np.unpackbits(np.frombuffer(b, dtype=np.uint8), count=n)
            return bits.astype(bool).reshape(h, w)

        return cls(x0, y0, unpack(d["free"]), unpack(d["occ"]))


def rasterise(
    x: int, y: int, ranges: np.ndarray, angles: np.ndarray, max_cells: float, shape: tuple
) -> LocalMap:
    """Turn one scan (ranges in cells from the centre of cell (x, y)) into a :class:`LocalMap`.

    A cell is passed if a beam enters it before its range, hit if it is the cell a beam
    enters *at* its range (when that range is below ``max_cells``: a beam that returned
    nothing hits nothing). The walk is the laser's own, so the hit cell is found exactly.
    """
    h, w = shape
    reach = int(math.ceil(max_cells)) + 1
    bx, by = max(0, x - reach), max(0, y - reach)
    ex, ey = min(w, x + reach + 1), min(h, y + reach + 1)
    free_p = np.zeros((ey - by, ex - bx), dtype=np.bool_)
    occ_p = np.zeros_like(free_p)
    _rasterise(
        int(x), int(y), np.asarray(angles, np.float64), np.asarray(ranges, np.float64),
        float(max_cells), bx, by, free_p, occ_p,
    )
    free_p &= ~occ_p
    return LocalMap(bx, by, free_p, occ_p)


class OccupancyGrid:
    """One robot's map: log-odds per cell, 0 = unknown (p = 0.5).

    :meth:`apply` queues a local map; reading :attr:`logodds` first adds whatever is queued.
    """

    def __init__(self, shape: tuple[int, int]) -> None:
        self._logodds = np.zeros(shape, dtype=np.float32)
        self._pending: list[np.ndarray] = []
        self.updates = 0

    @property
    def logodds(self) -> np.ndarray:
        if self._pending:
            self._flush()
        return self._logodds

    @property
    def pending(self) -> int:
        """Local maps given but not added yet."""
        return len(self._pending)

    @property
    def shape(self) -> tuple[int, int]:
        return self._logodds.shape

    def apply(self, local: LocalMap) -> None:
        """Bayesian update with one local map (own or received: the same function)."""
        self._pending.append(local.runs())
        self.updates += 1

    def _flush(self) -> None:
        p = self._pending
        runs = p[0] if len(p) == 1 else np.concatenate(p)
        p.clear()
        _add_runs(self._logodds, runs, L_MISS, L_HIT, L_MIN, L_MAX)

    def free(self) -> np.ndarray:
        return self.logodds < 0

    def occupied(self) -> np.ndarray:
        return self.logodds > 0

    def unknown(self) -> np.ndarray:
        return self.logodds == 0

    def known(self) -> np.ndarray:
        return self.logodds != 0

    def probability(self) -> np.ndarray:
        return probability(self.logodds)
