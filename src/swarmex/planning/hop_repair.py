"""Repairing a hop field in place when vertices become blocked (a decremental BFS).

When an agent discovers obstacles, only the vertices whose every shortest path ran through
them can change; :func:`_repair_hops` re-derives those alone, so a stored
:class:`~swarmex.planning.fieldcache.KnownGraph` row stays exact (bit-identical to a fresh
search) at the cost of the change. :func:`swarmex.planning.distance.repair_hops` is its
Python entry point.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.planning.kernel_arrays import Hops, Indices, Indptr, Mask, Scratch, Vertices


@kernel(cache=True, nogil=True)
def _repair_hops(
    indptr: Indptr, indices: Indices, blocked: Mask, hops: Hops, source: int, new: Vertices,
    state: NDArray[np.int8], touched: Scratch, work: Scratch, order_key: Scratch, limit: int,
    max_hop: int,
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """Decremental BFS: make the single-source ``hops`` exact after ``new`` became blocked.

    Returns ``(changed, largest value written, affected)``: the ``affected`` vertices whose
    value was re-derived are left in ``order_key[:affected]`` (a caller keeping summaries of
    the row updates them from there). ``changed`` is -1 (``hops`` untouched)
    when more than ``limit`` vertices would have to be re-derived, where a fresh BFS is
    cheaper, and -2 (``hops`` unusable) when a distance would exceed ``max_hop``, the
    largest value the table's integer type holds. ``state`` (int8,
    all zero on entry and on exit), ``touched``, ``work`` and ``order_key`` are scratch of
    length n.

    Phase 1 finds the *affected* vertices, in increasing hop order: those whose every
    shortest-path parent was blocked or is itself affected. Nobody else can change, because
    blocking only lengthens paths and an unaffected vertex keeps a path of its old length.
    Phase 2 re-derives the affected ones by a BFS over them seeded from their unaffected
    neighbours (a two-queue merge: seeds sorted by distance, then the FIFO of unit steps).
    """
    # state: 0 untouched, 1 checked & unaffected, 2 affected, 3 newly blocked, 4 settled
    nt = 0
    n_removed = 0
    for o in new:
        if o == source or hops[o] < 0 or state[o] != 0:
            continue
        state[o] = 3
        touched[nt] = o
        nt += 1
        n_removed += 1
    # candidates: children on a shortest path of a removed vertex (in `work`, sorted below)
    nc = 0
    for j in range(nt):
        o = touched[j]
        ho = hops[o] + 1
        for k in range(indptr[o], indptr[o + 1]):
            u = indices[k]
            if state[u] == 0 and hops[u] == ho and not blocked[u]:
                state[u] = 1
                touched[nt] = u
                nt += 1
                work[nc] = u
                nc += 1
    if nc > 1:
        for j in range(nc):
            order_key[j] = hops[work[j]]
        perm = np.argsort(order_key[:nc], kind="mergesort")
        tmp = work[:nc][perm]
        work[:nc] = tmp
    # merge the sorted candidates with a FIFO of children of affected vertices; the FIFO
    # lives in work[nc:]; affected vertices are appended to `order_key` (reused as a list)
    n_aff = 0
    ia = 0
    fh = nc
    ft = nc
    while ia < nc or fh < ft:
        if fh >= ft or (ia < nc and hops[work[ia]] <= hops[work[fh]]):
            x = work[ia]
            ia += 1
        else:
            x = work[fh]
            fh += 1
        hx = hops[x]
        ok = False
        for k in range(indptr[x], indptr[x + 1]):
            p = indices[k]
            if hops[p] == hx - 1 and state[p] != 2 and (p == source or not blocked[p]):
                ok = True
                break
        if ok:
            continue
        state[x] = 2
        order_key[n_aff] = x
        n_aff += 1
        if n_aff > limit:
            for j in range(nt):
                state[touched[j]] = 0
            return -1, 0, 0
        for k in range(indptr[x], indptr[x + 1]):
            y = indices[k]
            if state[y] == 0 and hops[y] == hx + 1 and not blocked[y]:
                state[y] = 1
                touched[nt] = y
                nt += 1
                work[ft] = y
                ft += 1
    # phase 2: removed vertices become unreachable; affected ones are re-derived
    for j in range(nt):
        v = touched[j]
        if state[v] == 3:
            hops[v] = -1
    big = max_hop + 1  # "not derived yet"; a real distance never reaches it
    capped = False  # a distance was cut at max_hop: the type is too narrow for this field
    top = 0
    for j in range(n_aff):
        hops[order_key[j]] = big
    ns = 0
    for j in range(n_aff):
        x = order_key[j]
        best = big
        for k in range(indptr[x], indptr[x + 1]):
            p = indices[k]
            hp = hops[p]
            ok = state[p] != 2 and 0 <= hp < big and (p == source or not blocked[p])
            if ok and hp + 1 < best:
                best = hp + 1
            if ok and hp == max_hop:
                capped = True
        if best < big:
            hops[x] = best
            top = max(top, best)
            work[ns] = x
            ns += 1
    if ns > 1:
        keys = np.empty(ns, dtype=np.int32)
        for j in range(ns):
            keys[j] = hops[work[j]]
        perm = np.argsort(keys, kind="mergesort")
        tmp = work[:ns][perm]
        work[:ns] = tmp
    # FIFO after the seeds; entries may be stale (a vertex re-pushed with a smaller value)
    ia = 0
    fh = ns
    ft = ns
    while ia < ns or fh < ft:
        if fh >= ft or (ia < ns and hops[work[ia]] <= hops[work[fh]]):
            x = work[ia]
            ia += 1
        else:
            x = work[fh]
            fh += 1
        if state[x] != 2:
            continue  # settled already (stale entry)
        state[x] = 4
        hx1 = hops[x] + 1
        if hx1 == big:
            capped = True
        for k in range(indptr[x], indptr[x + 1]):
            y = indices[k]
            if state[y] == 2 and hx1 < hops[y]:
                hops[y] = hx1
                top = max(top, hx1)
                work[ft] = y
                ft += 1
    overflow = False
    for j in range(n_aff):
        x = order_key[j]
        if state[x] == 2:  # never reached: cut off by the new obstacles (or too far)
            hops[x] = -1
            overflow = overflow or capped
    for j in range(nt):
        state[touched[j]] = 0
    if overflow:
        return -2, 0, 0
    return n_aff + n_removed, top, n_aff
