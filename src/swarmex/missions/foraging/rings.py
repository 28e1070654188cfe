"""Rings: our stronger strategy — Sectors' equal-area division, swept in distance order.

Why. The thesis's data show two complementary strengths: Spiral finds near food fastest
because it sweeps the plane in order of distance from the nest, and Sectors wins on far food
because its equal-area division keeps every robot busy until the grid is covered (the spiral
arms run off the finite grid and revisit cells). *Rings* combines both: every robot owns one
of Sectors' equal-area sectors (``n = 4`` uses the quadrants), but sweeps it ring pair by ring
pair — cells at Manhattan distance ``2p+1`` and ``2p+2`` — walking the sector's arc back and
forth (boustrophedon along the arc, staircase between the two rings). All robots therefore
advance their frontier at the same distance from the nest, like the spiral, and neighbouring
sectors' robots stay close, which keeps the communication detours short.

Deployment, emission order, neighbours and communication are those of Sectors.
"""

from __future__ import annotations

from swarmex.missions.foraging import sectors
from swarmex.missions.foraging.plan import Plan


def ring_order(cells: list[tuple[int, int]], lower: bool) -> list[tuple[int, int]]:
    """Ring pairs outward; along the arc alternately by increasing and decreasing angle."""
    del lower  # the arc order does not depend on the sub-quadrant

    def key(c: tuple[int, int]) -> tuple[int, float, int]:
        u, v = c
        d = u + v
        p = (d - 1) // 2
        a = v / d
        return (p, a if p % 2 == 0 else -a, -d if p % 2 == 0 else d)

    return sorted(cells, key=key)


def plan(g: int, n: int) -> Plan:
    return sectors.plan(g, n, name="rings", order_fn=ring_order)
