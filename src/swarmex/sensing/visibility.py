"""Line of sight among polygon walls: compiled segment tests against obstacle edges.

A target is seen from a viewpoint when it lies within the sensor range and the straight
segment between them touches no obstacle edge (walls block sight; grazing a corner blocks it
too, the same closed-set rule as collision checks in :mod:`swarmex.worlds.polygon`). Both
endpoints are free points, so "crosses no boundary segment" is equivalent to "misses every
obstacle".

Why numba rather than shapely here: coverage needs tens of millions of point-to-point
visibility tests per run (every raster cell near every viewpoint along every edge), each of
which is a handful of multiplications; a GEOS call per test costs microseconds of overhead.
Two tricks keep the count low: each cell remembers the wall that last blocked it (the same
wall usually hides it from the next viewpoint a few units on), and with a finite range only
edges whose bounding box meets the range square are tested.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel


@kernel(cache=True, inline="always")
def _orient(
    ax: float, ay: float, bx: float, by: float, cx: float, cy: float
) -> float:  # pragma: no cover - compiled
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


@kernel(cache=True)
def segments_touch(
    px: float, py: float, qx: float, qy: float, ax: float, ay: float, bx: float, by: float
) -> bool:  # pragma: no cover - compiled
    """Closed test: do segments pq and ab share at least one point?"""
    if max(px, qx) < min(ax, bx) or max(ax, bx) < min(px, qx):
        return False
    if max(py, qy) < min(ay, by) or max(ay, by) < min(py, qy):
        return False
    o1 = _orient(px, py, qx, qy, ax, ay)
    o2 = _orient(px, py, qx, qy, bx, by)
    o3 = _orient(ax, ay, bx, by, px, py)
    o4 = _orient(ax, ay, bx, by, qx, qy)
    if o1 == 0.0 and o2 == 0.0:
        if px == qx and py == qy:  # pq is a point: touching means lying on ab
            return o3 == 0.0
        return True  # collinear with overlapping bounding boxes (checked above)
    return o1 * o2 <= 0.0 and o3 * o4 <= 0.0


@kernel(cache=True)
def first_blocker(
    px: float, py: float, qx: float, qy: float, edges: NDArray[np.float64],
    local: NDArray[np.int64], n_local: int, hint: int,
) -> int:  # pragma: no cover - compiled
    """Index of an edge blocking segment pq (the hinted one first), or -1."""
    if hint >= 0:
        e = edges[hint]
        if segments_touch(px, py, qx, qy, e[0], e[1], e[2], e[3]):
            return hint
    for j in range(n_local):
        k = local[j]
        if k == hint:
            continue
        e = edges[k]
        if segments_touch(px, py, qx, qy, e[0], e[1], e[2], e[3]):
            return k
    return -1


@kernel(cache=True)
def segments_blocked(
    a: NDArray[np.float64], b: NDArray[np.float64], edges: NDArray[np.float64]
) -> NDArray[np.bool_]:  # pragma: no cover - compiled
    """Vector form: for each row i, does segment a[i]–b[i] touch any edge?"""
    m = a.shape[0]
    out = np.zeros(m, dtype=np.bool_)
    local = np.arange(edges.shape[0])
    for i in range(m):
        out[i] = first_blocker(a[i, 0], a[i, 1], b[i, 0], b[i, 1], edges, local,
                               edges.shape[0], -1) >= 0
    return out


@kernel(cache=True)
def _sweep_cell(
    ax: float, ay: float, bx: float, by: float, m: int, rng_r: float, cx: float, cy: float,
    edges: NDArray[np.float64], local: NDArray[np.int64], n_local: int, hint: int,
) -> tuple[bool, int]:
    # pragma: no cover - compiled
    """Is cell centre c seen from some viewpoint p_s = a + s/m (b − a)? → (seen, blocker).

    The viewpoints in range form one run s_lo..s_hi (a disc meets a line in an interval).
    A wall's shadow is convex, so the viewpoints one wall hides also form a run: once a wall
    hides p_s, a binary search finds the end of its run and the scan jumps past it. A cell
    hidden along the whole segment therefore costs a few tests per wall, not per viewpoint.
    """
    dx, dy = bx - ax, by - ay
    s_lo, s_hi = 0, m
    if np.isfinite(rng_r):
        # |a + t d − c|² ≤ r²  ⇔  A t² + B t + C ≤ 0
        fx, fy = ax - cx, ay - cy
        qa = dx * dx + dy * dy
        qb = 2.0 * (fx * dx + fy * dy)
        qc = fx * fx + fy * fy - rng_r * rng_r
        if qa == 0.0:
            if qc > 0.0:
                return False, hint
        else:
            disc = qb * qb - 4.0 * qa * qc
            if disc < 0.0:
                return False, hint
            sq = np.sqrt(disc)
            t0 = (-qb - sq) / (2.0 * qa)
            t1 = (-qb + sq) / (2.0 * qa)
            s_lo = max(0, int(np.ceil(t0 * m - 1e-9)))
            s_hi = min(m, int(np.floor(t1 * m + 1e-9)))
            # guard the rounding at both ends with the exact distance test
            while s_lo <= s_hi and ((ax + s_lo / m * dx - cx) ** 2
                                    + (ay + s_lo / m * dy - cy) ** 2) > rng_r * rng_r:
                s_lo += 1
            while s_hi >= s_lo and ((ax + s_hi / m * dx - cx) ** 2
                                    + (ay + s_hi / m * dy - cy) ** 2) > rng_r * rng_r:
                s_hi -= 1
            if s_lo > s_hi:
                return False, hint
    ex = ax + s_hi / m * dx
    ey = ay + s_hi / m * dy
    if hint >= 0:
        e = edges[hint]
        if (segments_touch(ax + s_lo / m * dx, ay + s_lo / m * dy, cx, cy,
                           e[0], e[1], e[2], e[3])
                and segments_touch(ex, ey, cx, cy, e[0], e[1], e[2], e[3])):
            return False, hint  # both ends of the run in this wall's shadow
    k = hint
    s = s_lo
    while s <= s_hi:
        px = ax + s / m * dx
        py = ay + s / m * dy
        kk = first_blocker(px, py, cx, cy, edges, local, n_local, k)
        if kk < 0:
            return True, k
        k = kk
        e = edges[kk]
        if segments_touch(ex, ey, cx, cy, e[0], e[1], e[2], e[3]):
            return False, k  # p_s and the last viewpoint both hidden by kk: all between too
        lo, hi = s, s_hi  # kk hides p_lo, not p_hi: find where its shadow run ends
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if segments_touch(ax + mid / m * dx, ay + mid / m * dy, cx, cy,
                              e[0], e[1], e[2], e[3]):
                lo = mid
            else:
                hi = mid
        s = hi
    return False, k


@kernel(cache=True)
def _shadowed(
    ax: float, ay: float, bx: float, by: float, qx: float, qy: float, e: NDArray[np.float64]
) -> bool:  # pragma: no cover - compiled
    """Does wall edge e hide point q from both a and b (hence from all of segment ab)?"""
    return (segments_touch(ax, ay, qx, qy, e[0], e[1], e[2], e[3])
            and segments_touch(bx, by, qx, qy, e[0], e[1], e[2], e[3]))


@kernel(cache=True)
def sweep_segment(
    ax: float, ay: float, bx: float, by: float, rng_r: float, spacing: float, x0: float,
    y0: float, h: float, free: NDArray[np.bool_], seen_at: NDArray[np.int64],
    blocker: NDArray[np.int64], block_unseen: NDArray[np.int64],
    block_hint: NDArray[np.int64], bs: int, edges: NDArray[np.float64], t_now: int,
) -> int:  # pragma: no cover - compiled
    """Sense along segment a→b: viewpoints every ``spacing``; mark visible free cells.

    A cell is seen when some viewpoint is within range and has line of sight to its centre.
    The shadow a wall edge casts from a point is convex, which gives two exact shortcuts:
    a wall that hides a cell from both ends of the segment hides it from every viewpoint
    between, and a wall that hides the four corners of a ``bs`` × ``bs`` block of cells from
    both ends hides the whole block. Each cell and block remembers the wall that last hid it,
    and tries it first. ``seen_at`` (step first seen, -1 never) and ``block_unseen`` are
    updated in place. Returns how many cells became seen.
    """
    ny, nx = free.shape
    nby, nbx = block_unseen.shape
    length = np.hypot(bx - ax, by - ay)
    m = max(1, int(np.ceil(length / spacing)))
    finite = np.isfinite(rng_r)
    r2 = rng_r * rng_r if finite else 0.0
    local = np.empty(edges.shape[0], dtype=np.int64)
    n_local = 0
    if finite:
        rx0, rx1 = min(ax, bx) - rng_r, max(ax, bx) + rng_r
        ry0, ry1 = min(ay, by) - rng_r, max(ay, by) + rng_r
        for k in range(edges.shape[0]):
            e = edges[k]
            if (min(e[0], e[2]) <= rx1 and max(e[0], e[2]) >= rx0
                    and min(e[1], e[3]) <= ry1 and max(e[1], e[3]) >= ry0):
                local[n_local] = k
                n_local += 1
        bi0 = max(0, int(np.floor((rx0 - x0) / (h * bs))))
        bi1 = min(nbx - 1, int(np.floor((rx1 - x0) / (h * bs))))
        bj0 = max(0, int(np.floor((ry0 - y0) / (h * bs))))
        bj1 = min(nby - 1, int(np.floor((ry1 - y0) / (h * bs))))
    else:
        for k in range(edges.shape[0]):
            local[k] = k
        n_local = edges.shape[0]
        bi0, bi1, bj0, bj1 = 0, nbx - 1, 0, nby - 1
    dx, dy = bx - ax, by - ay
    l2 = dx * dx + dy * dy
    half_diag = 0.7072 * bs * h
    new = 0
    for bj in range(bj0, bj1 + 1):
        for bi in range(bi0, bi1 + 1):
            if block_unseen[bj, bi] == 0:
                continue
            qx0 = x0 + bi * bs * h
            qy0 = y0 + bj * bs * h
            qx1 = qx0 + bs * h
            qy1 = qy0 + bs * h
            if finite:
                mx, my = 0.5 * (qx0 + qx1), 0.5 * (qy0 + qy1)
                u = 0.0 if l2 == 0.0 else min(1.0, max(0.0, ((mx - ax) * dx + (my - ay) * dy) / l2))
                dd = np.sqrt((ax + u * dx - mx) ** 2 + (ay + u * dy - my) ** 2)
                if dd - half_diag > rng_r:
                    continue
            hb = block_hint[bj, bi]
            if hb >= 0:
                e = edges[hb]
                if (_shadowed(ax, ay, bx, by, qx0, qy0, e)
                        and _shadowed(ax, ay, bx, by, qx1, qy0, e)
                        and _shadowed(ax, ay, bx, by, qx0, qy1, e)
                        and _shadowed(ax, ay, bx, by, qx1, qy1, e)):
                    continue
            last = -1
            for j in range(bj * bs, min(ny, (bj + 1) * bs)):
                cy = y0 + (j + 0.5) * h
                for i in range(bi * bs, min(nx, (bi + 1) * bs)):
                    if seen_at[j, i] >= 0 or not free[j, i]:
                        continue
                    cx = x0 + (i + 0.5) * h
                    if finite:
                        u = 0.0 if l2 == 0.0 else min(
                            1.0, max(0.0, ((cx - ax) * dx + (cy - ay) * dy) / l2))
                        if (ax + u * dx - cx) ** 2 + (ay + u * dy - cy) ** 2 > r2:
                            continue
                    seen, k = _sweep_cell(ax, ay, bx, by, m, rng_r, cx, cy, edges, local,
                                          n_local, blocker[j, i])
                    if seen:
                        seen_at[j, i] = t_now
                        block_unseen[bj, bi] -= 1
                        new += 1
                    else:
                        blocker[j, i] = k
                        last = k
            if last >= 0:
                block_hint[bj, bi] = last
    return new


@kernel(cache=True)
def first_sighting(
    ax: float, ay: float, bx: float, by: float, gx: float, gy: float, rng_r: float,
    spacing: float, edges: NDArray[np.float64],
) -> float:  # pragma: no cover
    """Fraction t ∈ [0, 1] of the first viewpoint along a→b that sees g, or -1."""
    length = np.hypot(bx - ax, by - ay)
    m = max(1, int(np.ceil(length / spacing)))
    local = np.arange(edges.shape[0])
    for s in range(m + 1):
        t = s / m
        px = ax + t * (bx - ax)
        py = ay + t * (by - ay)
        if (gx - px) ** 2 + (gy - py) ** 2 > rng_r * rng_r:
            continue
        if first_blocker(px, py, gx, gy, edges, local, edges.shape[0], -1) < 0:
            return t
    return -1.0


def line_of_sight(edges: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """For each row: is the segment a[i]–b[i] free of every wall edge?"""
    a = np.ascontiguousarray(np.asarray(a, dtype=np.float64).reshape(-1, 2))
    b = np.ascontiguousarray(np.asarray(b, dtype=np.float64).reshape(-1, 2))
    if edges.shape[0] == 0:
        return np.ones(len(a), dtype=bool)
    return ~segments_blocked(a, b, np.ascontiguousarray(edges))
