"""MADGTA's decisions while the known graph is an open lattice: distances in closed form.

On a 4-connected grid world's lattice (:func:`~swarmex.planning.distance.lattice_structure`)
with no obstacle known yet, the shortest path between two cells is their lattice (L1)
distance ``|dx| + |dy|`` hops: that is exactly the hop count a breadth-first search gives, so
every utility below is the same float, computed by the same operations in the same order,
as the hop-row kernels of :mod:`swarmex.missions.traversal.policies` compute it (and those
match the numpy code of ``Madgta.utilities``). Nothing here needs a distance field, so a
decision costs no field per agent (the field route pays one shift of the whole map for every
move of every agent, which is what made large open maps quadratic).

Branch 3 (no vacant neighbour: the best of all vacant vertices) is searched region by region
instead of vertex by vertex. Each square region of the grid gets an upper bound
of the max-min utility of its vertices, from the same separable form: a rival's advantage
``a·L1(r, v) - b·L1(me, v)`` splits into an x part and a y part, each piecewise linear with
its kinks at the two agents' coordinates, so its maximum over a square is found among at
most four points per axis. Regions form a tree (``BLOCK``-square blocks, joined 2 x 2 level
by level up to the whole map) searched best first: a region is split only when its bound
is the largest left, and blocks are scanned in order of decreasing bound; the search stops
at the first region whose bound (plus a safety margin for rounding) is below the
best value found minus the tie tolerance of Algorithm 2: every vertex that could be tied at
the max-min is still found, in the same vertex order, so the policy's tie-breaks and its
draw from the generator are the same.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.missions.traversal.selection import (
    FAR,
    JOB,
    NUMPY,
    PICK,
    close1,
    column_stats,
    select_top,
    vacant_neighbours,
)

I64 = NDArray[np.int64]
F64 = NDArray[np.float64]

#: side of the squares the branch-3 search bounds and scans (cells)
BLOCK = 32


@kernel(cache=True, nogil=True)
def _l1(width: int, v: int, x: int, y: int) -> int:  # pragma: no cover - compiled
    vy, vx = divmod(v, width)
    return abs(vx - x) + abs(vy - y)


@kernel(cache=True, nogil=True)
def util_matrix(
    width: int, sx: I64, sy: I64, cands: I64, step: float, tpu_me: float, jt_me: float,
    tpu: F64, jt: F64,
) -> F64:  # pragma: no cover - compiled
    """``util[rival, candidate]`` as ``Madgta.utilities`` computes it; ``sx, sy`` hold my
    cell first, then the rivals'. With no rival: one row, minus my own cost."""
    r = sx.shape[0] - 1
    c = cands.shape[0]
    util = np.empty((max(r, 1), c))
    for j in range(c):
        mine = (_l1(width, cands[j], sx[0], sy[0]) * step) * tpu_me
        mine = mine + jt_me
        if r == 0:
            util[0, j] = -mine
            continue
        for i in range(r):
            theirs = (_l1(width, cands[j], sx[i + 1], sy[i + 1]) * step) * tpu[i]
            util[i, j] = theirs + jt[i] - mine
    return util


@kernel(cache=True, nogil=True)
def top_candidates(
    width: int, sx: I64, sy: I64, cands: I64, step: float, tpu_me: float, jt_me: float,
    tpu: F64, jt: F64,
) -> I64:  # pragma: no cover - compiled
    """``top_columns(util_matrix(...))`` without the matrix: one column at a time (a
    branch-3 tie can hold most of the map)."""
    r = sx.shape[0] - 1
    c = cands.shape[0]
    mins = np.empty(c)
    sums = np.empty(c)
    errs = np.empty(c)
    col = np.empty(max(r, 1))
    for j in range(c):
        mine = (_l1(width, cands[j], sx[0], sy[0]) * step) * tpu_me
        mine = mine + jt_me
        if r == 0:
            col[0] = -mine
        for i in range(r):
            theirs = (_l1(width, cands[j], sx[i + 1], sy[i + 1]) * step) * tpu[i]
            col[i] = theirs + jt[i] - mine
        if not column_stats(col, j, mins, sums, errs):
            return np.full(1, -1, dtype=np.int64)
    return select_top(mins, sums, errs)


@kernel(cache=True, nogil=True)
def near_choice(
    width: int, sx: I64, sy: I64, indptr: I64, indices: NDArray[np.int32], here: int,
    status: NDArray[np.int32], reserved: NDArray[np.int32], me: int, step: float,
    tpu_me: float, jt_me: float, tpu: F64, jt: F64,
) -> tuple[int, I64]:  # pragma: no cover - compiled
    """Branch 2 in one call, as ``policies._near_choice`` does it from hop rows: ``(FAR,
    [])`` with no vacant neighbour, ``(PICK, tied)`` for the final draw, ``(NUMPY, W)``
    when numpy must add the sums."""
    cands = vacant_neighbours(indptr, indices, here, status, reserved, me)
    if cands.shape[0] == 0:
        return FAR, cands
    top = top_candidates(width, sx, sy, cands, step, tpu_me, jt_me, tpu, jt)
    if top[0] < 0:
        return NUMPY, cands
    return PICK, cands[top]


@kernel(cache=True, nogil=True)
def decide_near(
    width: int, loc: I64, me: int, indptr: I64, indices: NDArray[np.int32],
    status: NDArray[np.int32], reserved: NDArray[np.int32], step: float, tpu: F64, jt: F64,
    with_rivals: bool,
) -> tuple[int, I64, I64, I64, I64]:  # pragma: no cover - compiled
    """Branches 1 and 2 of a decision in one call, from the belief's arrays: ``(JOB, ...)``
    when my own vertex is not in KM, else :func:`near_choice`'s ``(code, picks)``; plus the
    rivals (ids of the other agents whose position is known; none for ``with_rivals``
    False, the nearest-vertex baseline) and ``sx, sy`` (my cell, then theirs)."""
    here = loc[me]
    owner = reserved[here]
    none = np.empty(0, dtype=np.int64)
    if status[here] == 0 and (owner == 0 or owner == me):
        return JOB, none, none, none, none
    r = 0
    rivals = np.empty(loc.shape[0], dtype=np.int64)
    if with_rivals:
        for a in range(loc.shape[0]):
            if loc[a] >= 0 and a != me:
                rivals[r] = a
                r += 1
    rivals = rivals[:r]
    sx = np.empty(r + 1, dtype=np.int64)
    sy = np.empty(r + 1, dtype=np.int64)
    sy[0], sx[0] = divmod(here, width)
    tpu_r = np.empty(r)
    jt_r = np.empty(r)
    for i in range(r):
        sy[i + 1], sx[i + 1] = divmod(loc[rivals[i]], width)
        tpu_r[i] = tpu[rivals[i]]
        jt_r[i] = jt[rivals[i]]
    jt_me = jt[me] if with_rivals else 0.0
    code, picks = near_choice(width, sx, sy, indptr, indices, here, status, reserved, me,
                              step, tpu[me], jt_me, tpu_r, jt_r)
    return code, picks, rivals, sx, sy


@kernel(cache=True, nogil=True)
def distances(width: int, source: int, vertices: I64, step: float) -> F64:  # pragma: no cover
    """``KnownGraph.distances(source, vertices)`` on the open lattice."""
    sy, sx = divmod(source, width)
    out = np.empty(vertices.shape[0])
    for i in range(vertices.shape[0]):
        out[i] = _l1(width, vertices[i], sx, sy) * step
    return out


@kernel(cache=True, nogil=True)
def _axis_max(lo: int, hi: int, r: int, m: int, a: float, b: float) -> float:  # pragma: no cover
    """Max over integers ``x`` in ``[lo, hi]`` of ``a|x - r| - b|x - m|``: piecewise linear
    with kinks at ``r`` and ``m``, so the max is at an end or at a kink."""
    best = a * abs(lo - r) - b * abs(lo - m)
    for x in (hi, min(max(r, lo), hi), min(max(m, lo), hi)):
        v = a * abs(x - r) - b * abs(x - m)
        if v > best:
            best = v
    return best


@kernel(cache=True, nogil=True)
def _axis_gap(lo: int, hi: int, x: int) -> int:  # pragma: no cover - compiled
    """Distance from ``x`` to the interval ``[lo, hi]``."""
    if x < lo:
        return lo - x
    if x > hi:
        return x - hi
    return 0


@kernel(cache=True, nogil=True)
def tree_nodes(width: int, height: int, block: int) -> int:  # pragma: no cover - compiled
    """How many regions the block tree of :func:`far_choice` has (its flags' size)."""
    nx = (width + block - 1) // block
    ny = (height + block - 1) // block
    total = nx * ny
    while nx > 1 or ny > 1:
        nx = (nx + 1) // 2
        ny = (ny + 1) // 2
        total += nx * ny
    return total


@kernel(cache=True, nogil=True)
def _rect_bound(
    x0: int, x1: int, y0: int, y1: int, sx: I64, sy: I64, klass: I64, ctpu: F64, cjt: F64,
    step: float, tpu_me: float, jt_me: float, margin: float,
) -> float:  # pragma: no cover - compiled
    """Upper bound of the max-min utility over the cells of ``[x0, x1] x [y0, y1]``."""
    r = sx.shape[0] - 1
    xm, ym = sx[0], sy[0]
    if r == 0 or ctpu.shape[0] == 0:
        d = _axis_gap(x0, x1, xm) + _axis_gap(y0, y1, ym)
        return -((d * step) * tpu_me + jt_me) + margin
    b = step * tpu_me
    u = np.inf
    for i in range(r):
        k = klass[i]
        a = step * ctpu[k]
        v = (_axis_max(x0, x1, sx[i + 1], xm, a, b) + _axis_max(y0, y1, sy[i + 1], ym, a, b)
             + cjt[k] - jt_me)
        if v < u:
            u = v
    return u + margin


@kernel(cache=True, nogil=True)
def _push(keys: F64, ids: I64, size: int, key: float, node: int) -> int:  # pragma: no cover
    """Max-heap push; returns the new size."""
    i = size
    while i > 0:
        p = (i - 1) // 2
        if keys[p] >= key:
            break
        keys[i] = keys[p]
        ids[i] = ids[p]
        i = p
    keys[i] = key
    ids[i] = node
    return size + 1


@kernel(cache=True, nogil=True)
def _pop(keys: F64, ids: I64, size: int) -> int:  # pragma: no cover - compiled
    """Max-heap pop of the root (read keys[0], ids[0] first); returns the new size."""
    size -= 1
    key = keys[size]
    node = ids[size]
    i = 0
    while True:
        c = 2 * i + 1
        if c >= size:
            break
        if c + 1 < size and keys[c + 1] > keys[c]:
            c += 1
        if keys[c] <= key:
            break
        keys[i] = keys[c]
        ids[i] = ids[c]
        i = c
    if size > 0:
        keys[i] = key
        ids[i] = node
    return size


@kernel(cache=True, nogil=True)
def _axis_sums(n: int, coords: I64, klass: I64, ctpu: F64, step: float, b: float,
               mine: int) -> F64:  # pragma: no cover - compiled
    """``out[x] = sum_i a_i |x - coords[i+1]| - r b |x - mine|`` for ``x < n``: one axis of the
    sum over rivals of the utility, which is separable on the lattice (``a_i = step`` times
    rival ``i``'s class's time per unit, ``b = step`` times mine)."""
    r = coords.shape[0] - 1
    out = np.empty(n)
    for x in range(n):
        v = -r * b * abs(x - mine)
        for i in range(r):
            v += step * ctpu[klass[i]] * abs(x - coords[i + 1])
        out[x] = v
    return out


@kernel(cache=True, nogil=True)
def _level_maxima(vals: F64, block: int, counts: I64, levels: int) -> tuple[F64, I64]:
    """Maxima of ``vals`` over the tree's aligned segments, level by level: segment ``i`` of
    level ``l`` holds cells ``[i, i + 1) * (block << l)``; ``(flat, offsets)``."""
    off = np.empty(levels + 1, dtype=np.int64)
    off[0] = 0
    for lev in range(levels):
        off[lev + 1] = off[lev] + counts[lev]
    flat = np.empty(off[levels])
    n = vals.shape[0]
    for i in range(counts[0]):
        m = -np.inf
        for x in range(i * block, min(n, (i + 1) * block)):
            m = max(m, vals[x])
        flat[i] = m
    for lev in range(1, levels):
        for i in range(counts[lev]):
            m = flat[off[lev - 1] + 2 * i]
            if 2 * i + 1 < counts[lev - 1]:
                m = max(m, flat[off[lev - 1] + 2 * i + 1])
            flat[off[lev] + i] = m
    return flat, off


@kernel(cache=True, nogil=True)
def _scan_block(
    x0: int, x1: int, y0: int, y1: int, width: int, sx: I64, sy: I64, klass: I64,
    ctpu: F64, cjt: F64, status: NDArray[np.int32], reserved: NDArray[np.int32], me: int,
    step: float, tpu_me: float, jt_me: float, far: I64, mins: F64, nf: int, best: float,
    found: int, near: I64, cut: I64, hk: I64,
) -> tuple[int, float, int, bool]:  # pragma: no cover - compiled
    """Every cell of a leaf block: each vacant one's max-min utility, the ones that may be
    tied at the best appended to ``far``/``mins``; ``(nf, best, found, live)``."""
    r = sx.shape[0] - 1
    nk = ctpu.shape[0]
    xm, ym = sx[0], sy[0]
    # a rival farther from every cell of the block than some rival of its class is
    # from the block's farthest cell is never the nearest of its class there
    for k in range(nk):
        cut[k] = 1 << 62
    for i in range(r):
        far_d = max(abs(x0 - sx[i + 1]), abs(x1 - sx[i + 1])) + max(
            abs(y0 - sy[i + 1]), abs(y1 - sy[i + 1]))
        if far_d < cut[klass[i]]:
            cut[klass[i]] = far_d
    nn = 0
    for i in range(r):
        if _axis_gap(x0, x1, sx[i + 1]) + _axis_gap(y0, y1, sy[i + 1]) <= cut[klass[i]]:
            near[nn] = i
            nn += 1
    live = False
    for y in range(y0, y1 + 1):
        for x in range(x0, x1 + 1):
            v = y * width + x
            if status[v] != 0:
                continue
            live = True
            owner = reserved[v]
            if owner != 0 and owner != me:
                continue
            found = 1
            hm = abs(x - xm) + abs(y - ym)
            mine = (hm * step) * tpu_me
            mine = mine + jt_me
            if nk == 0:
                m = -mine
            else:
                for k in range(nk):
                    hk[k] = 1 << 62
                for j in range(nn):
                    i = near[j]
                    d = abs(x - sx[i + 1]) + abs(y - sy[i + 1])
                    if d < hk[klass[i]]:
                        hk[klass[i]] = d
                m = np.inf
                for k in range(nk):
                    theirs = (hk[k] * step) * ctpu[k]
                    u = theirs + cjt[k] - mine
                    if u < m:
                        m = u
            if m > best:
                best = m
            if m >= best - 1e-9 * (1.0 + abs(best)):
                far[nf] = v
                mins[nf] = m
                nf += 1
    return nf, best, found, live


@kernel(cache=True, nogil=True)
def far_choice(
    width: int, height: int, sx: I64, sy: I64, klass: I64, ctpu: F64, cjt: F64,
    status: NDArray[np.int32], reserved: NDArray[np.int32], me: int, step: float,
    tpu_me: float, jt_me: float, block: int, far: I64, mins: F64, dead: NDArray[np.uint8],
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """Branch 3 on the open lattice (``fartiles.far_tiles`` on hop fields) by a best-first
    search over a tree of bounded regions.

    Returns ``(found, tied, scanned)``: whether any vacant vertex exists (0 or more), how
    many vertices are left for the tie-break by sum (in ascending order in ``far[:tied]``)
    and how many vertices were looked at. ``far[:tied]`` holds every vertex tied at the
    max-min that could win Algorithm 2's tie-break by the sum over rivals: with rivals, the
    tied vertices whose sum is certainly below the best tied one's are left out, and
    :func:`top_candidates` over the rest picks what it would pick over them all.
    ``klass[i]`` is rival ``i``'s (speed, job time) class, ``ctpu, cjt`` the classes'
    values; ``sx, sy`` hold my cell first, then the rivals'.

    The leaves are ``block``-square blocks of cells; each level above joins 2 x 2 regions,
    up to one region holding the map (:func:`tree_nodes` regions in all). Regions are taken
    in order of decreasing bound of the max-min (a heap); a leaf is scanned, an inner
    region's children are bounded and queued. The search stops at the first region whose
    bound is below the best utility found minus the tie tolerance, so a decision costs the
    regions near its answer, not the whole map. ``dead`` (this belief's flags, reset when a
    job is undone) marks regions with every vertex done: skipped.

    Once no region left can beat the best max-min (their bounds are all at it: a tie over
    regions, as when the team stands together and most of the map ties), the search goes
    on by the bound of the *sum* over rivals instead, which is separable on the lattice (a
    maximum over a region is a maximum per axis): a region whose sum cannot reach the best
    tied vertex's is skipped unscanned. Issue: 64 agents on one nest of a 1000 x 1000 grid
    tied 730,000 vertices per decision, of which about 1,000 had the best sum; each
    decision scanned and summed them all (170 ms).
    """
    found, nt, scanned, sound = _far_search(
        width, height, sx, sy, klass, ctpu, cjt, status, reserved, me, step, tpu_me, jt_me,
        block, far, mins, dead, True)
    if not sound:  # the best moved while the sums pruned: the plain search, once
        found, nt, again, _ = _far_search(
            width, height, sx, sy, klass, ctpu, cjt, status, reserved, me, step, tpu_me,
            jt_me, block, far, mins, dead, False)
        scanned += again
    return found, nt, scanned


@kernel(cache=True, nogil=True)
def _far_search(
    width: int, height: int, sx: I64, sy: I64, klass: I64, ctpu: F64, cjt: F64,
    status: NDArray[np.int32], reserved: NDArray[np.int32], me: int, step: float,
    tpu_me: float, jt_me: float, block: int, far: I64, mins: F64, dead: NDArray[np.uint8],
    by_sums: bool,
) -> tuple[int, int, int, bool]:  # pragma: no cover - compiled
    """:func:`far_choice`'s search; ``by_sums`` False never prunes by the sum. The last
    value is False when a pruning by the sum may have been unsound (the best max-min rose
    past its tolerance after it began, or the vertex whose sum pruned left the tie)."""
    r = sx.shape[0] - 1
    nk = ctpu.shape[0]
    xm, ym = sx[0], sy[0]
    # rounding between the real-valued bound and the floats of a vertex's utility is a few
    # ulps of the largest term; the margin is far above that and far below one hop
    amax = step * tpu_me
    cmax = abs(jt_me)
    for k in range(nk):
        amax = max(amax, step * ctpu[k])
        cmax = max(cmax, abs(cjt[k]))
    margin = 1e-9 * (1.0 + amax * (width + height) + cmax)
    # the same for a sum over r rivals, each term a utility
    smargin = (r + 1) * margin
    # the rounding itself, with room (90 ulps of the largest term): a bound minus its
    # margin within this of the best cannot hide a better vertex
    rnd = 1e-14 * (1.0 + amax * (width + height) + cmax)
    # the tree's levels: level 0 = leaves; off[l] = first flag of level l
    nxs = np.empty(64, dtype=np.int64)
    nys = np.empty(64, dtype=np.int64)
    off = np.empty(64, dtype=np.int64)
    nxs[0] = (width + block - 1) // block
    nys[0] = (height + block - 1) // block
    off[0] = 0
    top = 0
    while nxs[top] > 1 or nys[top] > 1:
        off[top + 1] = off[top] + nxs[top] * nys[top]
        nxs[top + 1] = (nxs[top] + 1) // 2
        nys[top + 1] = (nys[top] + 1) // 2
        top += 1
    total = off[top] + 1
    keys = np.empty(total)
    ids = np.empty(total, dtype=np.int64)
    ubm = np.empty(total)  # each queued region's bound of the max-min
    size = 0
    if not dead[off[top]]:
        size = _push(keys, ids, size, np.inf, off[top])
        ubm[off[top]] = np.inf
    best = -np.inf
    found = 0
    nf = 0
    scanned = 0
    near = np.empty(r, dtype=np.int64)  # the rivals that can be nearest in a block
    cut = np.empty(max(nk, 1), dtype=np.int64)
    hk = np.empty(max(nk, 1), dtype=np.int64)
    # the sum phase: per-axis sums over rivals, their maxima per region, the best tied
    # vertex's sum and max-min, and the best max-min when the phase began
    summing = False
    xsum = np.empty(0)
    ysum = np.empty(0)
    xmx = np.empty(0)
    ymx = np.empty(0)
    xo = np.empty(0, dtype=np.int64)
    yo = np.empty(0, dtype=np.int64)
    csum = 0.0
    best_sum = -np.inf
    bs_m = -np.inf
    at_switch = 0.0
    while size > 0:
        key = keys[0]
        node = ids[0]
        size = _pop(keys, ids, size)
        tie = 1e-9 * (1.0 + abs(best))
        ub = ubm[node]
        if summing:
            # no region left can reach the best tied sum (within every rounding): done
            if key + smargin < best_sum - smargin - 2e-9 * (1.0 + abs(best_sum)):
                break
            if ub < best - tie:
                continue
        else:
            if found and ub < best - tie:
                break
            if by_sums and r > 0 and found and ub - margin <= best + rnd:
                # no region left can beat the best max-min (not even within its tie
                # tolerance: a better one would move the tie window): go on by the sum
                summing = True
                at_switch = best
                xsum = _axis_sums(width, sx, klass, ctpu, step, step * tpu_me, xm)
                ysum = _axis_sums(height, sy, klass, ctpu, step, step * tpu_me, ym)
                xmx, xo = _level_maxima(xsum, block, nxs, top + 1)
                ymx, yo = _level_maxima(ysum, block, nys, top + 1)
                csum = -r * jt_me
                for i in range(r):
                    csum += cjt[klass[i]]
                best_sum, bs_m = _best_tied_sum(far, mins, 0, nf, best - tie, width, xsum,
                                                ysum, csum, best_sum, bs_m)
                queued = ids[:size].copy()
                size = 0
                for nd in queued:
                    size = _push(keys, ids, size, _sum_bound(
                        nd, off, nxs, top, xmx, xo, ymx, yo, csum), nd)
                size = _push(keys, ids, size, _sum_bound(
                    node, off, nxs, top, xmx, xo, ymx, yo, csum), node)
                continue
        lev = 0
        while lev < top and node >= off[lev + 1]:
            lev += 1
        idx = node - off[lev]
        by, bx = divmod(idx, nxs[lev])
        side = block << lev
        if lev > 0:  # bound the children and queue them
            for cy in range(2 * by, min(2 * by + 2, nys[lev - 1])):
                for cx in range(2 * bx, min(2 * bx + 2, nxs[lev - 1])):
                    child = off[lev - 1] + cy * nxs[lev - 1] + cx
                    if dead[child]:
                        continue
                    half = side >> 1
                    x0, y0 = cx * half, cy * half
                    x1, y1 = min(width, x0 + half) - 1, min(height, y0 + half) - 1
                    bound = _rect_bound(x0, x1, y0, y1, sx, sy, klass, ctpu, cjt, step,
                                        tpu_me, jt_me, margin)
                    ubm[child] = bound
                    if not summing:
                        size = _push(keys, ids, size, bound, child)
                    elif bound >= best - tie:
                        size = _push(keys, ids, size, _sum_bound(
                            child, off, nxs, top, xmx, xo, ymx, yo, csum), child)
            continue
        x0, y0 = bx * block, by * block
        x1, y1 = min(width, x0 + block) - 1, min(height, y0 + block) - 1
        first = nf
        nf, best, found, live = _scan_block(
            x0, x1, y0, y1, width, sx, sy, klass, ctpu, cjt, status, reserved, me, step,
            tpu_me, jt_me, far, mins, nf, best, found, near, cut, hk)
        scanned += (x1 - x0 + 1) * (y1 - y0 + 1)
        if summing:
            best_sum, bs_m = _best_tied_sum(far, mins, first, nf,
                                            best - 1e-9 * (1.0 + abs(best)), width, xsum,
                                            ysum, csum, best_sum, bs_m)
        if not live:  # every vertex done: flag the block, and each region now all dead
            dead[node] = 1
            lev, cx, cy = 0, bx, by
            while lev < top:
                px, py = cx // 2, cy // 2
                alive = False
                for yy in range(2 * py, min(2 * py + 2, nys[lev])):
                    for xx in range(2 * px, min(2 * px + 2, nxs[lev])):
                        if not dead[off[lev] + yy * nxs[lev] + xx]:
                            alive = True
                if alive:
                    break
                lev += 1
                cx, cy = px, py
                dead[off[lev] + cy * nxs[lev] + cx] = 1
    # a pruning by the sum stood on the best max-min at the switch and on the vertex whose
    # sum pruned: both must still hold (else the caller searches again without it)
    sound = not summing or (best <= at_switch + 1e-9 * (1.0 + abs(at_switch))
                            and close1(bs_m, best))
    if not found:
        return 0, 0, scanned, sound
    nt = 0
    for j in range(nf):
        if close1(mins[j], best):
            far[nt] = far[j]
            nt += 1
    far[:nt].sort()
    return found, nt, scanned, sound


@kernel(cache=True, nogil=True)
def _best_tied_sum(far: I64, mins: F64, lo: int, hi: int, least: float, width: int,
                   xsum: F64, ysum: F64, csum: float, best_sum: float,
                   bs_m: float) -> tuple[float, float]:  # pragma: no cover - compiled
    """The best sum over rivals (from the per-axis sums) among ``far[lo:hi]`` whose max-min
    is at least ``least`` (tied), with that vertex's max-min: ``(best_sum, bs_m)`` updated."""
    for j in range(lo, hi):
        if mins[j] >= least:
            vy, vx = divmod(far[j], width)
            sv = xsum[vx] + ysum[vy] + csum
            if sv > best_sum:
                best_sum, bs_m = sv, mins[j]
    return best_sum, bs_m


@kernel(cache=True, nogil=True)
def _sum_bound(node: int, off: I64, nxs: I64, top: int, xmx: F64, xo: I64, ymx: F64,
               yo: I64, csum: float) -> float:  # pragma: no cover - compiled
    """The maximum over region ``node`` of the (real-valued) sum over rivals of the
    utility: the per-axis maxima of its segments, plus the constant part."""
    lev = 0
    while lev < top and node >= off[lev + 1]:
        lev += 1
    by, bx = divmod(node - off[lev], nxs[lev])
    return xmx[xo[lev] + bx] + ymx[yo[lev] + by] + csum
