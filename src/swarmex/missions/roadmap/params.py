"""Parameters of a roadmap run (seed 004), with their defaults, units and checks.

Conventions (also in ``swarmex roadmap --help``):

* Coordinates are in the environment's own units (a JSON file's; cells of a ``.map`` or image,
  y pointing down). A point is ``"x,y"`` with real coordinates or a Python pair ``(x, y)``;
  ``starts`` is ``"x,y;x,y;…"`` or a sequence of pairs.
* ``env`` is a file (JSON polygons, MovingAI ``.map``, image) or, from Python, an already
  loaded :class:`~swarmex.worlds.polygon.PolygonWorld`.
* ``sensor_range`` is a length, ``"inf"`` (or ``math.inf``), or a multiple of the step ε
  (``"1eps"``, ``"2ε"``, ``"0.5*eps"``): seed 004 never gives its base range r, and Table 1
  is fitted better by r = ε than by any fixed length (docs/roadmap.md, "Sensor range").
* Starts: ``starts`` if given; otherwise the file's when their number matches ``agents``;
  otherwise the default cluster (:mod:`.starts`), centred on the file's starts when it has
  some. Goal: ``goal``, else the file's; ``task="search"`` needs one. These need the
  environment, so the mission checks them when it prepares the world.
* ``step_budget`` defaults to 2·K steps for PRM (whose agents cannot know they are done) and
  to a safety net for WMA-RRT, which ends by itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmex.errors import InputError, require
from swarmex.missions.base import (
    REQUIRED,
    Params,
    Parser,
    Point,
    integer,
    option,
    optional,
    path_or,
    point,
    points,
    real,
    text,
)

if TYPE_CHECKING:
    from swarmex.worlds.polygon import PolygonWorld

PLANNERS = ("wma-rrt", "prm", "wma-rrt-takeover", "wma-rrt-fairshare", "ompl-prm")
# the planners whose roadmap is a graph walked by PRM walkers (no branches, no COMPLETE):
# the project's PRM and OMPL's (extra `ompl`)
GRAPH_PLANNERS = ("prm", "ompl-prm")
#: roadmap nodes a run may ask for
MAX_NODES = 1_000_000
TASKS = ("coverage", "search")
# the coverage raster's cells on the long side; equal to sensing.coverage_raster.DEFAULT_CELLS
# (a test checks it), not imported from there because that module pulls in numba
RASTER_CELLS = 256
# the finest raster accepted: 4096 cells on the long side already take about 0.8 GB and a few
# seconds; a larger value would fail with a numpy MemoryError (or swap) instead of one line
RASTER_MAX = 4096
_INFINITE = ("inf", "infinite", "infinity", "∞")


@dataclass(frozen=True)
class SensorRange:
    """A sensor range as the user gave it: a length (possibly infinite), or, with
    ``per_step``, a multiple of the step ε (its length is known once the step is)."""

    value: float
    per_step: bool = False

    def length(self, step: float) -> float:
        return self.value * float(step) if self.per_step else self.value

    def __str__(self) -> str:
        if self.per_step:
            return f"{self.value:g}eps"
        return "inf" if math.isinf(self.value) else f"{self.value:g}"


def _length(value: Any, flag: str) -> float:
    """A positive length (or infinity) from a number or its text."""
    if isinstance(value, str) and value.strip().lower() in _INFINITE:
        return math.inf
    try:
        if isinstance(value, bool):
            raise TypeError
        r = float(value)
    except (TypeError, ValueError):
        raise InputError(
            f"{flag} must be a positive number, a multiple of ε like '2eps', or "
            f"'inf', got {value!r}"
        ) from None
    if not r > 0 or math.isnan(r):
        raise InputError(f"{flag} must be positive, got {value!r}")
    return r


def sensor_range() -> Parser:
    """``25``, ``"25"``, ``"inf"``, ``math.inf`` or ``"2eps"`` / ``"2ε"`` -> SensorRange."""

    def parse(value: Any, flag: str) -> SensorRange:
        if isinstance(value, SensorRange):
            return value
        if isinstance(value, str):
            low = value.strip().lower().replace("ε", "eps")
            if low.endswith("eps"):
                head = low[:-3].rstrip("*· ") or "1"
                try:
                    return SensorRange(_length(head, flag), per_step=True)
                except InputError:
                    raise InputError(
                        f"{flag} {value!r}: the multiple of ε must be a positive number"
                    ) from None
        return SensorRange(_length(value, flag))

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def parse_range(value: str | float, step: float | None = None) -> float:
    """A sensor range as a length: ``"2eps"`` with ``step`` 20 is 40 (see :func:`sensor_range`)."""
    r = sensor_range()(value, "--sensor-range")
    if r.per_step and step is None:
        raise InputError(f"--sensor-range {value!r}: a multiple of ε needs the step")
    return r.length(step if step is not None else 1.0)


def _polygon_world() -> type:
    from swarmex.worlds.polygon import PolygonWorld

    return PolygonWorld


def environment() -> Parser:
    """An environment file (str or Path), or a PolygonWorld passed through as it is."""
    return path_or(_polygon_world, "an environment file or a PolygonWorld")


@dataclass(frozen=True)
class RoadmapParams(Params):
    mission = "roadmap"

    env: Path | PolygonWorld = option(
        REQUIRED, help="JSON polygons, MovingAI .map or image.", parse=environment()
    )
    task: str = option("coverage", help="coverage | search", parse=text(TASKS))
    planner: str = option(
        "wma-rrt",
        help="wma-rrt | prm | wma-rrt-takeover | wma-rrt-fairshare (improved helpers) | "
        "ompl-prm (OMPL's PRM)",
        parse=text(PLANNERS),
    )
    agents: int = option(REQUIRED, help="Number of agents (= branches).", parse=integer(lo=1))
    # a bound well above the studies' (400-800) and the bench's 20,000: 10^9 was accepted and
    # grew to 8 GB in a minute
    nodes: int = option(REQUIRED, help="Roadmap nodes K (Main Root excluded, at most "
                        "1,000,000).", parse=integer(lo=1, hi=MAX_NODES))
    step: float = option(REQUIRED, help="Step size ε between nodes.", parse=real(above=0))
    sensor_range: SensorRange = option(
        REQUIRED,
        help="Sensor range R, a multiple of the step ('1eps', '2eps'), or 'inf'.",
        parse=sensor_range(),
    )
    goal: Point | None = option(None, help="Goal 'x,y' (search).", parse=optional(point()))
    starts: tuple[Point, ...] | None = option(
        None, help="Starts 'x,y;x,y;…'.", parse=optional(points())
    )
    # numpy's generators refuse negative seeds: refuse them here, by name, before any work
    seed: int = option(0, help="Seed of every random choice.", parse=integer(lo=0))
    step_budget: int | None = option(
        None,
        help="Stop after this many steps (PRM default: 2K).",
        parse=optional(integer(lo=1)),
    )
    raster: int = option(
        RASTER_CELLS,
        help=f"Coverage raster cells on the long side (8 to {RASTER_MAX}).",
        parse=integer(lo=8, hi=RASTER_MAX),
    )

    def check(self) -> None:
        if self.planner == "ompl-prm":  # one line naming the extra, before any work
            require("ompl.base", "ompl", "--planner ompl-prm")
        if self.nodes < self.agents:
            raise InputError(
                f"--nodes {self.nodes} is fewer than --agents {self.agents} (one root each)"
            )
        if self.starts is not None and len(self.starts) != self.agents:
            raise InputError(
                f"--starts gives {len(self.starts)} positions for --agents {self.agents}"
            )

    def ignored(self) -> dict[str, str]:
        if self.goal is not None and self.task != "search":
            return {"goal": f"only the search task reads a goal, not {self.task}"}
        return {}

    @property
    def range_length(self) -> float:
        """The sensor range R as a length (a multiple of ε resolved with ``step``)."""
        return self.sensor_range.length(self.step)


__all__ = [
    "GRAPH_PLANNERS",
    "PLANNERS",
    "RASTER_CELLS",
    "RASTER_MAX",
    "TASKS",
    "RoadmapParams",
    "SensorRange",
    "parse_range",
    "sensor_range",
]
