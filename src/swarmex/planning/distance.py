"""Distance fields on a :class:`~swarmex.worlds.NodeGraph`, from one or many sources.

A distance field is a float array with one entry per vertex: the shortest-path length from
the nearest source, ``inf`` where unreachable. Vertices flagged in ``blocked`` are never
entered (a blocked source still radiates, which is how an agent standing on a vertex that
turned out to be an obstacle is handled: it does not occur in the missions, but the kernel
stays total).

Kernels are numba-compiled loops over the CSR arrays: breadth-first search when all edges
have one length (grids), a binary-heap Dijkstra otherwise. Many *separate* fields (one per
source) are computed in one call by :func:`distance_fields`, which is what MADGTA needs: the
distance from every agent to every candidate vertex.
"""

from __future__ import annotations

from collections.abc import Sequence

import numba as nb
import numpy as np

from swarmex.worlds.nodegraph import NodeGraph


@nb.njit(cache=True, nogil=True)
def _bfs(indptr, indices, step, blocked, sources, out):  # pragma: no cover - compiled
    n = indptr.shape[0] - 1
    hops = np.full(n, -1, dtype=np.int64)
    queue = np.empty(n, dtype=np.int64)
    head = 0
    tail = 0
    for s in sources:
        if hops[s] < 0:
            hops[s] = 0
            queue[tail] = s
            tail += 1
    while head < tail:
        u = queue[head]
        head += 1
        hu = hops[u] + 1
        for k in range(indptr[u], indptr[u + 1]):
            v = indices[k]
            if hops[v] < 0 and not blocked[v]:
                hops[v] = hu
                queue[tail] = v
                tail += 1
    for i in range(n):
        out[i] = hops[i] * step if hops[i] >= 0 else np.inf


@nb.njit(cache=True, nogil=True)
def _dijkstra(indptr, indices, weights, blocked, sources, out):  # pragma: no cover - compiled
    n = indptr.shape[0] - 1
    for i in range(n):
        out[i] = np.inf
    done = np.zeros(n, dtype=np.bool_)
    # binary heap of (distance, vertex) in two parallel arrays
    cap = indices.shape[0] + sources.shape[0] + 1
    hd = np.empty(cap, dtype=np.float64)
    hv = np.empty(cap, dtype=np.int64)
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


def _as_sources(sources: int | Sequence[int] | np.ndarray) -> np.ndarray:
    return np.atleast_1d(np.asarray(sources, dtype=np.int64))


def distance_field(
    graph: NodeGraph,
    sources: int | Sequence[int] | np.ndarray,
    blocked: np.ndarray | None = None,
) -> np.ndarray:
    """Shortest-path length from the nearest of ``sources`` to every vertex."""
    src = _as_sources(sources)
    if blocked is None:
        blocked = np.zeros(graph.n_nodes, dtype=bool)
    out = np.empty(graph.n_nodes, dtype=np.float64)
    if graph.uniform:
        step = float(graph.weights[0]) if graph.weights.size else 1.0
        _bfs(graph.indptr, graph.indices, step, blocked, src, out)
    else:
        _dijkstra(graph.indptr, graph.indices, graph.weights, blocked, src, out)
    return out


def distance_fields(
    graph: NodeGraph,
    sources: Sequence[int] | np.ndarray,
    blocked: np.ndarray | None = None,
) -> np.ndarray:
    """One separate field per source: array of shape ``(len(sources), n_nodes)``."""
    src = _as_sources(sources)
    return np.stack([distance_field(graph, int(s), blocked) for s in src]) if src.size else (
        np.empty((0, graph.n_nodes))
    )


def steps_towards(graph: NodeGraph, field_to_target: np.ndarray, node: int) -> np.ndarray:
    """Neighbours of ``node`` that lie on a shortest path to the target of the field.

    ``field_to_target`` is the distance field *from* the target (graphs are undirected).
    """
    nbrs = graph.neighbors(node)
    w = graph.neighbor_weights(node)
    d = field_to_target[node]
    if not np.isfinite(d):
        return nbrs[:0]
    on_path = np.isclose(field_to_target[nbrs] + w, d, rtol=1e-9, atol=1e-9)
    return nbrs[on_path]
