"""Registry of exploration patterns: name → plan builder, cached per ``(name, g, n)``.

``recall`` (:data:`ADAPTIVE`) is a valid ``--algorithm`` too, but it has no plan of its own:
it chooses one of these per run (:mod:`.recall`).

:data:`BUILDERS` is the one list of valid ``--algorithm`` names: :data:`ALGORITHMS` (what the
parser, its error message and ``--help`` show) is read off it, the thesis's six patterns first
and then ours, so a name can be offered only if a builder accepts it.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

from swarmex.errors import InputError
from swarmex.missions.foraging import (
    comb,
    hilbert,
    loop_strips,
    modified_zigzag,
    rings,
    sector_loop,
    sectors,
    spiral,
    strips,
    zigzag,
)
from swarmex.missions.foraging.plan import Plan

BUILDERS: dict[str, Callable[[int, int], Plan]] = {
    "strips": strips.plan,
    "zigzag": zigzag.plan,
    "hilbert": hilbert.plan,
    "sectors": sectors.plan,
    "spiral": spiral.plan,
    "modified-zigzag": modified_zigzag.plan,
    "rings": rings.plan,
    "loop-strips": loop_strips.plan,
    "sector-loop": sector_loop.plan,
    "comb": comb.plan,
}
THESIS_ALGORITHMS = ("strips", "zigzag", "hilbert", "sectors", "spiral", "modified-zigzag")
#: Choosers, not patterns: :mod:`.recall` picks a pattern per run from the team's memory
ADAPTIVE = ("recall",)
OURS = (*(name for name in BUILDERS if name not in THESIS_ALGORITHMS), *ADAPTIVE)
ALGORITHMS = (*THESIS_ALGORITHMS, *OURS)
assert set(ALGORITHMS) == set(BUILDERS) | set(ADAPTIVE), "every thesis pattern needs a builder"


@lru_cache(maxsize=64)
def build_plan(name: str, g: int, n: int) -> Plan:
    if name in ADAPTIVE:
        raise InputError(f"{name} chooses its pattern per run (swarmex.missions.foraging.recall)")
    if name not in BUILDERS:
        raise InputError(f"unknown --algorithm {name!r}; choose one of {', '.join(ALGORITHMS)}")
    if g < 2:
        raise InputError(f"--grid must be at least 2 (got {g})")
    if n < 1:
        raise InputError(f"--agents must be at least 1 (got {n})")
    p = BUILDERS[name](g, n)
    p.validate()
    return p
