"""Distance fields on a :class:`~swarmex.worlds.NodeGraph`, from one or many sources.

A distance field is a float array with one entry per vertex: the shortest-path length from
the nearest source, ``inf`` where unreachable. Vertices flagged in ``blocked`` are never
entered (a blocked source still radiates, which is how an agent standing on a vertex that
turned out to be an obstacle is handled: it does not occur in the missions, but the kernel
stays total).

Which function to use:

* :func:`distance_field` — one field, nearest of several sources (a multi-source search);
* :func:`distance_fields` — one *separate* field per source, split over one thread per core
  (the kernels release the GIL); each row equals :func:`distance_field` of its source;
* :func:`hop_field`, :func:`repair_hops`, :func:`shift_hop_field` — integer hop counts for
  graphs whose edges all have one length. They are what
  :class:`~swarmex.planning.fieldcache.KnownGraph` stores: exact (no rounding), so a field
  can be *repaired* in place when vertices become blocked, or *shifted* to a neighbouring
  source, and the result is bit-identical to a fresh search either way.

Kernels are numba-compiled loops (:mod:`swarmex._kernels`: compiled on first use, or run
as Python in small one-shot runs): a level-synchronous breadth-first search when all edges
have one length, a binary-heap Dijkstra otherwise. On a full 4-connected lattice (what a
4-connected grid world builds; :func:`lattice_structure` recognises it) the searches compute
neighbours (u ± 1, u ± width) instead of reading the CSR arrays, about 3x faster. A BFS field
is ``hops * step`` computed per vertex, so every route to a field (BFS, repair, shift,
conversion) gives the same floats. Work arrays are reused per thread: fresh large arrays
would cost page faults at every call.

The kernels that keep a stored hop field exact live beside this module:
:mod:`~swarmex.planning.hop_repair` (obstacles discovered) and
:mod:`~swarmex.planning.hop_shift` (the source moved one edge); the array types all these
kernels share are in :mod:`~swarmex.planning.kernel_arrays`.
"""

from __future__ import annotations

import os
import threading
import weakref
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
from numpy.typing import DTypeLike, NDArray

from swarmex._kernels import kernel
from swarmex.planning.hop_repair import _repair_hops
from swarmex.planning.hop_shift import (
    _shift_by_complement,
    _shift_by_complement_bits,
    _shift_lattice,
    _shift_source_lattice,
)
from swarmex.planning.kernel_arrays import (
    BLOCKED,
    UNREACHED,
    Field,
    Hops,
    Indices,
    Indptr,
    Mask,
    NbMask,
    Scratch,
    Vertices,
    Weights,
)
from swarmex.worlds.nodegraph import NodeGraph


@kernel(cache=True, nogil=True)
def _bfs_hops(
    indptr: Indptr, indices: Indices, blocked: Mask, sources: Vertices, hops: Hops,
    queue: Scratch,
) -> int:  # pragma: no cover - compiled
    """Hop counts from the nearest source into ``hops`` (int32, -1 unreached); returns the
    number of vertices reached. ``queue`` is int32 scratch of length n."""
    n = indptr.shape[0] - 1
    for i in range(n):
        hops[i] = -1
    tail = 0
    for s in sources:
        if hops[s] < 0:
            hops[s] = 0
            queue[tail] = s
            tail += 1
    head = 0
    level = 0
    while head < tail:
        level += 1
        end = tail
        while head < end:
            u = queue[head]
            head += 1
            for k in range(indptr[u], indptr[u + 1]):
                v = indices[k]
                if hops[v] < 0 and not blocked[v]:
                    hops[v] = level
                    queue[tail] = v
                    tail += 1
    return tail


@kernel(cache=True, nogil=True)
def _bfs_hops_csr(
    indptr: Indptr, indices: Indices, source: int, hops: Hops, queue: Scratch, max_hop: int
) -> int:  # pragma: no cover
    """Single-source hop counts into ``hops``, which must arrive holding UNREACHED or
    BLOCKED per vertex (a copy of a template: one array to test instead of two). Returns the
    largest hop count, or -1 when it would exceed ``max_hop`` (the row is then unusable:
    a narrow hop table has to be widened first)."""
    hops[source] = 0
    queue[0] = source
    tail = 1
    head = 0
    level = 0
    while head < tail:
        level += 1
        if level > max_hop:
            return -1
        end = tail
        while head < end:
            u = queue[head]
            head += 1
            for k in range(indptr[u], indptr[u + 1]):
                v = indices[k]
                if hops[v] == -1:
                    hops[v] = level
                    queue[tail] = v
                    tail += 1
    return level - 1


@kernel(cache=True, nogil=True)
def _bfs_hops_lattice(
    width: int, nbmask: NbMask, source: int, hops: Hops, queue: Scratch, max_hop: int
) -> int:  # pragma: no cover
    """:func:`_bfs_hops_csr` on a full 4-connected lattice (a grid world's graph).

    Neighbours are computed (u ± 1, u ± width, gated by ``nbmask`` bits up/left/right/down)
    instead of read from the CSR arrays: the working set drops to the hop, queue and mask
    arrays, which is what makes this about 3x faster than the general kernel.
    """
    hops[source] = 0
    queue[0] = source
    tail = 1
    head = 0
    level = 0
    while head < tail:
        level += 1
        if level > max_hop:
            return -1
        end = tail
        while head < end:
            u = queue[head]
            head += 1
            m = nbmask[u]
            if m & 1:
                v = u - width
                if hops[v] == -1:
                    hops[v] = level
                    queue[tail] = v
                    tail += 1
            if m & 2:
                v = u - 1
                if hops[v] == -1:
                    hops[v] = level
                    queue[tail] = v
                    tail += 1
            if m & 4:
                v = u + 1
                if hops[v] == -1:
                    hops[v] = level
                    queue[tail] = v
                    tail += 1
            if m & 8:
                v = u + width
                if hops[v] == -1:
                    hops[v] = level
                    queue[tail] = v
                    tail += 1
    return level - 1


@kernel(cache=True, nogil=True)
def _bfs(
    indptr: Indptr, indices: Indices, step: float, blocked: Mask, sources: Vertices,
    out: Field, queue: Scratch,
) -> None:  # pragma: no cover - compiled
    """Float BFS field; the visited test reads ``out`` itself, so there is no second array.
    ``queue`` is int32 scratch of length n."""
    n = indptr.shape[0] - 1
    for i in range(n):
        out[i] = np.inf
    tail = 0
    for s in sources:
        if out[s] > 0.0:
            out[s] = 0.0
            queue[tail] = s
            tail += 1
    head = 0
    level = 0
    while head < tail:
        level += 1
        val = level * step  # == hops * step of a per-vertex conversion: same float
        end = tail
        while head < end:
            u = queue[head]
            head += 1
            for k in range(indptr[u], indptr[u + 1]):
                v = indices[k]
                if out[v] == np.inf and not blocked[v]:
                    out[v] = val
                    queue[tail] = v
                    tail += 1


@kernel(cache=True, nogil=True)
def _bfs_lattice(
    width: int, nbmask: NbMask, step: float, blocked: Mask, sources: Vertices, out: Field,
    queue: Scratch,
) -> None:  # pragma: no cover
    """:func:`_bfs` on a full 4-connected lattice (neighbours computed, not read)."""
    n = out.shape[0]
    for i in range(n):
        out[i] = np.inf
    tail = 0
    for s in sources:
        if out[s] > 0.0:
            out[s] = 0.0
            queue[tail] = s
            tail += 1
    head = 0
    level = 0
    while head < tail:
        level += 1
        val = level * step
        end = tail
        while head < end:
            u = queue[head]
            head += 1
            m = nbmask[u]
            for b in range(4):
                if m & (1 << b):
                    if b == 0:
                        v = u - width
                    elif b == 1:
                        v = u - 1
                    elif b == 2:
                        v = u + 1
                    else:
                        v = u + width
                    if out[v] == np.inf and not blocked[v]:
                        out[v] = val
                        queue[tail] = v
                        tail += 1


@kernel(cache=True, nogil=True)
def _dijkstra(
    indptr: Indptr, indices: Indices, weights: Weights, blocked: Mask, sources: Vertices,
    out: Field, done: Mask, hd: NDArray[np.float64], hv: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """Binary-heap Dijkstra. Scratch: ``done`` (bool, n) and the heap's distance and vertex
    arrays ``hd``/``hv`` (length >= number of CSR entries + sources + 1)."""
    n = indptr.shape[0] - 1
    for i in range(n):
        out[i] = np.inf
        done[i] = False
    # binary heap of (distance, vertex) in two parallel arrays
    size = 0
    for s in sources:
        if out[s] > 0.0:
            out[s] = 0.0
            hd[size] = 0.0
            hv[size] = s
            size += 1
    # heapify (all zeros: already a heap)
    while size > 0:
        d = hd[0]
        u = hv[0]
        size -= 1
        if size > 0:
            # move last to root and sift down
            ld = hd[size]
            lv = hv[size]
            i = 0
            while True:
                c = 2 * i + 1
                if c >= size:
                    break
                if c + 1 < size and hd[c + 1] < hd[c]:
                    c += 1
                if hd[c] < ld:
                    hd[i] = hd[c]
                    hv[i] = hv[c]
                    i = c
                else:
                    break
            hd[i] = ld
            hv[i] = lv
        if done[u]:
            continue
        done[u] = True
        for k in range(indptr[u], indptr[u + 1]):
            v = indices[k]
            if blocked[v] or done[v]:
                continue
            nd = d + weights[k]
            if nd < out[v]:
                out[v] = nd
                # push and sift up
                i = size
                size += 1
                while i > 0:
                    p = (i - 1) // 2
                    if hd[p] > nd:
                        hd[i] = hd[p]
                        hv[i] = hv[p]
                        i = p
                    else:
                        break
                hd[i] = nd
                hv[i] = v


@kernel(cache=True, nogil=True)
def _fields_chunk(
    indptr: Indptr, indices: Indices, weights: Weights, width: int, nbmask: NbMask,
    uniform: bool, blocked: Mask, sources: Vertices, out: NDArray[np.float64], lo: int, hi: int,
) -> None:  # pragma: no cover - compiled
    """Rows ``lo:hi`` of :func:`distance_fields` (one thread's share), with own scratch."""
    n = indptr.shape[0] - 1
    queue = np.empty(n, dtype=np.int32)
    done = np.empty(n, dtype=np.bool_)
    cap = 1 if uniform else indices.shape[0] + 2
    hd = np.empty(cap, dtype=np.float64)
    hv = np.empty(cap, dtype=np.int64)
    step = weights[0] if weights.shape[0] else 1.0
    for i in range(lo, hi):
        src = sources[i : i + 1]
        if not uniform:
            _dijkstra(indptr, indices, weights, blocked, src, out[i], done, hd, hv)
        elif width > 0:
            _bfs_lattice(width, nbmask, step, blocked, src, out[i], queue)
        else:
            _bfs(indptr, indices, step, blocked, src, out[i], queue)


@kernel(cache=True, nogil=True)
def _first_steps(
    indptr: Indptr, indices: Indices, hops: Hops, target: int, mark: Scratch, epoch: int,
    queue: Scratch, out: Vertices,
) -> int:  # pragma: no cover - compiled
    """The neighbours of a hop row's source that lie on a shortest path to ``target``,
    into ``out`` (returns how many; 0 if ``target`` is unreached or is the source).

    A walk back from ``target`` through the row's shortest-path parents (neighbours one hop
    nearer the source), level by level, visits exactly the vertices on shortest paths
    between the two, and its last level (hop 1) is the answer: the same set as the
    neighbours whose distance *from the target* is one less than the source's, without a
    field of the target. ``mark`` (int32, n) gets ``epoch`` on visited vertices."""
    top = hops[target]
    if top < 0:
        return 0
    if top == 0:  # the target is the source: no step leads nearer
        return 0
    if top == 1:
        out[0] = target
        return 1
    mark[target] = epoch
    queue[0] = target
    head = 0
    tail = 1
    found = 0
    while head < tail:
        x = queue[head]
        head += 1
        want = hops[x] - 1
        for k in range(indptr[x], indptr[x + 1]):
            p = indices[k]
            if hops[p] == want and mark[p] != epoch:
                mark[p] = epoch
                if want == 1:
                    out[found] = p
                    found += 1
                else:
                    queue[tail] = p
                    tail += 1
    return found


_LATTICES: weakref.WeakKeyDictionary[NodeGraph, tuple[int, NbMask | None]] = (
    weakref.WeakKeyDictionary()
)


def lattice_structure(graph: NodeGraph) -> tuple[int, NbMask | None]:
    """``(width, nbmask)`` if ``graph`` is exactly a full 4-connected ``width``-wide lattice
    with one edge length (what a 4-connected GridWorld builds), else ``(0, None)``.

    ``nbmask[v]`` has bit 0/1/2/3 set when v has a neighbour up/left/right/down. Checked
    once per graph by comparing the CSR arrays with the lattice's own, so a graph that only
    looks like a grid never takes the lattice kernel.
    """
    hit = _LATTICES.get(graph)
    if hit is not None:
        return hit
    result: tuple[int, NbMask | None] = (0, None)
    n = graph.n_nodes
    if graph.uniform and n > 0 and graph.indices.size:
        diffs = np.abs(np.repeat(np.arange(n), np.diff(graph.indptr)) - graph.indices)
        width = int(diffs.max())
        if width >= 1 and n % width == 0:
            ys, xs = np.divmod(np.arange(n), width)
            height = n // width
            mask = (
                (ys > 0) * 1 | (xs > 0) * 2 | (xs < width - 1) * 4 | (ys < height - 1) * 8
            ).astype(np.uint8)
            deg = np.zeros(n, dtype=np.int64)
            for bit in (1, 2, 4, 8):
                deg += (mask & bit) > 0
            if np.array_equal(np.diff(graph.indptr), deg):
                offs = np.array([-width, -1, 1, width])
                want = np.concatenate(
                    [np.nonzero(mask & (1 << b))[0] for b in range(4)]
                )
                wnbr = np.concatenate(
                    [np.nonzero(mask & (1 << b))[0] + offs[b] for b in range(4)]
                )
                order = np.lexsort((wnbr, want))
                if np.array_equal(wnbr[order], graph.indices):
                    result = (width, mask)
    _LATTICES[graph] = result
    return result


def _as_sources(sources: int | Sequence[int] | np.ndarray) -> np.ndarray:
    return np.atleast_1d(np.asarray(sources, dtype=np.int64))


def _blocked_or_none(graph: NodeGraph, blocked: np.ndarray | None) -> np.ndarray:
    if blocked is None:
        return np.zeros(graph.n_nodes, dtype=bool)
    return blocked


def max_hop_of(dtype: type[np.integer[Any]] | np.dtype[np.integer[Any]]) -> int:
    """Largest hop count a hop table of integer ``dtype`` stores (one value is kept free
    as the repair's "not derived yet" marker)."""
    return int(np.iinfo(dtype).max) - 1


def step_length(graph: NodeGraph) -> float:
    """The one edge length of a ``uniform`` graph (what a BFS hop is worth)."""
    return float(graph.weights[0]) if graph.weights.size else 1.0


_SCRATCH = threading.local()
_POOL: ThreadPoolExecutor | None = None
_POOL_LOCK = threading.Lock()


def scratch(name: str, size: int, dtype: DTypeLike) -> np.ndarray:
    """This thread's reusable work array ``name`` of ``size`` items, zeroed when first made
    (a caller may keep it all zero between its calls).

    Searches need arrays as large as the map; allocated afresh, a few megabytes come back
    from the allocator as new pages, and touching them cost more than a short search itself
    (about 0.6 ms per exploration plan on 800 × 800 cells)."""
    store = getattr(_SCRATCH, "arrays", None)
    if store is None:
        store = _SCRATCH.arrays = {}
    arr = store.get(name)
    if arr is None or arr.size < size or arr.dtype != dtype:
        arr = store[name] = np.zeros(size, dtype=dtype)
    return arr[:size]


def _pool() -> ThreadPoolExecutor:
    global _POOL
    with _POOL_LOCK:
        if _POOL is None:
            _POOL = ThreadPoolExecutor(max_workers=os.cpu_count() or 1,
                                       thread_name_prefix="swarmex-fields")
        return _POOL


def distance_field(
    graph: NodeGraph,
    sources: int | Sequence[int] | np.ndarray,
    blocked: np.ndarray | None = None,
) -> np.ndarray:
    """Shortest-path length from the nearest of ``sources`` to every vertex."""
    src = _as_sources(sources)
    blocked = _blocked_or_none(graph, blocked)
    n = graph.n_nodes
    out = np.empty(n, dtype=np.float64)
    if graph.uniform:
        queue = scratch("queue", n, np.int32)
        width, mask = lattice_structure(graph)
        if mask is not None:  # (width > 0)
            _bfs_lattice(width, mask, step_length(graph), blocked, src, out, queue)
        else:
            _bfs(graph.indptr, graph.indices, step_length(graph), blocked, src, out, queue)
    else:
        cap = graph.indices.shape[0] + src.size + 1
        _dijkstra(graph.indptr, graph.indices, graph.weights, blocked, src, out,
                  scratch("done", n, np.bool_), scratch("hd", cap, np.float64),
                  scratch("hv", cap, np.int64))
    return out


def distance_fields(
    graph: NodeGraph,
    sources: Sequence[int] | np.ndarray,
    blocked: np.ndarray | None = None,
) -> np.ndarray:
    """One separate field per source: array of shape ``(len(sources), n_nodes)``.

    The fields are independent, so large batches are split over one thread per core (the
    kernels release the GIL); each row equals :func:`distance_field` of its source.
    """
    src = _as_sources(sources)
    n = graph.n_nodes
    out = np.empty((src.size, n), dtype=np.float64)
    if src.size == 0:
        return out
    blocked = _blocked_or_none(graph, blocked)
    width, mask = lattice_structure(graph) if graph.uniform else (0, None)
    mask = mask if mask is not None else np.zeros(1, dtype=np.uint8)
    args = (graph.indptr, graph.indices, graph.weights, width, mask, bool(graph.uniform),
            blocked, src, out)
    workers = min(os.cpu_count() or 1, src.size)
    if workers < 2 or src.size * n < 200_000:  # too little work to be worth a thread
        _fields_chunk(*args, 0, src.size)
        return out
    bounds = np.linspace(0, src.size, workers + 1).astype(int)
    jobs = [_pool().submit(_fields_chunk, *args, int(lo), int(hi))
            for lo, hi in zip(bounds[:-1], bounds[1:], strict=True)]
    for job in jobs:
        job.result()
    return out


def hop_field(
    graph: NodeGraph,
    sources: int | Sequence[int] | np.ndarray,
    blocked: np.ndarray | None = None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Edge counts (int32, -1 unreachable) from the nearest source, ignoring edge lengths.

    On a ``uniform`` graph the distance field is exactly ``hops * step_length(graph)``.
    """
    src = _as_sources(sources)
    blocked = _blocked_or_none(graph, blocked)
    n = graph.n_nodes
    if out is None:
        out = np.empty(n, dtype=np.int32)
    queue = scratch("queue", n, np.int32)
    width, mask = lattice_structure(graph)
    if mask is not None and src.size == 1:  # (width > 0)
        np.copyto(out, np.where(blocked, BLOCKED, UNREACHED))
        _bfs_hops_lattice(width, mask, int(src[0]), out, queue, max_hop_of(np.int32))
        out[out < 0] = UNREACHED
    else:
        _bfs_hops(graph.indptr, graph.indices, blocked, src, out, queue)
    return out


def repair_hops(
    graph: NodeGraph,
    hops: np.ndarray,
    source: int,
    new_blocked: Sequence[int] | np.ndarray,
    blocked: np.ndarray,
) -> int:
    """Update in place the hop field ``hops`` of ``source`` after ``new_blocked`` joined
    ``blocked`` (which must already include them); returns how many vertices changed.

    ``hops`` must have been exact for ``blocked`` minus ``new_blocked``. The result is the
    same array a fresh :func:`hop_field` would give, found by re-deriving only the vertices
    whose shortest paths all ran through the new obstacles (any negative entry means
    unreached).
    """
    n = graph.n_nodes
    new = np.asarray(new_blocked, dtype=np.int64).ravel()
    changed, _, _ = _repair_hops(
        graph.indptr, graph.indices, blocked, hops, int(source), new,
        np.zeros(n, dtype=np.int8), np.empty(n, dtype=np.int32),
        np.empty(2 * n + 2, dtype=np.int32), np.empty(n, dtype=np.int32), n,
        max_hop_of(hops.dtype),
    )
    if changed == -2:
        raise OverflowError(f"a distance exceeds what {hops.dtype} holds")
    return int(changed)


def shift_hop_field(
    graph: NodeGraph, hops: np.ndarray, new_source: int, method: str = "auto"
) -> np.ndarray:
    """The hop field of ``new_source`` from ``hops``, the exact single-source field of a
    neighbour of it (which must not be an obstacle), on a 4-connected lattice graph (see
    :func:`lattice_structure`). ``method``: search the ``"cone"`` (vertices that get
    nearer), its ``"complement"`` (``"complement-bits"``: marks kept in the row, for hop
    counts below ``OUTSIDE_BIT - 2``), or ``"auto"``: whichever looks smaller."""
    width, mask = lattice_structure(graph)
    if mask is None:  # (width == 0)
        raise ValueError("shift_hop_field needs a full 4-connected lattice graph")
    if hops[new_source] != 1:
        raise ValueError(f"vertex {new_source} is not at one hop from the field's source")
    zeros = np.flatnonzero(hops == 0)
    if zeros.size != 1:
        raise ValueError("shift_hop_field needs a single-source field")
    if hops.max() >= max_hop_of(hops.dtype):
        raise OverflowError(f"shifted distances would exceed what {hops.dtype} holds")
    n = graph.n_nodes
    out = np.empty_like(hops)
    queue = np.empty(n, dtype=np.int32)
    mark = np.zeros(n, dtype=np.int32)
    old_source = int(zeros[0])
    if method == "cone":
        _shift_source_lattice(width, mask, hops, out, int(new_source), queue)
    elif method == "complement":
        _shift_by_complement(width, mask, hops, out, int(new_source), old_source, mark, 1,
                             queue)
    elif method == "complement-bits":
        _shift_by_complement_bits(width, mask, hops, out, int(new_source), old_source, queue)
    elif method == "auto":
        col_free, row_free = free_counts(hops >= 0, width)
        _shift_lattice(width, mask, hops, out, int(new_source), old_source, col_free, row_free,
                       mark, 1, queue, int(hops.max()))
    else:
        raise ValueError(
            f"method must be auto, cone, complement or complement-bits, got {method!r}")
    return out


def free_counts(free: np.ndarray, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Per grid column and per grid row, how many vertices of a ``width``-wide lattice are
    ``free`` (int64): what :func:`_shift_lattice` guesses a shift's cone size from."""
    grid = free.reshape(-1, width)
    return grid.sum(axis=0, dtype=np.int64), grid.sum(axis=1, dtype=np.int64)


def hops_to_distances(hops: np.ndarray, step: float) -> np.ndarray:
    """``hops * step`` with ``inf`` for unreached vertices: the float field of a hop field."""
    out = hops * step
    out[hops < 0] = np.inf
    return out


def steps_towards(graph: NodeGraph, field_to_target: np.ndarray, node: int) -> np.ndarray:
    """Neighbours of ``node`` that lie on a shortest path to the target of the field.

    ``field_to_target`` is the distance field *from* the target (graphs are undirected).
    """
    nbrs = graph.neighbors(node)
    return on_path_neighbors(graph, node, field_to_target[node], field_to_target[nbrs])


def on_path_neighbors(
    graph: NodeGraph, node: int, d_node: float, d_nbrs: np.ndarray
) -> np.ndarray:
    """:func:`steps_towards` given only the field's values at ``node`` and its neighbours
    (in CSR order), for callers that hold the field in another form (hop counts)."""
    nbrs = graph.neighbors(node)
    if not np.isfinite(d_node):
        return nbrs[:0]
    w = graph.neighbor_weights(node)
    # np.isclose(d_nbrs + w, d_node, rtol=1e-9, atol=1e-9) for a finite d_node, written
    # out: the same float operations without its generic set-up cost
    on_path = np.abs(d_nbrs + w - d_node) <= 1e-9 + 1e-9 * abs(d_node)
    return nbrs[on_path]
