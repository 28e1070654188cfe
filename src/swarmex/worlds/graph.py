"""GraphWorld: any undirected graph (networkx) whose vertices may be obstacles.

This is the thesis's own model (seed 000 §3.1): the job is done at vertices, an obstacle is a
vertex that cannot be entered, and it is only detected from an adjacent vertex. Vertices of
any degree are allowed. Edge length comes from the edge attribute ``weight`` (default 1);
positions from the node attribute ``pos`` or, failing that, a seeded spring layout (used only
for drawing and for the ``x, y`` of trajectories).
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.nodegraph import NodeGraph

if TYPE_CHECKING:  # networkx costs ~0.15 s to import; grid-only runs never need it
    import networkx as nx


class GraphWorld:
    kind = "graph"

    def __init__(
        self,
        graph: nx.Graph,
        obstacles: Iterable[Hashable] = (),
        weight: str = "weight",
        source: str = "networkx",
    ) -> None:
        if graph.is_directed():
            raise InputError("GraphWorld needs an undirected graph")
        if graph.number_of_nodes() == 0:
            raise InputError("graph has no vertices")
        self.nx_graph = graph
        self.labels: list[Hashable] = list(graph.nodes)
        self.index = {label: i for i, label in enumerate(self.labels)}
        blocked = np.zeros(len(self.labels), dtype=bool)
        for o in obstacles:
            if o not in self.index:
                raise InputError(f"obstacle {o!r} is not a vertex of the graph")
            blocked[self.index[o]] = True
        self._blocked = blocked
        self.weight = weight
        self.source = source

    @property
    def n_nodes(self) -> int:
        return len(self.labels)

    @property
    def blocked(self) -> np.ndarray:
        return self._blocked

    @property
    def free_cells(self) -> int:
        return int((~self._blocked).sum())

    def node(self, label: Hashable) -> int:
        try:
            return self.index[label]
        except KeyError:
            raise InputError(f"{label!r} is not a vertex of the graph") from None

    def label(self, node: int) -> str:
        return str(self.labels[node])

    def xy(self, node: int) -> tuple[float, float]:
        x, y = self.graph.pos[node]
        return float(x), float(y)

    @cached_property
    def graph(self) -> NodeGraph:
        g = self.nx_graph
        n = len(self.labels)
        edges = [
            (self.index[a], self.index[b], d.get(self.weight, 1.0))
            for a, b, d in g.edges(data=True)
            if a != b
        ]
        if edges:
            u, v, w = (np.array(c) for c in zip(*edges, strict=True))
        else:
            u = v = np.zeros(0, dtype=np.int64)
            w = np.zeros(0)
        if np.any(np.asarray(w, dtype=float) <= 0):
            raise InputError("edge lengths must be positive")
        import networkx as nx

        pos_attr = nx.get_node_attributes(g, "pos")
        if len(pos_attr) == n:
            pos = np.array([pos_attr[label] for label in self.labels], dtype=float)
        else:
            layout = nx.spring_layout(g, seed=0)
            pos = np.array([layout[label] for label in self.labels], dtype=float)
        return NodeGraph.from_edges(n, u, v, w, pos)

    def describe(self) -> dict[str, Any]:
        return {
            "kind": "graph",
            "source": self.source,
            "width": None,
            "height": None,
            "nodes": self.n_nodes,
            "edges": self.nx_graph.number_of_edges(),
            "free_cells": self.free_cells,
        }

    def __repr__(self) -> str:
        return f"GraphWorld({self.n_nodes} vertices, {self.free_cells} free, {self.source})"
