"""Distance fields that follow a growing set of known obstacles without being recomputed.

MADGTA needs, at every decision, the travel distance from every agent's node to every
candidate vertex, on the graph minus the obstacles known so far. Agents discover obstacles
one by one, so naive caching would throw every field away at every discovery.
:class:`KnownGraph` instead keeps a log of discoveries and, when a cached field is asked for,
checks whether the new obstacles can change it at all (:func:`_still_exact`); only then is it
recomputed. The check is exact: a field is unchanged by blocking a set of vertices iff every
vertex whose shortest path could run through them keeps another shortest-path predecessor.
"""

from __future__ import annotations

from collections import OrderedDict

import numba as nb
import numpy as np

from swarmex.planning.distance import distance_field
from swarmex.worlds.nodegraph import NodeGraph


@nb.njit(cache=True, nogil=True)
def _still_exact(indptr, indices, weights, blocked, field, new_obstacles):  # pragma: no cover
    for o in new_obstacles:
        do = field[o]
        if not np.isfinite(do):
            continue
        for k in range(indptr[o], indptr[o + 1]):
            u = indices[k]
            if blocked[u]:
                continue
            du = field[u]
            if abs(du - (do + weights[k])) > 1e-9 * (1.0 + du):
                continue
            ok = False
            for j in range(indptr[u], indptr[u + 1]):
                x = indices[j]
                if blocked[x]:
                    continue
                if abs(field[x] + weights[j] - du) <= 1e-9 * (1.0 + du):
                    ok = True
                    break
            if not ok:
                return False
    return True


class KnownGraph:
    """A graph plus the obstacles someone knows about, with a cache of distance fields.

    ``blocked`` only ever gains vertices (obstacles are static), which is what makes the
    incremental validity check sound.
    """

    def __init__(self, graph: NodeGraph, capacity: int = 64) -> None:
        self.graph = graph
        self.blocked = np.zeros(graph.n_nodes, dtype=bool)
        self._log: list[int] = []
        self._cache: OrderedDict[int, tuple[np.ndarray, int]] = OrderedDict()
        self.capacity = capacity
        self.recomputed = 0
        self.reused = 0

    @property
    def version(self) -> int:
        return len(self._log)

    def add_obstacles(self, vertices) -> bool:
        """Mark vertices as known obstacles; returns True if any was new."""
        new = False
        for v in vertices:
            v = int(v)
            if not self.blocked[v]:
                self.blocked[v] = True
                self._log.append(v)
                new = True
        return new

    def field(self, source: int) -> np.ndarray:
        """Distance from ``source`` to every vertex on the graph minus known obstacles.

        The returned array is shared with the cache: read it, never write it.
        """
        hit = self._cache.get(source)
        if hit is not None:
            fld, ver = hit
            if ver == self.version:
                self._cache.move_to_end(source)
                self.reused += 1
                return fld
            g = self.graph
            new = np.asarray(self._log[ver:], dtype=np.int64)
            if _still_exact(g.indptr, g.indices, g.weights, self.blocked, fld, new):
                fld[new] = np.inf
                fld[source] = 0.0
                self._cache[source] = (fld, self.version)
                self._cache.move_to_end(source)
                self.reused += 1
                return fld
        fld = distance_field(self.graph, source, self.blocked)
        self.recomputed += 1
        self._cache[source] = (fld, self.version)
        self._cache.move_to_end(source)
        while len(self._cache) > self.capacity:
            self._cache.popitem(last=False)
        return fld
