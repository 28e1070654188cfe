"""Visual coverage of a PolygonWorld measured on a fine raster of the free space.

The sensor of seed 004 is "agents' sensor range" r (2r, 4r, ∞ in the tables); the paper gives
no model, and its ∞-range coverage of 99 % rather than 100 % says walls block sight. So the
sensor here is a disc of radius R cut by line of sight, and it senses *continuously*: along
every traversed segment viewpoints are placed at most one raster cell apart, so the swept area
is right to within half a cell (sensing only at nodes would under-count long edges).

Coverage = seen free cells / free cells, where a cell is free when its centre is free and seen
when its centre is visible from some viewpoint. The raster has ``cells`` cells along the
longer side of the bounds (default 256: 2.5 units per cell on the 640 × 480 reproduction
environments, i.e. 1/8 of the smaller step ε = 20), square cells, ``ceil`` on the other side.
Each cell stores the step it was first seen (``seen_at``), which gives coverage-over-time
curves and animation frames for free.

A segment is sensed once: a second traversal of the same roadmap edge sees exactly the same
cells, so callers may skip it (the simulations do, per undirected edge).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from swarmex.sensing.visibility import first_sighting, sweep_segment
from swarmex.worlds.polygon import PolygonWorld

DEFAULT_CELLS = 256
BLOCK = 8


class CoverageRaster:
    def __init__(self, world: PolygonWorld, sensor_range: float, cells: int = DEFAULT_CELLS):
        if not sensor_range > 0:
            raise ValueError("sensor range must be positive")
        self.world = world
        self.sensor_range = float(sensor_range)
        xmin, ymin, xmax, ymax = world.bounds
        self.h = max(world.width, world.height) / cells
        self.nx = max(1, math.ceil(world.width / self.h - 1e-9))
        self.ny = max(1, math.ceil(world.height / self.h - 1e-9))
        self.x0, self.y0 = xmin, ymin
        cx = xmin + (np.arange(self.nx) + 0.5) * self.h
        cy = ymin + (np.arange(self.ny) + 0.5) * self.h
        gx, gy = np.meshgrid(cx, cy)
        self.free = world.points_free(np.column_stack([gx.ravel(), gy.ravel()])).reshape(
            self.ny, self.nx
        )
        self.free_cells = int(self.free.sum())
        self.seen_at = np.full((self.ny, self.nx), -1, dtype=np.int64)
        self._blocker = np.full((self.ny, self.nx), -1, dtype=np.int64)
        self._edges = np.ascontiguousarray(world.edges)
        # blocks of BLOCK × BLOCK cells let one shadow test dismiss 64 hidden cells at once
        bny, bnx = -(-self.ny // BLOCK), -(-self.nx // BLOCK)
        pad = np.zeros((bny * BLOCK, bnx * BLOCK), dtype=np.int64)
        pad[: self.ny, : self.nx] = self.free
        self._block_unseen = pad.reshape(bny, BLOCK, bnx, BLOCK).sum(axis=(1, 3))
        self._block_hint = np.full((bny, bnx), -1, dtype=np.int64)
        self.seen_cells = 0

    @property
    def spacing(self) -> float:
        return self.h

    def sense_segment(self, a: np.ndarray, b: np.ndarray, t: int) -> int:
        """Sweep the sensor from a to b at step t; returns how many cells became seen."""
        new = sweep_segment(
            float(a[0]), float(a[1]), float(b[0]), float(b[1]), self.sensor_range, self.h,
            self.x0, self.y0, self.h, self.free, self.seen_at, self._blocker,
            self._block_unseen, self._block_hint, BLOCK, self._edges, int(t),
        )
        self.seen_cells += new
        return int(new)

    def sighting(self, a: np.ndarray, b: np.ndarray, goal: np.ndarray) -> float:
        """First fraction along a→b from which ``goal`` is seen, or -1."""
        return float(first_sighting(
            float(a[0]), float(a[1]), float(b[0]), float(b[1]), float(goal[0]),
            float(goal[1]), self.sensor_range, self.h, self._edges,
        ))

    def coverage(self) -> float:
        return self.seen_cells / self.free_cells if self.free_cells else 0.0

    def seen_mask(self, t: int | None = None) -> np.ndarray:
        if t is None:
            return self.seen_at >= 0
        return (self.seen_at >= 0) & (self.seen_at <= t)

    def curve(self, steps: int) -> list[float]:
        """Coverage after each step 0..steps (from ``seen_at``)."""
        if not self.free_cells:
            return [0.0] * (steps + 1)
        at = self.seen_at[self.seen_at >= 0]
        counts = np.bincount(np.minimum(at, steps), minlength=steps + 1)
        return (np.cumsum(counts) / self.free_cells).tolist()

    def describe(self) -> dict[str, Any]:
        return {"cells_x": self.nx, "cells_y": self.ny, "cell_size": self.h,
                "free_cells": self.free_cells}
