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

Copy elision (:class:`GridPool`, the simulator's): with the noise-free laser every scan of one
truth *passes* only free cells and *hits* only walls, so a cell only ever receives one kind of
increment, and adding k equal increments with clamping gives the same float whatever their
order. A grid is then a function of the *set* of local maps merged into it: grids of a team
that merged the same set are the same array (copied on write), and what is derived from a
grid (traversable cells, frontiers) is computed once per state for all of them. A team whose
flood reached everyone merges each scan once, not once per robot.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.sensing.laser import _axis, _cross

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


@kernel(cache=True, nogil=True)
def _rasterise(
    x0: int, y0: int, angles: NDArray[np.float64], ranges: NDArray[np.float64],
    max_cells: float, bx: int, by: int, free_p: NDArray[np.bool_], occ_p: NDArray[np.bool_],
) -> None:  # pragma: no cover
    ph, pw = free_p.shape
    for b in range(angles.shape[0]):
        r = ranges[b]
        sx, ddx = _axis(math.cos(angles[b]))
        sy, ddy = _axis(math.sin(angles[b]))
        kx = 0
        ky = 0
        cx = x0
        cy = y0
        free_p[cy - by, cx - bx] = True
        while True:
            t, kx, ky, cx, cy = _cross(kx, ky, cx, cy, sx, sy, ddx, ddy)
            inside = 0 <= cx - bx < pw and 0 <= cy - by < ph
            if t >= r:
                if r < max_cells and inside:
                    occ_p[cy - by, cx - bx] = True
                break
            if inside:
                free_p[cy - by, cx - bx] = True


@kernel(cache=True, nogil=True)
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


@kernel(cache=True, nogil=True)
def _add_runs(
    flat: NDArray[np.float32], width: int, runs: NDArray[np.int32], miss: np.float32,
    hit: np.float32, lo: np.float32, hi: np.float32,
) -> None:  # pragma: no cover - compiled
    """Add ``hit`` or ``miss`` to every cell of every run, in order, clamped to [lo, hi]."""
    for k in range(runs.shape[0]):
        base = runs[k, 0] * width
        d = hit if runs[k, 3] else miss
        for i in range(base + runs[k, 1], base + runs[k, 2]):
            v = flat[i] + d
            v = lo if v < lo else v
            flat[i] = hi if v > hi else v


_TAGS = itertools.count(1)
_M64 = (1 << 64) - 1
_M128 = (1 << 128) - 1


def _mix64(z: int) -> int:
    """splitmix64's finaliser: spreads a counter over 64 bits."""
    z = (z + 0x9E3779B97F4A7C15) & _M64
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _M64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _M64
    return z ^ (z >> 31)


def _tag(i: int) -> int:
    return (_mix64(2 * i) << 64) | _mix64(2 * i + 1)


@dataclass(eq=False)
class LocalMap:
    """What one scan saw: a box of the grid with the cells it passed and the cells it hit."""

    x0: int  # column of the box's first cell
    y0: int  # row of the box's first cell
    free: np.ndarray  # bool (rows, cols)
    occ: np.ndarray  # bool (rows, cols), disjoint from ``free``
    _runs: np.ndarray | None = field(default=None, repr=False)
    # a 128-bit tag, unique per local map: a grid's state is the sum of its maps' tags
    tag: int = field(default_factory=lambda: _tag(next(_TAGS)), repr=False, compare=False)

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


class _State:
    """One grid array shared by the grids in the same state, and what is derived from it."""

    __slots__ = ("arr", "derived", "key", "users")

    def __init__(self, arr: np.ndarray, key: int) -> None:
        self.arr = arr
        self.key = key
        self.users = 1
        self.derived: dict[Any, Any] = {}


class GridPool:
    """Grids of one simulated team that merged the same set of local maps share one array.

    Valid when every local map comes from one truth through the noise-free laser (see the
    module docstring); the simulator makes one per run. Counts what it saves.
    """

    def __init__(self) -> None:
        self.states: dict[int, _State] = {}
        self.merged = 0  # local maps added to an array
        self.shared = 0  # flushes answered by an existing state (no merge)
        self.copies = 0  # arrays copied because another grid still used them


class OccupancyGrid:
    """One robot's map: log-odds per cell, 0 = unknown (p = 0.5).

    :meth:`apply` queues a local map; reading :attr:`logodds` first adds whatever is queued.
    With a :class:`GridPool` the array may be shared with other grids in the same state:
    treat it as read-only (every update goes through :meth:`apply`).
    """

    def __init__(self, shape: tuple[int, int], pool: GridPool | None = None) -> None:
        self._logodds = np.zeros(shape, dtype=np.float32)
        self._pending: list[LocalMap] = []
        self.updates = 0
        self.key = 0  # sum of the tags of the local maps given (mod 2**128): the state
        self._derived: dict[Any, Any] = {}
        self.pool = pool
        self._state: _State | None = None
        if pool is not None:
            self._attach(pool)

    def _attach(self, pool: GridPool) -> None:
        st = pool.states.get(self.key)
        if st is None:
            st = pool.states[self.key] = _State(self._logodds, self.key)
        else:
            st.users += 1
            self._logodds = st.arr
        self._state = st

    def share(self, pool: GridPool) -> None:
        """Join ``pool`` (before anything was merged)."""
        if self.pool is not None or self.updates:
            raise ValueError("a grid joins a pool once, before any update")
        self.pool = pool
        self._attach(pool)

    @property
    def logodds(self) -> np.ndarray:
        if self._pending:
            self._flush()
        return self._logodds

    @property
    def sharers(self) -> int:
        """Grids in this grid's current state (itself included; 1 without a pool): how many
        robots a result cached with :meth:`derived` now would serve. Grids merge lazily, so
        a grid that was given the same maps but not read since is not counted yet."""
        if self._pending:
            self._flush()
        return self._state.users if self._state is not None else 1

    @property
    def pending(self) -> int:
        """Local maps given but not added yet."""
        return len(self._pending)

    @property
    def shape(self) -> tuple[int, int]:
        return self._logodds.shape

    def apply(self, local: LocalMap) -> None:
        """Bayesian update with one local map (own or received: the same function)."""
        self._pending.append(local)
        self.key = (self.key + local.tag) & _M128
        self.updates += 1

    def derived(self, name: Any, make: Callable[[np.ndarray], Any]) -> Any:
        """``make(logodds)``, computed once per grid state (and shared within a pool).
        The result must not be modified."""
        lo = self.logodds
        cache = self._state.derived if self._state is not None else self._derived
        got = cache.get(name)
        if got is None:
            got = cache[name] = make(lo)
        return got

    def _flush(self) -> None:
        pending = self._pending
        pool = self.pool
        st = self._state
        if pool is None or st is None:
            self._derived = {}
            self._merge(self._logodds, pending)
            return
        target = pool.states.get(self.key)
        if target is not None:  # another grid reached this state: share its array
            pending.clear()
            pool.shared += 1
            self._leave(pool, st)
            target.users += 1
            self._state = target
            self._logodds = target.arr
            return
        if st.users > 1:  # copy on write
            arr = st.arr.copy()
            pool.copies += 1
            self._leave(pool, st)
        else:
            arr = st.arr
            if pool.states.get(st.key) is st:
                del pool.states[st.key]
        pool.merged += len(pending)
        self._merge(arr, pending)
        new = pool.states[self.key] = _State(arr, self.key)
        self._state = new
        self._logodds = arr

    @staticmethod
    def _leave(pool: GridPool, st: _State) -> None:
        st.users -= 1
        if st.users == 0 and pool.states.get(st.key) is st:
            del pool.states[st.key]

    @staticmethod
    def _merge(arr: np.ndarray, pending: list[LocalMap]) -> None:
        runs = pending[0].runs() if len(pending) == 1 else np.concatenate(
            [m.runs() for m in pending])
        pending.clear()
        _add_runs(arr.reshape(-1), arr.shape[1], runs, L_MISS, L_HIT, L_MIN, L_MAX)

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
