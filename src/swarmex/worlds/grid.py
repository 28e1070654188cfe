"""GridWorld: a rectangular map of free and blocked cells, stored as one numpy bool array.

Cells are addressed ``(x = column, y = row)`` with row 0 the first map row, as in MovingAI
files and the result record. Vertex index of a cell is ``y * width + x``.

Connectivity: 4 (the studies' grids) or 8. With 8, a diagonal step has length sqrt(2) and is
only an edge when both orthogonal cells it passes are free (the MovingAI no-corner-cutting
rule); that rule is applied to the *true* map once, when the adjacency is built, because a
diagonal squeeze between two walls is a property of the terrain, not of anyone's knowledge.
"""

from __future__ import annotations

from functools import cached_property
from typing import Any

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.nodegraph import NodeGraph


class GridWorld:
    kind = "grid"

    def __init__(
        self,
        free: np.ndarray,
        connectivity: int = 4,
        source: str = "generated",
        terrain: np.ndarray | None = None,
    ) -> None:
        free = np.asarray(free, dtype=bool)
        if free.ndim != 2 or free.shape[0] < 1 or free.shape[1] < 1:
            raise InputError(f"grid must be a non-empty 2-D array, got shape {free.shape}")
        if connectivity not in (4, 8):
            raise InputError(f"connectivity must be 4 or 8, got {connectivity}")
        self.free = free
        self.connectivity = connectivity
        self.source = source
        self.terrain = terrain

    @property
    def height(self) -> int:
        return int(self.free.shape[0])

    @property
    def width(self) -> int:
        return int(self.free.shape[1])

    @property
    def n_nodes(self) -> int:
        return self.free.size

    @property
    def free_cells(self) -> int:
        return int(self.free.sum())

    @property
    def blocked(self) -> np.ndarray:
        """Truth: which vertices are obstacles (flat, one per cell)."""
        return ~self.free.ravel()

    def node(self, x: int, y: int) -> int:
        return int(y) * self.width + int(x)

    def xy(self, node: int) -> tuple[int, int]:
        return int(node) % self.width, int(node) // self.width

    def in_bounds(self, x: int, y: int) -> bool:
        return 0 <= x < self.width and 0 <= y < self.height

    def label(self, node: int) -> str:
        x, y = self.xy(node)
        return f"({x},{y})"

    @cached_property
    def graph(self) -> NodeGraph:
        u, v, lengths = self.edge_arrays()
        h, w = self.free.shape
        ys, xs = np.divmod(np.arange(h * w), w)
        pos = np.stack([xs, ys], axis=1).astype(np.float64)
        return NodeGraph.from_edges(h * w, u, v, self.edge_lengths(u, v, lengths), pos)

    def edge_lengths(self, u: np.ndarray, v: np.ndarray, unit: np.ndarray) -> np.ndarray:
        """The length of each edge ``u[i]``–``v[i]``: here its length in cells (``unit``: 1,
        or √2 for a diagonal); a world with real distances (a GPS grid) overrides it."""
        return unit

    def edge_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every edge once, as (u, v, length in cells), in a fixed order: rows' horizontal
        edges, columns' vertical ones, then the diagonals of connectivity 8."""
        h, w = self.free.shape
        idx = np.arange(h * w, dtype=np.int64).reshape(h, w)
        us = [idx[:, :-1].ravel(), idx[:-1, :].ravel()]
        vs = [idx[:, 1:].ravel(), idx[1:, :].ravel()]
        ws = [np.ones(h * (w - 1)), np.ones((h - 1) * w)]
        if self.connectivity == 8:
            f = self.free
            # down-right and down-left diagonals, without corner cutting
            ok_dr = f[:-1, 1:] & f[1:, :-1]  # the two orthogonal cells of a (y,x)->(y+1,x+1) step
            ok_dl = f[:-1, :-1] & f[1:, 1:]  # the two orthogonal cells of a (y,x+1)->(y+1,x) step
            us += [idx[:-1, :-1][ok_dr], idx[:-1, 1:][ok_dl]]
            vs += [idx[1:, 1:][ok_dr], idx[1:, :-1][ok_dl]]
            ws += [np.full(int(ok_dr.sum()), np.sqrt(2.0)), np.full(int(ok_dl.sum()), np.sqrt(2.0))]
        return np.concatenate(us), np.concatenate(vs), np.concatenate(ws)

    def describe(self) -> dict[str, Any]:
        return {
            "kind": "grid",
            "source": self.source,
            "width": self.width,
            "height": self.height,
            "connectivity": self.connectivity,
            "free_cells": self.free_cells,
        }

    def __repr__(self) -> str:
        return f"GridWorld({self.width}x{self.height}, {self.free_cells} free, {self.source})"
