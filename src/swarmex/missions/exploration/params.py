"""Parameters of one exploration run, with their defaults, units and checks (the Mission
contract's Params for ``swarmex explore``, ``swarmex.run("exploration", ...)``, scenario files
and sweeps, and the simulator's own parameters).

Defaults are the thesis's experiment (ch. 4) where it gives them — 5 cm cells, 100 ms ticks,
planning every 2 s, heartbeats every 1 s, a 2 m laser — and swarmex's choices where it does
not (spec §6.11–6.12): a robot of radius 0.1 m, a 10 m radio, 360 beams, a 3 s neighbour
timeout, and robots starting as a compact group around the free cell nearest the map's
centre (the thesis does not give start positions; a common start makes the team's initial
dispersion, Fig. 4.3(a), part of the run).

Conventions (also in ``swarmex explore --help``):

* the world is exactly one of ``map`` (a MovingAI ``.map`` read at ``cell`` metres per cell,
  or a ROS ``.yaml``/``.pgm`` map at its own resolution; from Python also a ``GridWorld``
  read at ``cell``, or a ``MetricGrid`` with its own cell size) and ``empty`` (a walled
  rectangle of ``"WxH"`` or ``(W, H)`` metres at ``cell``, default 0.05 m);
* lengths are metres (``laser_range``, ``comm_range``, ``robot_radius``; ``comm_range`` may be
  ``inf``); times are steps of 100 ms (``max_ticks``, ``plan_pause``);
* ``starts`` are cells ``x,y`` (x the column, y the row, row 0 the first map row), one per
  robot: ``"1,2;3,4"`` or ``[(1, 2), (3, 4)]``.

Every value check lives in the options' parsers (and :meth:`ExplorationParams.check_run` for
the rules tying options together); :func:`validate` reruns them on Params built directly
(``ExplorationParams(robots=3, ...)``, as the simulator's tests and the reproduction do) and
adds the checks that need the world. The fields declared without :func:`option`
(``plan_period``, ``heartbeat_period``, ``neighbour_timeout``) are the simulator's own
constants: no command-line flag, the thesis's values.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.base import (
    REQUIRED,
    Params,
    Parser,
    boolean,
    cells,
    integer,
    option,
    optional,
    path_or,
    real,
    text,
)
from swarmex.missions.exploration.strategies import STRATEGIES
from swarmex.worlds.metric import MetricGrid, parse_size

if TYPE_CHECKING:
    from swarmex.worlds.grid import GridWorld

Cell = tuple[int, int]
TICK_SECONDS = 0.1
WORLD_OPTIONS = ("map", "empty", "cell")  # how the world is built: not simulator parameters


def metric_size() -> Parser:
    """``"20x20"`` or ``(20, 20)`` -> (width, height) in metres, both positive and finite."""

    def parse(value: Any, flag: str) -> tuple[float, float]:
        if isinstance(value, str):
            return parse_size(value)
        if (
            isinstance(value, Sequence)
            and len(value) == 2
            and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            w, h = float(value[0]), float(value[1])
            if not all(math.isfinite(v) and v > 0 for v in (w, h)):
                raise InputError(f"{flag} sizes must be positive, got {value!r}")
            return w, h
        raise InputError(f"{flag} must look like WxH in metres (e.g. 20x20), got {value!r}")

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def start_cells() -> Parser:
    """Cells ``"x,y;x,y"`` or pairs; ``None`` or a blank string: the default group start."""
    inner = cells()

    def parse(value: Any, flag: str) -> tuple[Cell, ...] | None:
        if value is None or (isinstance(value, str) and not value.strip()):
            return None
        return inner(value, flag)

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def _world_types() -> tuple[type, ...]:
    """The world objects ``map`` takes (imported on use: the CLI's options need no numpy)."""
    from swarmex.worlds.grid import GridWorld

    return (GridWorld, MetricGrid)


@dataclass(frozen=True)
class ExplorationParams(Params):
    mission = "exploration"
    required_one_of = (("map", "empty"),)

    map: Path | GridWorld | MetricGrid | None = option(
        None,
        help="MovingAI .map or ROS map (.yaml beside its .pgm); from Python also a GridWorld"
        " or MetricGrid.",
        parse=optional(path_or(_world_types, "a map file path, a GridWorld or a MetricGrid")),
    )
    empty: tuple[float, float] | None = option(
        None, help="Empty walled world WxH in metres.", parse=optional(metric_size())
    )
    cell: float | None = option(
        None,
        help="Cell size in metres (default 0.05; a ROS map has its own).",
        parse=optional(real(above=0)),
    )
    robots: int = option(REQUIRED, help="Team size.", parse=integer(lo=1))
    laser_range: float = option(2.0, help="Laser range, metres.", parse=real(above=0))
    # inf: everyone hears everyone
    comm_range: float = option(
        10.0, help="Radio range, metres (inf: every robot hears every other).",
        parse=real(above=0, finite=False),
    )
    strategy: str = option(
        "greedy-exclusion",
        help="greedy | greedy-exclusion | utility | minpos | hungarian | hungarian-exclusion"
        " | adaptive-exclusion",
        parse=text(tuple(STRATEGIES)),
    )
    robot_radius: float = option(0.1, help="Robot radius, metres.", parse=real(above=0))
    beams: int = option(360, help="Laser beams per 360° scan.", parse=integer(lo=8, hi=100_000))
    starts: tuple[Cell, ...] | None = option(  # default: a group at the centre
        None, help="Start cells 'x,y;x,y;…'.", parse=start_cells()
    )
    seed: int = option(0, help="Seed of every random choice.", parse=integer(lo=0))
    # default: generous, from the map size (see max_ticks_for)
    max_ticks: int | None = option(
        None, help="Stop after this many steps.", parse=optional(integer(lo=1))
    )
    plan_period: int = 20  # ticks (2 s)
    heartbeat_period: int = 10  # ticks (1 s)
    neighbour_timeout: int = 30  # ticks (3 s)
    # route unicasts (NEED_MAP, MAP, CHANGE_GOAL) with AODV (simulator and --processes)
    aodv: bool = option(
        True,
        help="Route multi-hop unicasts with AODV.",
        parse=boolean(),
        negation="--no-aodv",
    )
    # a robot that lost a goal conflict leaves the winner's zone even when every candidate
    # is in some zone (off: it falls back on plain greedy, usually the same goal)
    conflict_yield: bool = option(
        False,
        help="A goal conflict's loser must leave the winner's zone.",
        parse=boolean(),
    )
    # ticks a robot stands still after each plan generation (planning time; 0: instantaneous)
    plan_pause: int = option(
        0, help="Steps a robot stands still after each plan (0: none).", parse=integer(lo=0)
    )

    def check(self) -> None:
        if (self.map is None) == (self.empty is None):
            raise InputError("give exactly one of --map FILE and --empty WxH")
        self.check_run()

    def check_run(self) -> None:
        """The cross-field rules the simulator relies on (no world needed)."""
        for name in ("plan_period", "heartbeat_period", "neighbour_timeout"):
            if getattr(self, name) < 1:
                raise InputError(f"{name} must be at least one tick")
        if self.starts is not None and len(self.starts) != self.robots:
            raise InputError(f"--starts gives {len(self.starts)} cells for {self.robots} robots")

    def check_values(self) -> None:
        """Every option's own parser on the value it holds (for Params built directly)."""
        for name, info in self.options().items():
            info.parse(getattr(self, name), info.flag)

    def as_dict(self) -> dict:
        """The simulator's parameters (the record's ``params``, the mesh's scenario)."""
        # not asdict: it would deep-copy a world object given as ``map``, only to drop it
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in WORLD_OPTIONS}
        d["starts"] = None if self.starts is None else [list(s) for s in self.starts]
        d["comm_range"] = None if math.isinf(self.comm_range) else self.comm_range
        return d


def parse_starts(text: str | None) -> tuple[Cell, ...] | None:
    """``"x,y;x,y"`` (cells) → tuple of cells (``--starts``' own parser)."""
    return start_cells()(text, "--starts")


def validate(params: ExplorationParams, grid: MetricGrid) -> None:
    """Every option's check, then the checks that need the world (before any run)."""
    params.check_values()
    params.check_run()
    if params.laser_range < 2 * grid.cell:
        raise InputError(
            f"--laser-range must be at least two cells ({2 * grid.cell:g} m), "
            f"got {params.laser_range:g}"
        )
    if params.starts is None:  # the cheap bound first: a team no map could hold
        most = room_bound(grid, params.robot_radius)
        if params.robots > most:
            raise InputError(f"the map has room for at most {most} robots, not {params.robots}")
    check_memory(params.robots, grid.shape[0] * grid.shape[1])
    if params.starts is not None:
        h, w = grid.shape
        for x, y in params.starts:
            if not (0 <= x < w and 0 <= y < h):
                raise InputError(f"start ({x},{y}) is outside the {w}x{h} map")
            if not grid.free[y, x]:
                raise InputError(f"start ({x},{y}) is inside a wall")


#: bytes a robot's own map and its planning scratch take per cell (measured 29 Nov 2026:
#: 100 robots on 5.76 M cells peaked at 5.6 GB)
BYTES_PER_ROBOT_CELL = 10


def check_memory(robots: int, cells: int,
                 available: Callable[[], int | None] | None = None) -> None:
    """Refuse a team whose maps cannot fit: every robot keeps its own map of the whole
    world, so memory is robots x cells. Without this, a run accepted by every other check
    grew until the kernel killed it without a word (no swap) or ended in a MemoryError."""
    need = robots * cells * BYTES_PER_ROBOT_CELL
    have = (available or available_memory)()
    if have is not None and need > have:
        raise InputError(
            f"{robots} robots on {cells:,} cells need about {need / 2**30:.1f} GiB of maps "
            f"(each robot keeps its own, ~{BYTES_PER_ROBOT_CELL} bytes a cell), more than the "
            f"{have / 2**30:.1f} GiB available: fewer robots, a smaller map or a larger --cell"
        )


def available_memory() -> int | None:
    """Bytes of memory available to a new run (Linux's MemAvailable), None if unknown."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def min_region_cells(radius_cells: float) -> int:
    """Frontier regions "comparable to the size of the robot": at least its diameter."""
    return max(1, int(math.floor(2.0 * radius_cells)))


def max_ticks_for(grid: MetricGrid, laser_range: float) -> int:
    """A cap no sensible run reaches: six sweeps of the free area at one laser width."""
    return max(2000, int(6 * grid.world.free_cells / max(1.0, grid.cells(laser_range))))


def start_spacing(grid: MetricGrid, radius_m: float) -> int:
    """Cells between two default starts (a robot diameter, rounded up, plus one)."""
    return int(math.ceil(2 * radius_m / grid.cell)) + 1


def room_bound(grid: MetricGrid, radius_m: float) -> int:
    """At most one default start per spacing x spacing square: a bound checked before the
    search (10^6 robots took 53 s to be told the map holds 6241)."""
    spacing = start_spacing(grid, radius_m)
    h, w = grid.shape
    return math.ceil(h / spacing) * math.ceil(w / spacing)


def default_starts(grid: MetricGrid, n: int, radius_m: float) -> tuple[Cell, ...]:
    """``n`` cells around the traversable cell nearest the centre, a robot diameter apart."""
    from swarmex.missions.exploration.paths import distance_steps, footprint_offsets, inflate

    if not grid.free.any():
        raise InputError("the map has no free cell to start from")
    r = radius_m / grid.cell
    h, w = grid.shape
    # a footprint wider than the map's diagonal around any wall covers every cell: say so
    # now (the inflation loops over the footprint's offsets, π r² of them: minutes for a
    # robot of radius 100 m on a 3 m map)
    too_big = r >= math.hypot(h, w) and not grid.free.all()
    trav = None if too_big else grid.free & ~inflate(~grid.free, footprint_offsets(r))
    if trav is None or not trav.any():
        # the run would end at tick 0 with "complete" true and little explored: nobody can
        # move (a MovingAI map read at the default 5 cm cells has passages of 5 cm)
        raise InputError(
            f"a robot of radius {radius_m:g} m fits in no free cell of this map at "
            f"{grid.cell:g} m per cell: give a larger --cell or a smaller --robot-radius"
        )
    ys, xs = np.nonzero(trav)
    c = int(np.argmin((ys - (h - 1) / 2) ** 2 + (xs - (w - 1) / 2) ** 2))
    dist = distance_steps(trav, int(xs[c]), int(ys[c]))
    ry, rx = np.nonzero(dist >= 0)
    order = np.lexsort((rx, ry, dist[ry, rx]))
    spacing = start_spacing(grid, radius_m)
    chosen: list[Cell] = []
    near = np.zeros((h, w), dtype=bool)  # cells closer than spacing to a chosen start
    for i in order:
        x, y = int(rx[i]), int(ry[i])
        if not near[y, x]:  # Chebyshev distance >= spacing from every chosen start
            chosen.append((x, y))
            near[max(0, y - spacing + 1):y + spacing, max(0, x - spacing + 1):x + spacing] = True
            if len(chosen) == n:
                return tuple(chosen)
    room = f"{len(chosen)} robot" + ("" if len(chosen) == 1 else "s")
    raise InputError(f"the map has room for only {room}, not {n}")
