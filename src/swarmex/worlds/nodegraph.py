"""A compressed (CSR) adjacency shared by every discrete world.

Grids and general graphs both become a :class:`NodeGraph`: vertex ``i``'s neighbours are
``indices[indptr[i]:indptr[i+1]]`` with edge lengths ``weights[...]``. Obstacle vertices stay
in the graph (agents must be able to *see* them next to them); whether a vertex may be
entered is a separate boolean mask, so one adjacency serves every agent's belief.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True, eq=False)
class NodeGraph:
    """Undirected graph in CSR form with vertex positions.

    ``uniform`` is true when every edge has the same length, which lets distance kernels use
    breadth-first search instead of Dijkstra.
    """

    indptr: np.ndarray
    indices: np.ndarray
    weights: np.ndarray
    pos: np.ndarray
    uniform: bool = field(default=False)

    @property
    def n_nodes(self) -> int:
        return int(self.indptr.shape[0] - 1)

    @property
    def n_edges(self) -> int:
        """Undirected edge count (each is stored twice)."""
        return int(self.indices.shape[0] // 2)

    def neighbors(self, v: int) -> np.ndarray:
        return self.indices[self.indptr[v] : self.indptr[v + 1]]

    def neighbor_weights(self, v: int) -> np.ndarray:
        return self.weights[self.indptr[v] : self.indptr[v + 1]]

    def edge_length(self, u: int, v: int) -> float:
        nbrs = self.neighbors(u)
        hit = np.nonzero(nbrs == v)[0]
        if hit.size == 0:
            raise KeyError(f"no edge between {u} and {v}")
        return float(self.neighbor_weights(u)[hit[0]])

    @classmethod
    def from_edges(
        cls, n: int, u: np.ndarray, v: np.ndarray, w: np.ndarray, pos: np.ndarray
    ) -> NodeGraph:
        """Build from undirected edge arrays (each edge given once)."""
        u = np.asarray(u, dtype=np.int64)
        v = np.asarray(v, dtype=np.int64)
        w = np.asarray(w, dtype=np.float64)
        src = np.concatenate([u, v])
        dst = np.concatenate([v, u])
        ww = np.concatenate([w, w])
        order = np.lexsort((dst, src))
        src, dst, ww = src[order], dst[order], ww[order]
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.add.at(indptr, src + 1, 1)
        np.cumsum(indptr, out=indptr)
        uniform = bool(ww.size == 0 or np.allclose(ww, ww[0]))
        return cls(indptr, dst.astype(np.int32), ww, np.asarray(pos, dtype=np.float64), uniform)
