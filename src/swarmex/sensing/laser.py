"""A simulated 360° laser rangefinder, ray-cast against the true grid.

Seed 003 gives only the range (1.5 m or 2 m); the beam count, field of view and noise are
open (spec §6.10). swarmex's sensor, and why:

* **360° field of view, 360 beams by default** (1°): at 2 m and 5 cm cells the gap between
  neighbouring beams at full range is 0.7 cells, so a scan leaves no unseen holes inside its
  disc. ``beams`` is a parameter.
* **Noise-free.** The thesis simulates scans from the map file; its framework's noise model is
  not described. Without noise an occupied cell is only ever *hit* and a free cell only ever
  *passed*, which makes "unknown = exactly 0.5" a stable notion (see occupancy.py).
* **Beam angles** ``angle0 + i·2π/beams`` with a small irrational ``angle0``, so that a beam
  from a cell centre never passes *exactly* through a grid corner: every beam's walk then
  enters cells at strictly increasing distances, and the range alone identifies the hit cell
  when the scan is turned into a local map (:func:`swarmex.sensing.occupancy.rasterise`).
* **The sensor sits at the centre of the robot's cell**; everything is in cells inside the
  kernels (metres are converted once, by :class:`Laser`). Outside the map counts as wall.

The kernel is the Amanatides–Woo grid walk: a beam visits the 4-connected sequence of cells
it crosses (it cannot slip diagonally between two wall cells touching at a corner), and its
range is the distance at which it *enters* the first blocked cell. Crossing distances are
computed as ``(k + 0.5) · Δ`` from integer counts rather than accumulated, so the rasteriser
recomputes them bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.errors import InputError

# (sqrt(5) - 1) / 2 of a 1° step: far from every angle through a corner of a small grid
ANGLE0_FRACTION = 0.6180339887498949


@kernel(cache=True, nogil=True, inline="always")
def _axis(d: float) -> tuple[int, float]:  # pragma: no cover - compiled
    """Step direction and crossing spacing of one axis (Δ = inf when the beam is parallel)."""
    if d > 0.0:
        return 1, 1.0 / d
    if d < 0.0:
        return -1, -1.0 / d
    return 0, np.inf


@kernel(cache=True, nogil=True, inline="always")
def _cross(
    kx: int, ky: int, cx: int, cy: int, sx: int, sy: int, ddx: float, ddy: float,
) -> tuple[float, int, int, int, int]:  # pragma: no cover - compiled
    """One step of the grid walk of a beam from a cell centre (Amanatides & Woo): the
    distance ``t`` (cells) at which it enters the next cell, and the updated crossing
    counts (kx, ky) and cell (cx, cy). Shared by the laser, the rasteriser and the
    exploration bound, so all three pass exactly the same cells."""
    tx = (kx + 0.5) * ddx
    ty = (ky + 0.5) * ddy
    if tx < ty:
        return tx, kx + 1, ky, cx + sx, cy
    return ty, kx, ky + 1, cx, cy + sy


@kernel(cache=True, nogil=True)
def cast_rays_cells(
    free: NDArray[np.bool_], x0: int, y0: int, angles: NDArray[np.float64], max_cells: float,
    out: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Range (cells) of every beam from the centre of cell (x0, y0); ``max_cells`` if no hit."""
    h, w = free.shape
    for b in range(angles.shape[0]):
        dx = math.cos(angles[b])
        dy = math.sin(angles[b])
        sx, ddx = _axis(dx)
        sy, ddy = _axis(dy)
        kx = 0
        ky = 0
        cx = x0
        cy = y0
        r = max_cells
        while True:
            t, kx, ky, cx, cy = _cross(kx, ky, cx, cy, sx, sy, ddx, ddy)
            if t >= max_cells:
                break
            if cx < 0 or cy < 0 or cx >= w or cy >= h or not free[cy, cx]:
                r = t
                break
        out[b] = r


@dataclass(frozen=True)
class Laser:
    """Sensor geometry in metres, with the conversions to cells of one map."""

    range_m: float = 2.0
    beams: int = 360
    cell: float = 0.05

    def __post_init__(self) -> None:
        if not (math.isfinite(self.range_m) and self.range_m > 0):
            raise InputError(
                f"--laser-range must be a positive number of metres, got {self.range_m}"
            )
        if self.beams < 4:
            raise InputError(f"the laser needs at least 4 beams, got {self.beams}")
        if not self.cell > 0:
            raise InputError(f"cell size must be positive, got {self.cell}")

    @property
    def range_cells(self) -> float:
        return self.range_m / self.cell

    @cached_property
    def angles(self) -> np.ndarray:
        step = 2.0 * math.pi / self.beams
        return (ANGLE0_FRACTION + np.arange(self.beams)) * step

    def cast(self, free: np.ndarray, x: int, y: int) -> np.ndarray:
        """Ranges in cells from cell (x, y) against the truth ``free[row, col]``."""
        out = np.empty(self.beams, dtype=np.float64)
        cast_rays_cells(free, int(x), int(y), self.angles, self.range_cells, out)
        return out
