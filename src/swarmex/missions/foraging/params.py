"""Parameters of a foraging run (seed 002), with their defaults and checks.

Conventions (also in ``swarmex forage --help``):

* The grid is ``grid`` × ``grid`` cells; cells are ``x,y`` with x the column and y the row,
  ``(0, 0)`` the top-left corner, and the nest is the centre cell ``(g // 2, g // 2)``
  (:func:`~swarmex.missions.foraging.grid.nest_of`).
* Food placement: ``food`` puts it at a cell (``"x,y"`` or ``(x, y)``; not the nest);
  ``food_distance`` draws a cell whose distance from the nest lies in the band ``"LO-HI"``
  (percent of the corner–nest distance, ch. 6; ``(lo, hi)`` in Python) or anywhere
  (``"random"``); with neither, a uniformly random non-nest cell is drawn. Draws use
  ``numpy.random.default_rng(seed)``, so a seed fixes the whole run. At most one of the two.
* ``comm`` is the communication rule of :mod:`~swarmex.missions.foraging.comm`: ``seed`` (the
  default: the thesis's rule as its author's simulator plays it, no robot knowing what it was
  not told) or ``omniscient`` (the rule before 25 Nov 2026, which reproduces older records).
* ``food_units`` defaults to 100, the released simulator's value (the thesis does not state
  its k).
* ``algorithm`` is one of :data:`~swarmex.missions.foraging.patterns.ALGORITHMS`, the very list
  of plan builders: the thesis's six patterns, then ours (``rings``, ``loop-strips``). Each
  pattern has its own team-size rule (Strips: g a multiple of n; ZigZag and Hilbert: n a power
  of 4; ...), checked here by building the plan (cached, so the run reuses it).
  ``recall`` is not a pattern but a choice among them made per run from ``found``, the cells
  where food was found on earlier trips (:mod:`~swarmex.missions.foraging.recall`); ``found``
  is read by it alone.
* Size limits, so that no input makes the command seem to hang or run out of memory:
  ``grid`` is at most :data:`MAX_GRID` (1024, about a million cells; the exploration timetable
  is played round by round and every round's positions are kept, so a 1024 grid with one robot
  already takes seconds and half a gigabyte), ``agents`` at most :data:`MAX_AGENTS` (1024, the
  largest swarm the scale benchmarks run; planning Sectors for 256 robots on a 1024 grid
  takes ten seconds, and the time grows with the team) and at most the grid's cells (no
  pattern gives a robot an empty share), ``food_units`` at most :data:`MAX_FOOD_UNITS` (100
  times the released simulator's k; each unit is a trip).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from swarmex.errors import InputError
from swarmex.missions.base import (
    REQUIRED,
    Cell,
    Params,
    Parser,
    cell,
    cells,
    integer,
    option,
    optional,
    text,
)
from swarmex.missions.foraging.comm import COMM_RULES, SEED
from swarmex.missions.foraging.food import check_food, parse_band
from swarmex.missions.foraging.grid import nest_of
from swarmex.missions.foraging.patterns import ALGORITHMS, OURS, THESIS_ALGORITHMS, build_plan
from swarmex.missions.foraging.recall import NAME as RECALL
from swarmex.missions.foraging.recall import check as check_recall
from swarmex.missions.foraging.transport import TRANSPORTS

MAX_GRID = 1024
MAX_AGENTS = 1024
MAX_FOOD_UNITS = 10_000
RANDOM = "random"


def grid_side() -> Parser:
    """The grid side g: an integer from 2 to :data:`MAX_GRID`."""
    inner = integer(lo=2)

    def parse(value: Any, flag: str) -> int:
        g: int = inner(value, flag)
        if g > MAX_GRID:
            raise InputError(
                f"{flag} must be at most {MAX_GRID} (a {MAX_GRID}×{MAX_GRID} grid, "
                f"{MAX_GRID * MAX_GRID:,} cells), got {g}"
            )
        return g

    parse.kind = int  # type: ignore[attr-defined]
    return parse


def band() -> Parser:
    """A food band: ``"LO-HI"`` (percent), ``"random"``, or ``(lo, hi)`` in Python.

    A string is kept as given (it is what the record shows); a pair becomes ``"lo-hi"``.
    """

    def parse(value: Any, flag: str) -> str:
        if isinstance(value, str):
            out = value
        elif (
            isinstance(value, list | tuple)
            and len(value) == 2
            and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            out = f"{value[0]:g}-{value[1]:g}"
        else:
            raise InputError(f"{flag} must be LO-HI in percent or {RANDOM!r}, got {value!r}")
        if out != RANDOM:
            parse_band(out)  # names --food-distance in its messages
        return out

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def algorithm_help() -> str:
    """The --algorithm help: the names of :data:`ALGORITHMS` (spaced, so a narrow --help page
    wraps the line instead of cutting a name)."""
    return f"{' | '.join(THESIS_ALGORITHMS)}, or {' | '.join(OURS)} (ours)."


@dataclass(frozen=True)
class ForagingParams(Params):
    mission = "foraging"

    grid: int = option(REQUIRED, help="Grid side g (the grid is g×g).", parse=grid_side())
    agents: int = option(REQUIRED, help="Number of robots n.", parse=integer(lo=1, hi=MAX_AGENTS))
    algorithm: str = option(REQUIRED, help=algorithm_help(), parse=text(ALGORITHMS, lower=True))
    transport: str = option(
        "relay-food", help="end-to-end|relay-food|relay-path.", parse=text(TRANSPORTS, lower=True)
    )
    comm: str = option(
        SEED,
        help="Communication rule: seed (the thesis's and its simulator's) | omniscient "
        "(knows who already knows; before 25 Nov 2026).",
        parse=text(COMM_RULES, lower=True),
    )
    food: Cell | None = option(
        None,
        help="Food cell x,y (default: drawn from the seed anywhere but the nest, or in"
        " --food-distance's band).",
        parse=optional(cell()),
    )
    food_distance: str | None = option(
        None, help="Band LO-HI (percent of the corner–nest distance).", parse=optional(band())
    )
    food_units: int = option(
        100, help="Units k at the food cell.", parse=integer(lo=1, hi=MAX_FOOD_UNITS)
    )
    found: tuple[Cell, ...] = option(
        (),
        help='Cells where food was found on earlier trips, "x,y;x,y;…" oldest first: the'
        " memory --algorithm recall chooses its pattern from.",
        parse=cells(),
    )
    seed: int = option(0, help="Seed of every random choice.", parse=integer(lo=0))

    def check(self) -> None:
        if self.food is not None and self.food_distance is not None:
            raise InputError("give at most one of --food and --food-distance")
        if self.food is not None:
            check_food(self.food, self.grid)
        cells = self.grid * self.grid
        if self.agents > cells:
            raise InputError(
                f"--agents {self.agents}: more robots than the {self.grid}×{self.grid} grid's "
                f"{cells:,} cells"
            )
        if self.algorithm == RECALL:
            check_recall(self.grid, self.agents, self.found)
        else:
            for c in self.found:  # ignored, but still a grid's cells: a typo is said now
                check_food(c, self.grid, "--found")
            build_plan(self.algorithm, self.grid, self.agents)  # the pattern's team-size rule

    def ignored(self) -> dict[str, str]:
        # a note, not a refusal: a sweep may hold found fixed while it varies the pattern
        if self.found and self.algorithm != RECALL:
            return {"found": f"only {RECALL} reads where food was found; {self.algorithm}"
                             " searches by its own pattern"}
        return {}

    @property
    def nest(self) -> Cell:
        return nest_of(self.grid)


__all__ = ["MAX_AGENTS", "MAX_FOOD_UNITS", "MAX_GRID", "ForagingParams", "check_food"]
