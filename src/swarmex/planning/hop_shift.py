"""Moving a lattice hop field's source by one edge: exact, at about half a fresh search.

On a 4-connected lattice (a bipartite graph, with any vertices removed) every distance from
a source's neighbour differs by exactly one from the source's own. So a
:class:`~swarmex.planning.fieldcache.KnownGraph` row follows a walking agent by a shift
(:func:`_shift_lattice`: the cone of vertices that get nearer, or its complement, whichever
is smaller) instead of a new search, and the result is bit-identical to a fresh BFS. These
kernels are the shift alone; :func:`swarmex.planning.distance.shift_hop_field` is its
Python entry point.
"""

from __future__ import annotations

from swarmex._kernels import kernel
from swarmex.planning.kernel_arrays import Hops, NbMask, Scratch, Vertices

# Row passes of the shifts. Each takes its array(s) once so that the compiler vectorises it:
# a loop reading ``old`` and writing ``row`` falls back to scalar code when the two are the
# same array (the run-time alias check fails), about 15x slower on an in-place shift.


@kernel(cache=True, nogil=True)
def _plus_one_in_place(row: Hops) -> None:  # pragma: no cover - compiled
    """Add one to every reached entry of ``row`` (negative entries are kept)."""
    for x in range(row.shape[0]):
        h = row[x]
        row[x] = h + 1 if h >= 0 else h


@kernel(cache=True, nogil=True)
def _plus_one(old: Hops, row: Hops) -> None:  # pragma: no cover - compiled
    """``row = old + 1`` on reached entries, negative ones copied (distinct arrays)."""
    for x in range(old.shape[0]):
        h = old[x]
        row[x] = h + 1 if h >= 0 else h


@kernel(cache=True, nogil=True)
def _copy_row(old: Hops, row: Hops) -> None:  # pragma: no cover - compiled
    for x in range(old.shape[0]):
        row[x] = old[x]


@kernel(cache=True, nogil=True)
def _settle_outside_bits(row: Hops) -> None:  # pragma: no cover - compiled
    """Final pass of :func:`_shift_by_complement_bits`: entries carrying
    :data:`OUTSIDE_BIT` gain one hop (the bit cleared), other reached entries lose one,
    negative ones stay; written without branches so that it vectorises."""
    low = OUTSIDE_BIT - 1
    for x in range(row.shape[0]):
        v = row[x]
        out = (v & low) - 1 + 2 * ((v >> 14) & 1)
        row[x] = out if v >= 0 else v


@kernel(cache=True, nogil=True)
def _shift_source_lattice(
    width: int, nbmask: NbMask, old: Hops, row: Hops, new_source: int, queue: Scratch
) -> int:  # pragma: no cover
    """Write into ``row`` the hop field of ``new_source``, given in ``old`` the exact field
    of a neighbour of it (``old`` may be ``row`` itself: the shift works in place).

    On a bipartite graph (a 4-connected lattice, with any vertices removed) moving the
    source one edge changes every reachable distance by exactly one: down by one for the
    vertices with a shortest path through ``new_source`` (its *cone* in the shortest-path
    DAG of the old field), up by one for all others. So: one vectorisable pass adds one,
    then a search over the cone alone (about half the graph when agents walk) subtracts
    two. Exact, like a fresh BFS, at roughly half its cost. No visited marks are needed: a
    vertex is taken into the cone when it holds old(u) + 2, and once taken it holds
    old - 1, which no neighbour of a cone vertex can match again.

    The cone is everything reachable from ``new_source`` along edges that go one hop
    further from the old source, so the order of the search does not matter: it runs
    depth first from a stack (``queue``), which keeps the recently touched cells in cache
    (about 1.2x faster than breadth first on den520d). Returns the cone's size.
    """
    if old.ctypes.data == row.ctypes.data:
        _plus_one_in_place(row)
    else:
        _plus_one(old, row)
    row[new_source] = 0
    queue[0] = new_source
    top = 1
    size = 0
    while top > 0:
        top -= 1
        size += 1  # every cone vertex is pushed, and so popped, once
        u = queue[top]
        want = row[u] + 3  # old(u) + 1, stored as old + 1 (outside the cone)
        m = nbmask[u]
        if m & 1:
            v = u - width
            if row[v] == want:
                row[v] = want - 2
                queue[top] = v
                top += 1
        if m & 2:
            v = u - 1
            if row[v] == want:
                row[v] = want - 2
                queue[top] = v
                top += 1
        if m & 4:
            v = u + 1
            if row[v] == want:
                row[v] = want - 2
                queue[top] = v
                top += 1
        if m & 8:
            v = u + width
            if row[v] == want:
                row[v] = want - 2
                queue[top] = v
                top += 1
    return size


@kernel(cache=True, nogil=True)
def _shift_by_complement(
    width: int, nbmask: NbMask, old: Hops, row: Hops, new_source: int, old_source: int,
    mark: Scratch, epoch: int, queue: Scratch,
) -> int:  # pragma: no cover - compiled
    """:func:`_shift_source_lattice` computed from the other side: a search over the
    vertices *outside* the cone (those whose shortest paths from ``old_source`` all avoid
    ``new_source``; they gain one hop), then one pass writing every distance. A vertex is
    outside iff all its shortest-path parents are, so a level-by-level search from the old
    source decides each vertex when it is first met. Costs about twice as much per vertex
    as the cone search, so it pays when the cone is most of the graph (an agent stepping
    away from the bulk of the map). ``mark`` (int32, n) gets ``epoch`` for outside
    vertices and ``-epoch`` for rejected ones; ``old`` may be ``row``.
    """
    mark[old_source] = epoch
    queue[0] = old_source
    head = 0
    tail = 1
    while head < tail:
        u = queue[head]
        head += 1
        want = old[u] + 1
        m = nbmask[u]
        for b in range(4):
            if not m & (1 << b):
                continue
            if b == 0:
                y = u - width
            elif b == 1:
                y = u - 1
            elif b == 2:
                y = u + 1
            else:
                y = u + width
            if old[y] != want or mark[y] == epoch or mark[y] == -epoch or y == new_source:
                continue
            outside = True  # every parent of y (a neighbour one hop nearer) outside?
            my = nbmask[y]
            for c in range(4):
                if not my & (1 << c):
                    continue
                if c == 0:
                    p = y - width
                elif c == 1:
                    p = y - 1
                elif c == 2:
                    p = y + 1
                else:
                    p = y + width
                if old[p] == want - 1 and mark[p] != epoch:
                    outside = False
                    break
            if outside:
                mark[y] = epoch
                queue[tail] = y
                tail += 1
            else:
                mark[y] = -epoch
    for x in range(old.shape[0]):
        o = old[x]
        if o >= 0:
            row[x] = o + 1 if mark[x] == epoch else o - 1
        else:
            row[x] = o
    return tail


#: bit marking a vertex outside the cone in :func:`_shift_by_complement_bits` (hop counts
#: must stay below it there)
OUTSIDE_BIT = 0x4000


@kernel(cache=True, nogil=True)
def _shift_by_complement_bits(
    width: int, nbmask: NbMask, old: Hops, row: Hops, new_source: int, old_source: int,
    queue: Scratch,
) -> int:  # pragma: no cover - compiled
    """:func:`_shift_by_complement` with the outside marks kept in the row itself (bit
    :data:`OUTSIDE_BIT` of the old value) instead of a separate array: a search step reads
    one array instead of two, about twice as fast. Every reached hop count must be below
    ``OUTSIDE_BIT - 1``. ``old`` may be ``row``.

    The search runs depth first from a stack (``queue``; about 1.25x faster than level by
    level on den520d), so a vertex may be met before all of its parents are decided: it is
    then found inside (a parent is not marked yet) and left unmarked, and met again from
    each parent that is marked later. The last of its parents to be marked, if all are
    outside, marks it, so every outside vertex is found whatever the order. Returns how
    many vertices are outside.
    """
    if old.ctypes.data != row.ctypes.data:
        _copy_row(old, row)
    low = OUTSIDE_BIT - 1
    row[old_source] = row[old_source] | OUTSIDE_BIT
    queue[0] = old_source
    top = 1
    size = 0
    while top > 0:
        top -= 1
        size += 1  # every outside vertex is pushed, and so popped, once
        u = queue[top]
        want = (row[u] & low) + 1
        m = nbmask[u]
        for b in range(4):
            if not m & (1 << b):
                continue
            if b == 0:
                y = u - width
            elif b == 1:
                y = u - 1
            elif b == 2:
                y = u + 1
            else:
                y = u + width
            ry = row[y]
            if ry != want or y == new_source:  # not a child of u, or marked already
                continue
            outside = True  # every parent of y (a neighbour one hop nearer) outside?
            my = nbmask[y]
            for c in range(4):
                if not my & (1 << c):
                    continue
                if c == 0:
                    p = y - width
                elif c == 1:
                    p = y - 1
                elif c == 2:
                    p = y + 1
                else:
                    p = y + width
                if row[p] == want - 1:  # a parent without the mark: inside
                    outside = False
                    break
            if outside:
                row[y] = ry | OUTSIDE_BIT
                queue[top] = y
                top += 1
    _settle_outside_bits(row)
    return size


@kernel(cache=True, nogil=True)
def _cone_share(
    width: int, new_source: int, old_source: int, col_free: Vertices, row_free: Vertices
) -> float:  # pragma: no cover - compiled
    """Rough share of the reachable vertices inside the cone of a shift between lattice
    neighbours: the share of the free vertices nearer (in lattice steps) to the new source
    than to the old one, which is the half-plane beyond the old source's column (a
    horizontal move) or row (a vertical one). ``col_free`` / ``row_free`` count the free
    vertices per grid column / row, so this costs one pass over a row of counts instead of
    a sample of the field (it only picks the faster search; either gives the same row).
    Not neighbours (never in a shift): 0.0."""
    oy = old_source // width
    ox = old_source - oy * width
    d = new_source - old_source
    total = 0
    for c in range(col_free.shape[0]):
        total += col_free[c]
    ahead = 0
    if d == width:
        for y in range(oy + 1, row_free.shape[0]):
            ahead += row_free[y]
    elif d == -width:
        for y in range(oy):
            ahead += row_free[y]
    elif d == 1 and new_source // width == oy:
        for c in range(ox + 1, width):
            ahead += col_free[c]
    elif d == -1 and new_source // width == oy:
        for c in range(ox):
            ahead += col_free[c]
    return ahead / total if total else 0.0


#: above this estimated cone share, a shift searches the complement instead of the cone
#: (the complement costs about 1.8-2x the cone per vertex; 0.65-0.7 best on den520d's
#: recorded shifts since the cone search runs depth first)
COMPLEMENT_ABOVE = 0.65


@kernel(cache=True, nogil=True)
def _shift_lattice(
    width: int, nbmask: NbMask, old: Hops, row: Hops, new_source: int, old_source: int,
    col_free: Vertices, row_free: Vertices, mark: Scratch, epoch: int, queue: Scratch,
    top: int,
) -> int:  # pragma: no cover - compiled
    """Shift a lattice hop field to a neighbouring source by whichever search should be
    smaller (see :func:`_shift_source_lattice` and :func:`_shift_by_complement`); the
    result is the same either way. ``top`` bounds the old field's largest hop count (it
    selects the faster complement search when the counts leave a bit free)."""
    if _cone_share(width, new_source, old_source, col_free, row_free) > COMPLEMENT_ABOVE:
        if top < OUTSIDE_BIT - 2:
            return _shift_by_complement_bits(width, nbmask, old, row, new_source, old_source,
                                             queue)
        return _shift_by_complement(width, nbmask, old, row, new_source, old_source, mark,
                                    epoch, queue)
    return _shift_source_lattice(width, nbmask, old, row, new_source, queue)
