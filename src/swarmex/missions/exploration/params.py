"""Parameters of one exploration run, validated up front with messages naming the option.

Defaults are the thesis's experiment (ch. 4) where it gives them — 5 cm cells, 100 ms ticks,
planning every 2 s, heartbeats every 1 s, a 2 m laser — and swarmex's choices where it does
not (spec §6.11–6.12): a robot of radius 0.1 m, a 10 m radio, 360 beams, a 3 s neighbour
timeout, and robots starting as a compact group around the free cell nearest the map's
centre (the thesis does not give start positions; a common start makes the team's initial
dispersion, Fig. 4.3(a), part of the run).
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.exploration.paths import distance_steps, footprint_offsets, inflate
from swarmex.missions.exploration.strategies import get_strategy
from swarmex.worlds.metric import MetricGrid

Cell = tuple[int, int]
TICK_SECONDS = 0.1


@dataclass(frozen=True)
class ExplorationParams:
    robots: int = 1
    laser_range: float = 2.0  # metres
    comm_range: float = 10.0  # metres (inf: everyone hears everyone)
    strategy: str = "greedy-exclusion"
    robot_radius: float = 0.1  # metres
    beams: int = 360
    starts: tuple[Cell, ...] | None = None  # cells (x, y); default: a group at the centre
    seed: int = 0
    max_ticks: int | None = None  # default: generous, from the map size (see max_ticks_for)
    plan_period: int = 20  # ticks (2 s)
    heartbeat_period: int = 10  # ticks (1 s)
    neighbour_timeout: int = 30  # ticks (3 s)
    aodv: bool = True  # route unicasts (NEED_MAP, MAP, CHANGE_GOAL) with AODV (simulator)
    # a robot that lost a goal conflict leaves the winner's zone even when every candidate
    # is in some zone (off: it falls back on plain greedy, usually the same goal)
    conflict_yield: bool = False
    # ticks a robot stands still after each plan generation (planning time; 0: instantaneous)
    plan_pause: int = 0

    def as_dict(self) -> dict:
        d = asdict(self)
        d["starts"] = None if self.starts is None else [list(s) for s in self.starts]
        d["comm_range"] = None if math.isinf(self.comm_range) else self.comm_range
        return d


def parse_starts(text: str | None) -> tuple[Cell, ...] | None:
    """``"x,y;x,y"`` (cells) → tuple of cells."""
    if text is None or not text.strip():
        return None
    out = []
    for part in text.split(";"):
        m = re.fullmatch(r"\s*(-?\d+)\s*,\s*(-?\d+)\s*", part)
        if not m:
            raise InputError(f"--starts must be 'x,y;x,y;…' in cells, got {part.strip()!r}")
        out.append((int(m.group(1)), int(m.group(2))))
    return tuple(out)


def validate(params: ExplorationParams, grid: MetricGrid) -> None:
    get_strategy(params.strategy)
    if params.robots < 1:
        raise InputError(f"--robots must be at least 1, got {params.robots}")
    for name, v in (
        ("--laser-range", params.laser_range),
        ("--comm-range", params.comm_range),
        ("--robot-radius", params.robot_radius),
    ):
        if math.isnan(v) or v <= 0:
            raise InputError(f"{name} must be a positive number of metres, got {v:g}")
    if math.isinf(params.laser_range) or params.laser_range < 2 * grid.cell:
        raise InputError(
            f"--laser-range must be finite and at least two cells ({2 * grid.cell:g} m), "
            f"got {params.laser_range:g}"
        )
    if params.beams < 8:
        raise InputError(f"the laser needs at least 8 beams, got {params.beams}")
    for name in ("plan_period", "heartbeat_period", "neighbour_timeout"):
        if getattr(params, name) < 1:
            raise InputError(f"{name} must be at least one tick")
    if params.plan_pause < 0:
        raise InputError(f"plan_pause must be zero or more ticks, got {params.plan_pause}")
    if params.max_ticks is not None and params.max_ticks < 1:
        raise InputError(f"--max-ticks must be positive, got {params.max_ticks}")
    if params.starts is not None:
        if len(params.starts) != params.robots:
            raise InputError(
                f"--starts gives {len(params.starts)} cells for {params.robots} robots"
            )
        h, w = grid.shape
        for x, y in params.starts:
            if not (0 <= x < w and 0 <= y < h):
                raise InputError(f"start ({x},{y}) is outside the {w}x{h} map")
            if not grid.free[y, x]:
                raise InputError(f"start ({x},{y}) is inside a wall")


def min_region_cells(radius_cells: float) -> int:
    """Frontier regions "comparable to the size of the robot": at least its diameter."""
    return max(1, int(math.floor(2.0 * radius_cells)))


def max_ticks_for(grid: MetricGrid, laser_range: float) -> int:
    """A cap no sensible run reaches: six sweeps of the free area at one laser width."""
    return max(2000, int(6 * grid.world.free_cells / max(1.0, grid.cells(laser_range))))


def default_starts(grid: MetricGrid, n: int, radius_m: float) -> tuple[Cell, ...]:
    """``n`` cells around the traversable cell nearest the centre, a robot diameter apart."""
    r = radius_m / grid.cell
    trav = grid.free & ~inflate(~grid.free, footprint_offsets(r))
    if not trav.any():
        trav = grid.free
    h, w = grid.shape
    ys, xs = np.nonzero(trav)
    c = int(np.argmin((ys - (h - 1) / 2) ** 2 + (xs - (w - 1) / 2) ** 2))
    dist = distance_steps(trav, int(xs[c]), int(ys[c]))
    ry, rx = np.nonzero(dist >= 0)
    order = np.lexsort((rx, ry, dist[ry, rx]))
    spacing = int(math.ceil(2 * r)) + 1
    chosen: list[Cell] = []
    for i in order:
        x, y = int(rx[i]), int(ry[i])
        if all(max(abs(x - a), abs(y - b)) >= spacing for a, b in chosen):
            chosen.append((x, y))
            if len(chosen) == n:
                return tuple(chosen)
    raise InputError(f"the map has room for only {len(chosen)} robots, not {n}")
