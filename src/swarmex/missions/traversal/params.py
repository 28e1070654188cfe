"""Parameters of a traversal run (seed 000), with their defaults, units and checks.

Conventions (also in ``swarmex traverse --help``):

* Cells are ``x,y`` with x the column and y the row, row 0 the first map row (DESIGN.md);
  lists are ``"x,y;x,y;…"`` or Python sequences of pairs.
* ``travel_time`` is seconds per unit edge (a diagonal of ``connectivity=8`` takes √2 times as
  long); ``job_time`` seconds per job.
* Nests: agent *i* starts at nest ``i mod len(nests)``, so fewer nests than agents are shared
  round-robin (the thesis runs 1..m nests; several agents on one nest is its standard
  setting), and listing a cell twice is the same as sharing it. More nests than agents is an
  error (a nest nobody uses is a typo). Without ``nests`` every agent starts at the first
  free cell in row-major order (smallest y, then smallest x).
* Obstacles listed twice are harmless; ``obstacles`` may add walls to a ``map`` too.
* GPS grids (``center``, ``radius``, ``nodes_on_edge``, instead of ``map`` or ``grid``): seed
  000's K x K grid spanning 2R metres around a latitude and longitude, node positions and
  edge lengths geodesic (:mod:`swarmex.worlds.geo`); ``travel_time`` is then seconds per
  nominal edge of 2R / (K - 1) metres, and fleet speeds are metres per second.
* Fleets (``fleet``, or ``agents`` given as a list of tables): per-agent nest, altitude,
  speeds and job time by id (:mod:`swarmex.missions.traversal.fleet`); a row's missing field
  takes the option of the same name, so the timing options are the fleet's defaults.

Defaults of the timing options are the thesis's base agent (§5.1: 6.67 m edges flown at
3 m/s, 10 s jobs, climb 1.5 m/s, descent 0.3 m/s) without the 5 m takeoff, so
``additional_time`` is the return flight alone unless ``altitude`` is given.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Self

from swarmex.errors import InputError
from swarmex.missions.base import (
    Cell,
    Params,
    cells,
    integer,
    option,
    optional,
    path_or,
    plain_sequence,
    real,
    text,
)
from swarmex.missions.traversal.fleet import (
    MAX_ALTITUDE,
    MAX_EDGE_M,
    MAX_SECONDS,
    MIN_SPEED,
    FleetRow,
    fleet,
    is_table_list,
)
from swarmex.worlds.geo import MAX_NODES_ON_EDGE, MAX_RADIUS, check_center

if TYPE_CHECKING:
    from swarmex.worlds.grid import GridWorld

ALGORITHMS = (
    "madgta", "madgta+", "madgta-h", "madgta-r", "madgta-p", "madgta-k", "madgta-f", "madgta-s",
    "nearest", "optimal",
)
OBJECTIVES = ("sum", "makespan")
MAX_GRID_CELLS = 16_000_000  # a 4000x4000 grid; beyond that the arrays alone exhaust memory
_GRID = re.compile(r"^\s*(\d+)\s*[xX×]\s*(\d+)\s*$")


def grid_size() -> Any:
    """``"10x12"`` or ``(10, 12)`` -> (width, height), each >= 1, at most MAX_GRID_CELLS."""

    def parse(value: Any, flag: str) -> tuple[int, int]:
        value = plain_sequence(value)
        if isinstance(value, str):
            m = _GRID.match(value)
            if not m:
                raise InputError(f"{flag}: expected WxH such as 10x10, got {value!r}")
            w, h = int(m[1]), int(m[2])
        elif (
            isinstance(value, list | tuple)
            and len(value) == 2
            and all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in value)
        ):
            w, h = int(value[0]), int(value[1])
        else:
            raise InputError(f"{flag}: expected WxH such as 10x10, got {value!r}")
        if w < 1 or h < 1:
            raise InputError(f"{flag}: width and height must be >= 1, got {value!r}")
        if w * h > MAX_GRID_CELLS:
            raise InputError(f"{flag}: {w}x{h} has more than {MAX_GRID_CELLS:,} cells")
        return w, h

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def lat_lon() -> Any:
    """``"43.268304,-79.911135"`` or ``(43.268304, -79.911135)`` -> (lat, lon) in degrees."""

    def parse(value: Any, flag: str) -> tuple[float, float]:
        parts = value.split(",") if isinstance(value, str) else plain_sequence(value)
        if isinstance(parts, list | tuple) and len(parts) == 2:
            try:
                lat, lon = (float(v) for v in parts if not isinstance(v, bool))
            except (TypeError, ValueError):
                pass
            else:
                check_center(lat, lon, flag)
                return lat, lon
        raise InputError(f"{flag}: expected LAT,LON in degrees such as 43.268304,-79.911135,"
                         f" got {value!r}")

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def algorithm_name(algorithm: str) -> str:
    """The algorithm of a spec, without its options: ``madgta-f@ils=60`` -> ``madgta-f``."""
    return algorithm.partition("@")[0].strip()


def algorithm_spec() -> Any:
    """One of :data:`ALGORITHMS`, or a policy with options, ``NAME@KEY=VALUE,...``, checked
    against the policy's constructor and spelled one way
    (:func:`~swarmex.missions.traversal.policies.canonical_algorithm`)."""
    plain = text(ALGORITHMS)

    def parse(value: Any, flag: str) -> str:
        if not isinstance(value, str) or "@" not in value:
            return plain(value, flag)
        name = algorithm_name(value)
        if name not in ALGORITHMS or name == "optimal":
            choices = ", ".join(a for a in ALGORITHMS if a != "optimal")
            raise InputError(f"{flag}: options (NAME@KEY=VALUE) are for a policy: one of "
                             f"{choices}; got {value!r}")
        from swarmex.missions.traversal.policies import canonical_algorithm

        try:
            return canonical_algorithm(value)
        except InputError as exc:
            raise InputError(f"{flag}: {exc}") from None

    parse.kind = str  # type: ignore[attr-defined]
    parse.choices = None  # type: ignore[attr-defined]
    return parse


def _grid_world() -> type:
    from swarmex.worlds.grid import GridWorld

    return GridWorld


def map_source() -> Any:
    """A MovingAI file (str or Path), or a :class:`~swarmex.worlds.grid.GridWorld` passed
    through as it is (a world built or generated in Python, as roadmap's ``env`` takes a
    PolygonWorld)."""
    return path_or(_grid_world, "a .map file path or a GridWorld")


def connectivity() -> Any:
    inner = integer()

    def parse(value: Any, flag: str) -> int:
        out = inner(value, flag)
        if out not in (4, 8):
            raise InputError(f"{flag} must be 4 or 8, got {out}")
        return int(out)

    parse.kind = int  # type: ignore[attr-defined]
    return parse


@dataclass(frozen=True)
class TraversalParams(Params):
    mission = "traversal"
    required_one_of = (("map", "grid", "center"), ("agents", "fleet"))

    map: Path | GridWorld | None = option(
        None,
        help="MovingAI .map file (or give --grid); from Python also a GridWorld.",
        parse=optional(map_source()),
    )
    grid: tuple[int, int] | None = option(
        None, help="Empty WxH grid, e.g. 10x10 (or give --map).", parse=optional(grid_size())
    )
    obstacles: tuple[Cell, ...] = option(
        (), help='Blocked cells "x,y;x,y;…" (x column, y row).', parse=cells()
    )
    agents: int | None = option(
        None,
        help="Number of agents (>= 1); with --fleet, its number of rows.",
        parse=optional(integer(lo=1)),
    )
    nests: tuple[Cell, ...] | None = option(
        None,
        help='Start cells "x,y;…", shared round-robin when fewer than agents. '
        "Default: the first free cell in row-major order.",
        parse=optional(cells()),
    )
    travel_time: float = option(
        2.22, help="Seconds per grid edge (thesis: 6.67 m at 3 m/s).",
        parse=real(above=0, hi=MAX_SECONDS)
    )
    job_time: float = option(10.0, help="Seconds per job.", parse=real(lo=0, hi=MAX_SECONDS))
    algorithm: str = option(
        "madgta",
        help="madgta | madgta+ | madgta-h (mixed fleets: lower sum, longer makespan)"
        " | madgta-r (rollout over MADGTA in the end game) | madgta-p (madgta-r with an"
        " end-game team plan's vertex as one more candidate) | madgta-k (madgta-p with a sweep"
        " kept to each agent's part of a balanced partition) | madgta-f (madgta-k following"
        " its own end-game plan once a wall is known) | madgta-s (madgta-f sharing one plan by"
        " broadcast) | nearest | optimal (exact MILP)."
        " NAME@KEY=VALUE,... sets a policy's options, e.g. madgta-f@ils=60,keep=false.",
        parse=algorithm_spec(),
    )
    objective: str = option(
        "sum", help="What optimal minimises: sum (thesis §3.1) | makespan.", parse=text(OBJECTIVES)
    )
    connectivity: int = option(4, help="4 or 8 neighbours per cell.", parse=connectivity())
    start_interval: float = option(
        0.5, help="Seconds between agents' starts.", parse=real(lo=0, hi=MAX_SECONDS)
    )
    altitude: float = option(
        0.0, help="Working altitude, metres.", parse=real(lo=0, hi=MAX_ALTITUDE)
    )
    up_speed: float = option(1.5, help="Climb speed, m/s.", parse=real(lo=MIN_SPEED))
    down_speed: float = option(0.3, help="Descent speed, m/s.", parse=real(lo=MIN_SPEED))
    comm_range: float | None = option(
        None,
        help="Broadcast range in cells (default: unlimited).",
        parse=optional(real(above=0, finite=False)),
    )
    loss: float = option(
        0.0, help="Probability a receiver misses a message.", parse=real(lo=0, below=1)
    )
    delay: float = option(0.0, help="Message delay, seconds.", parse=real(lo=0, hi=MAX_SECONDS))
    job_failure: float = option(
        0.0, help="Probability a job fails and must be redone.", parse=real(lo=0, below=1)
    )
    # numpy's generators take only seeds >= 0 (a negative one was a traceback from deep inside
    # the run, after the world was built)
    seed: int = option(0, help="Seed of every random choice.", parse=integer(lo=0))
    fleet: tuple[FleetRow, ...] | None = option(
        None,
        help="Per-agent values by id: a TOML file of [[agents]] tables or a CSV with columns "
        "id, nest, altitude, travel_speed (m/s) or travel_time, job_time, up_speed, "
        "down_speed; a missing value takes the option of the same name.",
        parse=optional(fleet()),
        metavar="FILE",
    )
    edge_length: float | None = option(
        None,
        help="Metres per grid edge of --map/--grid, so that fleet speeds in m/s apply "
        "(default: none; a GPS grid has its own).",
        parse=optional(real(above=0, hi=MAX_EDGE_M)),
    )
    center: tuple[float, float] | None = option(
        None,
        help="GPS grid (instead of --map/--grid): its centre LAT,LON in degrees (WGS84); "
        "with --radius and --nodes-on-edge.",
        parse=optional(lat_lon()),
        metavar="LAT,LON",
    )
    radius: float | None = option(
        None,
        help="GPS grid: half its side, metres (the grid spans 2R).",
        parse=optional(real(above=0, hi=MAX_RADIUS)),
    )
    nodes_on_edge: int | None = option(
        None,
        help="GPS grid: K nodes on an edge (K x K nodes).",
        parse=optional(integer(lo=2, hi=MAX_NODES_ON_EDGE)),
    )

    @classmethod
    def from_values(cls, values: Mapping[str, Any] | None = None, **kw: Any) -> Self:
        """:meth:`Params.from_values`, where ``agents`` may also be the fleet's table list
        (a scenario's ``[[agents]]`` tables): it then means ``fleet``, and ``agents`` is
        the number of its rows."""
        raw = {**(values or {}), **kw}
        if is_table_list(raw.get("agents")):
            if raw.get("fleet") is not None:
                raise InputError("give the fleet as [[agents]] tables or as --fleet, not both")
            raw["fleet"] = raw.pop("agents")
        params = super().from_values(raw)
        if params.fleet is not None and params.agents is None:
            params = replace(params, agents=len(params.fleet))
        return params

    @property
    def team(self) -> int:
        """The number of agents (``agents``, or the fleet's rows)."""
        if self.agents is not None:
            return self.agents
        if self.fleet is not None:
            return len(self.fleet)
        raise InputError("traversal: --agents is required (or give --fleet)")

    def check(self) -> None:
        worlds = sum(v is not None for v in (self.map, self.grid, self.center))
        if worlds != 1:
            raise InputError("give exactly one of --map FILE, --grid WxH or --center LAT,LON")
        gps = {"--radius": self.radius, "--nodes-on-edge": self.nodes_on_edge}
        if self.center is not None:
            for flag, value in gps.items():
                if value is None:
                    raise InputError(f"--center needs {flag} too (the GPS grid's size)")
            if self.edge_length is not None:
                raise InputError("--edge-length: a GPS grid's edges are its geodesic lengths")
        else:
            for flag, value in gps.items():
                if value is not None:
                    raise InputError(f"{flag} belongs to a GPS grid: give --center LAT,LON")
        if self.agents is None and self.fleet is None:
            raise InputError("traversal: --agents is required (or give --fleet)")
        if self.fleet is not None and self.agents is not None and self.agents != len(self.fleet):
            raise InputError(
                f"--agents {self.agents} but the fleet lists {len(self.fleet)} agents"
            )
        team = self.team
        if self.nests is not None:
            if not self.nests:
                raise InputError("--nests: no cell given")
            if len(self.nests) > team:
                raise InputError(f"--nests: {len(self.nests)} nests for only {team} agents")

    def ignored(self) -> dict[str, str]:
        if self.objective != "sum" and self.algorithm != "optimal":
            return {"objective": f"only optimal minimises an objective ({self.objective});"
                                 f" {algorithm_name(self.algorithm)} plays its own rule"}
        if self.algorithm == "optimal":
            # the MILP plans offline with the whole map known: a radio or failing jobs never
            # enter it. A note, not a refusal, so a sweep may hold loss fixed while it
            # compares a policy with the optimum (the record keeps the value it was given)
            offline = {"loss": self.loss > 0, "delay": self.delay > 0,
                       "comm_range": self.comm_range not in (None, math.inf),
                       "job_failure": self.job_failure > 0}
            why = ("optimal is an offline plan with a perfect radio and jobs that never fail;"
                   " run a policy (e.g. madgta) for that")
            return {name: why for name, on in offline.items() if on}
        return {}


__all__ = ["ALGORITHMS", "OBJECTIVES", "TraversalParams", "algorithm_name", "algorithm_spec"]
