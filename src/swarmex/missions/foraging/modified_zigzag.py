"""Modified ZigZag (thesis §3.6, Algorithm 13, Table 4): eight robots, two per quadrant.

Each quadrant is read in a local frame ``(u, v)``: ``u`` horizontal away from the nest's
column, ``v`` vertical away from its row, ``(0, 0)`` the quadrant's cell nearest the nest. Its
*rings* are the cells with ``max(u, v) = r``. Table 4 walks exactly these rings: the even
(inner) codes from the inner corner outward — ring ``r`` odd runs ``(0,r) → (r,r) → (r,0)``,
even ``(r,0) → (r,r) → (0,r)`` — and the odd (outer) codes from the border corner on the nest's
row inward (``N_i − W_i − S − E_{i−1} − S_{i−1} − W`` for the North-East quadrant). The table's
first outer leg ``i = g/2`` overshoots a ``g/2`` quadrant by one; we start at ring ``g/2 - 1``.

Alg. 13 lets both robots of a quadrant run until they meet. We make that division explicit and
balanced: the inner robot takes rings ``0 … R-1`` and the outer robot ``R … S-1``, with ``R``
chosen so both finish at about the same time given their deployment times (the inner robot
walks to the border and back first); their last rings are adjacent, so they meet there.

Deployment: at round 1 the four outer robots leave horizontally for the border along the
quadrant's first row (learning ``g``); the inner robots follow one round behind, touch the
border and walk back to their inner corner. Communication (§4.3) is reduced to neighbours:
inner robots of adjacent quadrants, outer robots of adjacent quadrants, and each robot's
counterpart. Supported: ``n = 8`` and even ``g ≥ 4``.
"""

from __future__ import annotations

import math

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, lpath, nest_of
from swarmex.missions.foraging.plan import Plan

# quadrant → (sign of x per u, x offset from cx, sign of y per v, y offset from cy)
QUADS = {"NE": (1, 0, -1, -1), "NW": (-1, -1, -1, -1), "SW": (-1, -1, 1, 0), "SE": (1, 0, 1, 0)}


def local_to_grid(nest: Cell, q: str, u: int, v: int) -> Cell:
    sx, ox, sy, oy = QUADS[q]
    return (nest[0] + ox + sx * u, nest[1] + oy + sy * v)


def ring(r: int, outward_odd: bool) -> list[tuple[int, int]]:
    """Ring ``r`` as Table 4 walks it; the direction alternates with the ring's parity."""
    if r == 0:
        return [(0, 0)]
    up = [(r, v) for v in range(0, r + 1)] + [(u, r) for u in range(r - 1, -1, -1)]
    if (r % 2 == 1) == outward_odd:
        return up[::-1]  # (0,r) → (r,r) → (r,0)
    return up  # (r,0) → (r,r) → (0,r)


def plan(g: int, n: int) -> Plan:
    if n != 8:
        raise InputError(f"modified-zigzag is defined for --agents 8 only, not {n}")
    if g % 2 or g < 4:
        raise InputError(f"modified-zigzag needs an even grid size ≥ 4 (got {g})")
    nest = nest_of(g)
    S = g // 2
    t_out = S + 1  # outer robot reaches its border corner
    t_in = 2 * S + 1  # inner robot back at its inner corner (touch + return)
    R = round(math.sqrt(max(1.0, (S * S + t_out - t_in) / 2)))
    R = min(max(R, 1), S - 1)
    routes: list[list[Cell]] = []
    depart: list[int] = []
    explore_from: list[int] = []
    quads = ["NE", "NW", "SW", "SE"]
    for q in quads:  # outer robots: ids 0..3
        corner = local_to_grid(nest, q, 0, 0)
        border = local_to_grid(nest, q, S - 1, 0)
        r = [nest, *lpath(nest, corner), *lpath(corner, border)]
        explore_from.append(len(r) - 1)
        odd = (S - 1) % 2 == 0  # the first outer ring must start at the border corner
        cells = [c for rr in range(S - 1, R - 1, -1) for c in ring(rr, outward_odd=odd)]
        r.extend(local_to_grid(nest, q, u, v) for u, v in cells[1:])
        routes.append(r)
        depart.append(1)
    for q in quads:  # inner robots: ids 4..7
        corner = local_to_grid(nest, q, 0, 0)
        border = local_to_grid(nest, q, S - 1, 0)
        r = [nest, *lpath(nest, corner), *lpath(corner, border), *lpath(border, corner)]
        explore_from.append(len(r) - 1)
        cells = [c for rr in range(0, R) for c in ring(rr, outward_odd=True)]
        r.extend(local_to_grid(nest, q, u, v) for u, v in cells[1:])
        routes.append(r)
        depart.append(2)
    adj = {0: (1, 3), 1: (0, 2), 2: (1, 3), 3: (2, 0)}
    neighbours = [[*adj[a], a + 4] for a in range(4)] + [
        [adj[a][0] + 4, adj[a][1] + 4, a] for a in range(4)
    ]
    return Plan("modified-zigzag", g, n, routes, depart, explore_from, neighbours, notes={"R": R})
