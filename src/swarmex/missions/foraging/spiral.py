"""Spiral search of López-Ortiz & Sweet (thesis §3.5, ref. [3]): the literature baseline.

On the infinite lattice ``n = 2^k`` robots leave the origin together and follow interleaved,
non-overlapping spiral arms (Figs. 6, 39, 40). The thesis shows them only as figures, so we
build the arms from one rule. Every cell at Manhattan distance ``d ≥ 1`` has a *diamond angle*
``α ∈ [0, 4)`` (quarter turns counter-clockwise from East, linear along each diamond edge).
Arm ribbons are two rings wide and drift outward by ``n/2`` rings per quarter turn:
``m = ⌊(d - (n/2)·α - 1) / 2⌋`` is the ribbon of a cell and ``m mod n`` its arm, so ribbon ``m``
continues as ribbon ``m + n`` after a full turn and the ``n`` arms tile the plane, each advancing
``2n`` rings per lap — the n-arm spiral. Inside a ribbon the robot walks by increasing ``α``,
zig-zagging between its two rings (the "diagonal staircase" of the released code), outer ring
first on ties.

Finite grid (§3.5): cells outside the grid are dropped and the remaining ones of the arm are
joined by shortest paths — in the corners that is the "move along the boundary to where the
original path re-enters", and it is why many cells are visited more than once far from the
nest. All robots leave at round 1; where two arms' first steps out of the nest compete, the
engine's collision rule staggers them. A robot that finishes without news halts (§3.5).

Supported: ``n`` a power of two.
"""

from __future__ import annotations

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, join, nest_of, smooth
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.sectors import to_frame


def arm_cells(g: int, n: int) -> list[list[Cell]]:
    """Each arm's cells in visiting order (before joining)."""
    nest = nest_of(g)
    keyed: list[list[tuple[int, float, int, Cell]]] = [[] for _ in range(n)]
    for y in range(g):
        for x in range(g):
            if (x, y) == nest:
                continue
            q, u, v = to_frame(nest, (x, y))
            d = u + v
            # u_r = d - (n/2)(q + v/d); m = floor((u_r - 1) / 2), in exact integers
            m = (2 * d * d - n * (q * d + v) - 2 * d) // (4 * d)
            keyed[m % n].append((m, q + v / d, -d, (x, y)))
    return [smooth([c for *_, c in sorted(k)]) for k in keyed]


def plan(g: int, n: int) -> Plan:
    if n < 1 or n & (n - 1):
        raise InputError(f"spiral supports --agents a power of two (1, 2, 4, 8, 16, …), not {n}")
    nest = nest_of(g)
    arms = arm_cells(g, n)
    if any(not a for a in arms):
        raise InputError(f"spiral: grid {g}×{g} is too small for {n} arms")
    routes = [join(a, start=nest) for a in arms]
    if n == 1:
        neighbours: list[list[int]] = [[]]
    elif n == 2:
        neighbours = [[1], [0]]
    else:
        neighbours = [[(a - 1) % n, (a + 1) % n] for a in range(n)]
    return Plan("spiral", g, n, routes, [1] * n, [0] * n, neighbours)
