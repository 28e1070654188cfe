"""Sectors (thesis §3.4, Algorithms 11–12, Table 3, Fig. 32–35).

Division. With ``n = 8k`` every quadrant is cut into ``2k`` equal-area sectors by lines of
slope ``0, 1/k, …, 1, k/(k-1), …, k`` through the nest. Angles are measured counter-clockwise
from East in a y-up frame; quadrants are half-open (``[0°, 90°)`` is North-East, the released
code's convention), and so is every sector ``[α, β)``. Slopes are compared with exact integer
arithmetic, so cells on a dividing line go to the sector that starts there. Robot ids number
the sectors counter-clockwise from East.

Each quadrant is handled in a rotated frame ``(u, v)`` with ``u`` along the quadrant's first axis
(East for NE, North for NW, West for SW, South for SE) and ``v`` along its second, so Table 3
becomes one rule: a sector in the lower half (sub-quadrants 11, 21, 31, 41) uses levels of
constant ``u`` and transition ``+u``; one in the upper half uses levels of constant ``v`` and
transition ``+v`` (the forbidden direction is the one toward the nest).

Start-Cell (Alg. 11): the nearest cell of the sector; it is unique, because the hop count of
the nearest cell of each level grows strictly with the level. Exploration (Alg. 12): visit
every in-sector cell of the current level, then step to the next level; the within-level order
alternates (boustrophedon) and starts at the end nearer to where the previous level ended; gaps
between consecutive cells (empty or shifted levels near the nest) are bridged by shortest
paths, which is where the "few cells visited twice" come from.

Emission (§3.4.3): per quadrant, lower-half Start-Cells by decreasing ``u``, upper-half ones by
decreasing ``v`` (ties by the other coordinate), interleaved starting with the upper half as in
the thesis's example ``A7 → A3 → A5 → …``; the four quadrants emit in parallel, one robot each
per round (released code). Deployment (§3.4.4): along ``u`` first, then ``v``.

n = 4 is ZigZag with four agents (thesis §3.4.1; the released code runs exactly that), so the
N = 4 rows of the two patterns coincide. Supported: 4 and multiples of 8.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from fractions import Fraction

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.foraging import zigzag
from swarmex.missions.foraging.grid import Cell, join, nest_of
from swarmex.missions.foraging.plan import Plan

# (u, v) → (dx, dy) in grid coordinates (y down), one per quadrant counter-clockwise from NE
FRAMES: list[tuple[tuple[int, int], tuple[int, int]]] = [
    ((1, 0), (0, -1)),  # NE: u East, v North
    ((0, -1), (-1, 0)),  # NW: u North, v West
    ((-1, 0), (0, 1)),  # SW: u West, v South
    ((0, 1), (1, 0)),  # SE: u South, v East
]


def to_grid(nest: Cell, q: int, u: int, v: int) -> Cell:
    (ux, uy), (vx, vy) = FRAMES[q]
    return (nest[0] + u * ux + v * vx, nest[1] + u * uy + v * vy)


def to_frame(nest: Cell, c: Cell) -> tuple[int, int, int]:
    """Quadrant and ``(u, v)`` of a non-nest cell, with ``u > 0, v ≥ 0``."""
    X, Y = c[0] - nest[0], nest[1] - c[1]  # y up
    if X > 0 and Y >= 0:
        return 0, X, Y
    if X <= 0 and Y > 0:
        return 1, Y, -X
    if X < 0 and Y <= 0:
        return 2, -X, -Y
    return 3, -Y, X


def slopes(per_quadrant: int) -> list[Fraction]:
    """Lower boundaries of the ``2k`` sectors of a quadrant (tan of the start angle)."""
    k = per_quadrant // 2
    if per_quadrant == 1:
        return [Fraction(0)]
    return [Fraction(j, k) for j in range(k + 1)] + [Fraction(k, j) for j in range(k - 1, 0, -1)]


def sector_cells(g: int, n: int) -> list[list[tuple[int, int]]]:
    """For every sector (id order), its cells as frame coordinates ``(u, v)``, each list in
    row-major order of the grid.

    Vectorised: a loop over the cells and their boundaries cost O(g² · n) Python steps
    (25 s of the 37 s of a 1024 × 1024 run with 1,024 robots). ``lows`` ascend, so the
    sector is the number of boundaries past the first that ``v/u`` reaches, and each
    boundary is one integer comparison over the whole grid."""
    nest = nest_of(g)
    per_q = n // 4
    lows = slopes(per_q)
    ys, xs = np.divmod(np.arange(g * g, dtype=np.int64), g)
    big_x, big_y = xs - nest[0], nest[1] - ys  # y up, as to_frame
    quadrant = np.full(g * g, 3, dtype=np.int64)
    u, v = -big_y, big_x.copy()
    for q, mask, qu, qv in (
        (2, (big_x < 0) & (big_y <= 0), -big_x, -big_y),
        (1, (big_x <= 0) & (big_y > 0), big_y, -big_x),
        (0, (big_x > 0) & (big_y >= 0), big_x, big_y),
    ):  # to_frame's tests in reverse, so the first that holds wins
        quadrant[mask], u[mask], v[mask] = q, qu[mask], qv[mask]
    sector = np.zeros(g * g, dtype=np.int64)
    for lo in lows[1:]:
        sector += v * lo.denominator >= lo.numerator * u
    keep = (xs != nest[0]) | (ys != nest[1])
    ids = (quadrant * per_q + sector)[keep]
    u, v = u[keep], v[keep]
    order = np.argsort(ids, kind="stable")
    bounds = np.searchsorted(ids[order], np.arange(n + 1))
    us, vs = u[order].tolist(), v[order].tolist()
    return [list(zip(us[a:b], vs[a:b], strict=True)) for a, b in itertools.pairwise(bounds)]


def sweep(cells: list[tuple[int, int]], lower: bool) -> list[tuple[int, int]]:
    """Alg. 12 order of one sector's cells, in frame coordinates (level, along)."""
    levels: dict[int, list[int]] = {}
    for u, v in cells:
        lvl, w = (u, v) if lower else (v, u)
        levels.setdefault(lvl, []).append(w)
    order: list[tuple[int, int]] = []
    last_w: int | None = None
    for lvl in sorted(levels):
        ws = sorted(levels[lvl])
        if last_w is not None and abs(ws[-1] - last_w) < abs(ws[0] - last_w):
            ws.reverse()
        order.extend(((lvl, w) if lower else (w, lvl)) for w in ws)
        last_w = ws[-1]
    return order


Order = Callable[[list[tuple[int, int]], bool], list[tuple[int, int]]]


def plan(g: int, n: int, name: str = "sectors", order_fn: Order | None = None) -> Plan:
    """Sectors; ``order_fn(cells, lower)`` replaces Alg. 12's order (used by :mod:`.rings`)."""
    order_fn = order_fn or sweep
    if n == 4 and name == "sectors":
        p = zigzag.plan(g, 4)
        p.algorithm = name
        return p
    if n != 4 and (n % 8 or n < 8):
        raise InputError(f"{name} supports --agents 4 or a multiple of 8, not {n}")
    nest = nest_of(g)
    per_q = n // 4
    cells = sector_cells(g, n)
    if any(not c for c in cells):
        raise InputError(f"{name}: grid {g}×{g} is too small for {n} sectors")
    routes: list[list[Cell]] = [[] for _ in range(n)]
    explore_from = [0] * n
    depart = [0] * n
    for q in range(4):
        lower_q: list[tuple[int, Cell]] = []
        upper_q: list[tuple[int, Cell]] = []
        for s in range(per_q):
            a = q * per_q + s
            lower = s < per_q // 2 or per_q == 1
            order = order_fn(cells[a], lower)
            start = order[0]
            deploy = [nest, *_frame_lpath(nest, q, start)]
            explore_from[a] = len(deploy) - 1
            routes[a] = deploy[:-1] + join([to_grid(nest, q, u, v) for u, v in order])
            (lower_q if lower else upper_q).append((a, start))
        lower_q.sort(key=lambda e: (-e[1][0], -e[1][1]))
        upper_q.sort(key=lambda e: (-e[1][1], -e[1][0]))
        emission: list[int] = []
        for i in range(max(len(lower_q), len(upper_q))):
            if i < len(upper_q):
                emission.append(upper_q[i][0])
            if i < len(lower_q):
                emission.append(lower_q[i][0])
        for rank, a in enumerate(emission):
            depart[a] = rank + 1
    neighbours = [[(a - 1) % n, (a + 1) % n] for a in range(n)]
    return Plan(name, g, n, routes, depart, explore_from, neighbours)


def _frame_lpath(nest: Cell, q: int, target: tuple[int, int]) -> list[Cell]:
    """Deployment: along ``u`` first, then ``v`` (East then North in the NE quadrant)."""
    u, v = target
    return [to_grid(nest, q, i, 0) for i in range(1, u + 1)] + [
        to_grid(nest, q, u, j) for j in range(1, v + 1)
    ]
