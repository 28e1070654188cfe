"""Roadmap: nodes, undirected straight edges and (for trees) parent/branch labels.

One plain data structure for both planners so that missions, records and replays treat them
alike: ``pos`` (V × 2), ``edges`` (E × 2, node ids), per-node adjacency as lists of
``(neighbour, edge id)``. A WMA-RRT also carries ``parent`` and ``branch`` (node 0 is the Main
Root, branch -1) and ``first_edge[k]``, the edge Main Root → Secondary Root k. ``entry`` holds,
per agent, the straight leg from its start onto the roadmap (start → Main Root for WMA-RRT,
start → nearest visible node for PRM); legs are part of the record so a replay can check them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


@dataclass
class Roadmap:
    kind: str
    pos: np.ndarray
    edges: np.ndarray
    starts: np.ndarray
    entry_node: np.ndarray  # per agent: the node its entry leg reaches (-1: none visible)
    parent: np.ndarray | None = None
    branch: np.ndarray | None = None
    first_edge: np.ndarray | None = None
    samples: int = 0
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def n_nodes(self) -> int:
        return int(len(self.pos))

    @property
    def n_edges(self) -> int:
        return int(len(self.edges))

    @cached_property
    def adjacency(self) -> list[list[tuple[int, int]]]:
        adj: list[list[tuple[int, int]]] = [[] for _ in range(self.n_nodes)]
        for e, (u, v) in enumerate(self.edges.tolist()):
            adj[u].append((v, e))
            adj[v].append((u, e))
        return adj

    @cached_property
    def edge_length(self) -> np.ndarray:
        d = self.pos[self.edges[:, 1]] - self.pos[self.edges[:, 0]]
        return np.hypot(d[:, 0], d[:, 1])

    @cached_property
    def component_labels(self) -> np.ndarray:
        n = self.n_nodes
        if self.n_edges == 0:
            return np.arange(n)
        g = coo_matrix((np.ones(self.n_edges), (self.edges[:, 0], self.edges[:, 1])), (n, n))
        return connected_components(g, directed=False)[1]

    @property
    def components(self) -> int:
        return int(len(np.unique(self.component_labels))) if self.n_nodes else 0

    @property
    def cycles(self) -> int:
        """Independent cycles (cyclomatic number E − V + C): 0 for a forest."""
        return self.n_edges - self.n_nodes + self.components

    @property
    def is_tree(self) -> bool:
        return self.parent is not None

    def to_record(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "kind": self.kind,
            "nodes": np.round(self.pos, 6).tolist(),
            "edges": self.edges.tolist(),
            "entry_node": self.entry_node.tolist(),
            "components": self.components,
            "cycles": self.cycles,
            "samples": self.samples,
        }
        if self.branch is not None:
            d["branch"] = self.branch.tolist()
            d["main_root"] = 0
        d.update(self.info)
        return d
