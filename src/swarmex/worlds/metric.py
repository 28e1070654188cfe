"""Metric grids: a :class:`GridWorld` plus the size of one cell in metres.

Seed 003 measures everything in metres (a 20 × 20 m terrain, a 2 m laser, a 10 m radio) on
an occupancy grid of 5 cm cells. A :class:`MetricGrid` carries that scale next to the cell
array so sensing and communication can convert once, at the boundary, and every kernel keeps
working in cells. Outside the array counts as wall: a laser beam stops at the map edge.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.grid import GridWorld
from swarmex.worlds.mapfiles import is_ros_map

DEFAULT_CELL = 0.05  # metres, the thesis's 5 cm × 5 cm cell

_SIZE = re.compile(r"^\s*([0-9]*\.?[0-9]+)\s*[xX×]\s*([0-9]*\.?[0-9]+)\s*$")


@dataclass(frozen=True)
class MetricGrid:
    world: GridWorld
    cell: float  # metres per cell side

    def __post_init__(self) -> None:
        if not (math.isfinite(self.cell) and self.cell > 0):
            raise InputError(f"--cell must be a positive number of metres, got {self.cell}")

    @property
    def free(self) -> np.ndarray:
        return self.world.free

    @property
    def shape(self) -> tuple[int, int]:
        return self.world.free.shape  # (rows, cols)

    def cells(self, metres: float) -> float:
        """A length in metres expressed in cells (not rounded)."""
        return metres / self.cell

    def describe(self) -> dict[str, Any]:
        d = self.world.describe()
        d["cell_m"] = self.cell
        d["width_m"] = self.world.width * self.cell
        d["height_m"] = self.world.height * self.cell
        return d


def parse_size(text: str) -> tuple[float, float]:
    """``"20x20"`` → (20.0, 20.0) metres; the message names the option."""
    m = _SIZE.match(text or "")
    if not m:
        raise InputError(f"--empty must look like WxH in metres (e.g. 20x20), got {text!r}")
    w, h = float(m.group(1)), float(m.group(2))
    if w <= 0 or h <= 0:
        raise InputError(f"--empty sizes must be positive, got {text!r}")
    return w, h


def empty_metric(width_m: float, height_m: float, cell: float = DEFAULT_CELL) -> MetricGrid:
    """An empty rectangle of ``width_m × height_m`` metres whose outer ring of cells is wall.

    The walls are inside the size, so 20 × 20 m at 5 cm is the thesis's 400 × 400 grid.
    """
    if not (math.isfinite(cell) and cell > 0):
        raise InputError(f"--cell must be a positive number of metres, got {cell}")
    w, h = round(width_m / cell), round(height_m / cell)
    if w < 3 or h < 3:
        raise InputError(
            f"--empty {width_m:g}x{height_m:g} m at {cell:g} m cells is {w}x{h} cells; "
            "need at least 3x3 (walls around a free cell)"
        )
    if w * h > 25_000_000:
        raise InputError(
            f"--empty {width_m:g}x{height_m:g} m at {cell:g} m is {w}x{h} = {w * h:,} cells;"
            " at most 25,000,000 (a larger --cell or a smaller world)"
        )
    free = np.zeros((h, w), dtype=bool)
    free[1:-1, 1:-1] = True
    return MetricGrid(GridWorld(free, source=f"empty {width_m:g}x{height_m:g} m"), cell)


def load_metric(path: str | Path, cell: float | None = None) -> MetricGrid:
    """A MovingAI ``.map`` (cell from ``cell``) or a ROS ``.yaml``/``.pgm`` map (its resolution)."""
    from swarmex.worlds.movingai import load_movingai
    from swarmex.worlds.rosmap import load_rosmap

    p = Path(path)
    if is_ros_map(p):
        world, resolution = load_rosmap(p)
        if cell is not None and not math.isclose(cell, resolution, rel_tol=1e-6):
            raise InputError(
                f"{p}: the ROS map's resolution is {resolution:g} m per cell; "
                f"--cell {cell:g} cannot rescale it (omit --cell)"
            )
        return MetricGrid(world, resolution)
    return MetricGrid(load_movingai(p), DEFAULT_CELL if cell is None else cell)
