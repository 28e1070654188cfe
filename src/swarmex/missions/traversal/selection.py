"""Compiled pieces of Algorithm 2's selection shared by the policy's kernels.

:func:`top_columns` is GetBestNode on a utility matrix (max-min, then the sum over rivals)
for the cases where a compiled loop provably gives numpy's answer; :func:`vacant_neighbours`
is branch 2's W. Both the hop-row kernels of :mod:`swarmex.missions.traversal.policies` and
the lattice-distance kernels of :mod:`swarmex.missions.traversal.lattice` use them, so the
two routes choose the same way by construction.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel

#: outcomes of branch 2's compiled choice: no vacant neighbour (branch 3), candidates to draw
#: from, or candidates whose utilities numpy must rank (sums too close to call); and JOB:
#: branch 1 (my own vertex is vacant)
FAR, PICK, NUMPY, JOB = 0, 1, 2, 3


@kernel(cache=True, nogil=True)
def close1(v: float, best: float) -> bool:  # pragma: no cover - compiled; _close for one value
    if np.isinf(best):
        return v == best
    return abs(v - best) <= 1e-9 * (1.0 + abs(best))


#: unit roundoff of float64: a sum of n terms, added in any order, is within
#: (n - 1) * EPS * sum(|terms|) of the exact sum (to first order)
EPS = 2.0**-53


#: no counts: every value of the column once (:func:`column_stats`)
_EACH_ONCE = np.zeros(0, dtype=np.int64)


@kernel(cache=True, nogil=True)
def column_stats(
    col: NDArray[np.float64], j: int, mins: NDArray[np.float64], sums: NDArray[np.float64],
    errs: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Min, sum and the sum's rounding bound of one utility column into ``[j]`` of the
    outputs; False if the column holds a NaN (numpy must decide then)."""
    return group_stats(col, _EACH_ONCE, col.shape[0], j, mins, sums, errs)


@kernel(cache=True, nogil=True)
def group_stats(
    vals: NDArray[np.float64], counts: NDArray[np.int64], n: int, j: int,
    mins: NDArray[np.float64], sums: NDArray[np.float64], errs: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """:func:`column_stats` of a column of ``n`` values in which ``vals[g]`` occurs
    ``counts[g]`` times (rivals sharing a hop row and a class), in O(groups); with no
    ``counts``, ``vals`` is the column itself, added value by value.

    By groups the sum is added ``counts[g] * vals[g]`` at a time. Each product rounds once
    and the groups add with groups - 1 roundings, so this sum is within groups * EPS *
    sum|v| <= n EPS sum|v| of the exact one, and numpy's (in whatever order) within (n - 1)
    EPS sum|v|: the two differ by less than ``errs`` (2n EPS sum|v|, with 1 % for the second
    order), which is all :func:`select_top` assumes. Integers below 2**40 whose absolute sum
    stays below 2**53 add exactly in any order (every product and partial sum is an integer
    below 2**53): ``errs`` is 0 then."""
    grouped = counts.shape[0] > 0
    m = vals[0]
    s = 0.0
    a = 0.0
    exact = True
    for g in range(vals.shape[0]):
        v = vals[g]
        if np.isnan(v):
            return False
        if v < m:
            m = v
        if grouped:
            s += counts[g] * v
            a += counts[g] * abs(v)
        else:
            s += v
            a += abs(v)
        if exact and not (abs(v) <= 2.0**40 and v == np.floor(v)):
            exact = False
    mins[j] = m
    sums[j] = s
    if exact and a < 2.0**53:
        errs[j] = 0.0
    elif np.isfinite(a):
        errs[j] = 1.01 * 2.0 * n * EPS * a
    else:
        errs[j] = np.inf
    return True


@kernel(cache=True, nogil=True)
def select_top(
    mins: NDArray[np.float64], sums: NDArray[np.float64], errs: NDArray[np.float64]
) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """GetBestNode on per-column minima and sums: the columns left for the final draw, or
    ``[-1]`` when the float sums numpy would compute could rank them otherwise.

    ``get_best_node`` keeps the columns whose numpy sum is within 1e-9 (relative) of the
    largest. Each of those sums is known here to within ``errs``; a column is decided only
    when it is tied, or not, for every sums numpy could have computed, which is always the
    case unless two sums differ by about the tolerance itself.
    """
    c = mins.shape[0]
    best = mins.max()
    tied = np.empty(c, dtype=np.int64)
    nt = 0
    for j in range(c):
        if close1(mins[j], best):
            tied[nt] = j
            nt += 1
    if nt == 1:
        return tied[:1]
    lo = -np.inf  # bounds on numpy's largest sum among the tied
    hi = -np.inf
    for t in range(nt):
        j = tied[t]
        if not (np.isfinite(sums[j]) and np.isfinite(errs[j])):
            return np.full(1, -1, dtype=np.int64)
        lo = max(lo, sums[j] - errs[j])
        hi = max(hi, sums[j] + errs[j])
    big = max(abs(lo), abs(hi))
    small = 0.0 if lo <= 0.0 <= hi else min(abs(lo), abs(hi))
    tol_lo = 1e-9 * (1.0 + small)
    tol_hi = 1e-9 * (1.0 + big)
    top = np.empty(nt, dtype=np.int64)
    k = 0
    for t in range(nt):
        j = tied[t]
        if errs[j] == 0.0 and lo == hi:  # exact sums: get_best_node's test itself
            if close1(sums[j], hi):
                top[k] = j
                k += 1
            continue
        gap_hi = hi - (sums[j] - errs[j])  # the most numpy's gap could be
        gap_lo = lo - (sums[j] + errs[j])  # the least
        if gap_hi <= tol_lo:
            top[k] = j
            k += 1
        elif gap_lo <= tol_hi:
            return np.full(1, -1, dtype=np.int64)  # too close to call: numpy decides
    return top[:k]


@kernel(cache=True, nogil=True)
def top_columns(util: NDArray[np.float64]) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """get_best_node's choice as column indices, or ``[-1]`` when numpy must decide (a NaN,
    an infinite sum among the tied, or sums too close to call: see :func:`select_top`)."""
    r, c = util.shape
    mins = np.empty(c)
    sums = np.empty(c)
    errs = np.empty(c)
    col = np.empty(r)
    for j in range(c):
        for i in range(r):
            col[i] = util[i, j]
        if not column_stats(col, j, mins, sums, errs):
            return np.full(1, -1, dtype=np.int64)
    return select_top(mins, sums, errs)


@kernel(cache=True, nogil=True)
def vacant_neighbours(
    indptr: NDArray[np.int64], indices: NDArray[np.int32], here: int,
    status: NDArray[np.int32], reserved: NDArray[np.int32], me: int,
) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """Branch 2's W: the neighbours of ``here`` not in KM (not done, not an obstacle, not
    reserved by a rival), sorted and without duplicates."""
    lo = indptr[here]
    hi = indptr[here + 1]
    cands = np.empty(hi - lo, dtype=np.int64)
    c = 0
    for k in range(lo, hi):
        v = indices[k]
        owner = reserved[v]
        if status[v] != 0 or (owner != 0 and owner != me):
            continue
        j = c  # insertion sort, dropping duplicates
        while j > 0 and cands[j - 1] > v:
            j -= 1
        if j > 0 and cands[j - 1] == v:
            continue
        for t in range(c, j, -1):
            cands[t] = cands[t - 1]
        cands[j] = v
        c += 1
    return cands[:c]
