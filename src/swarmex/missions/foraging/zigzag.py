"""ZigZag (thesis §3.2, Algorithms 5–6, Table 1) and its hierarchical deployment.

Table 1 is executed as *rings*: row ``Direction(i)`` (``i`` odd) is ring ``r = i`` — one
transition step, ``i`` steps, ``i`` steps — followed by ring ``r = i + 1``. After ring ``r`` the
robot has covered an ``(r+1) × (r+1)`` block anchored at its Start-Cell. A ``size × size`` block
takes rings ``1 … size-1`` (``size² - 1`` moves); the literal ``while i ≠ size`` never stops for
even ``size``, so we stop after the first half of the last row, as the released code does.

Codes (Fig. 25 is an image; neighbours take mirror-image codes, §2.3 of the spec): the cell of
a 2×2 Start block that is the bottom-right corner of its square grows North-West (code 2),
bottom-left → North-East (1), top-left → South-East (7), top-right → South-West (8).

Deployment. n = 4: the Start-Cells are the 2×2 block of cells around the nest, so there is no
border trip; the robots step into it (two rounds) and start together. n = 16, 64, …: the
grid is cut into ``√n × √n`` squares of side ``size = g/√n`` and Alg. 6 gives the 2×2 Start
blocks. We use the per-quadrant deployment that the thesis's T_dep = 3g/2 − 2g/√n and Fig. 24
describe (and that the released code implements): one robot per quadrant per round leaves the
nest along the nest's row or column to its quadrant's border (learning g), runs along the
border, and turns into its Start-Cell; the farthest Start-Cell of a quadrant is served first, so
robots that follow never pass one that is parked. Alg. 5's "leave West" would give
T_dep ≈ 3g/2 + 1 and contradicts the thesis's own formula.

n = 1 ("spiralling around the nest", Fig. 20): a square spiral of growing rings around the
nest, clipped to the grid and joined along the border.
"""

from __future__ import annotations

from collections.abc import Callable

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, join, lpath, manhattan, nest_of, walk
from swarmex.missions.foraging.plan import Plan

# Table 1: (transition odd, first odd, second odd, transition even, first even, second even)
TABLE1: dict[int, tuple[str, str, str, str, str, str]] = {
    1: ("E", "N", "W", "N", "E", "S"),
    2: ("W", "N", "E", "N", "W", "S"),
    3: ("S", "E", "N", "E", "S", "W"),
    4: ("S", "W", "N", "W", "S", "E"),
    5: ("N", "E", "S", "E", "N", "W"),
    6: ("N", "W", "S", "W", "N", "E"),
    7: ("E", "S", "W", "S", "E", "N"),
    8: ("W", "S", "E", "S", "W", "N"),
}

# position of a Start-Cell inside its 2×2 block → code
BLOCK_CODE = {(0, 0): 2, (1, 0): 1, (0, 1): 8, (1, 1): 7}


def zigzag_moves(code: int, size: int) -> list[tuple[str, int]]:
    t1, a1, b1, t2, a2, b2 = TABLE1[code]
    moves: list[tuple[str, int]] = []
    for r in range(1, size):
        if r % 2:
            moves += [(t1, 1), (a1, r), (b1, r)]
        else:
            moves += [(t2, 1), (a2, r), (b2, r)]
    return moves


def zigzag_route(start: Cell, code: int, size: int) -> list[Cell]:
    """Exploration route (Start-Cell included) covering a ``size × size`` square."""
    return [start, *walk(start, zigzag_moves(code, size))]


def is_power_of_4(n: int) -> bool:
    while n > 1 and n % 4 == 0:
        n //= 4
    return n == 1


def hierarchical_start_cells(g: int, n: int) -> list[tuple[Cell, int]]:
    """Alg. 6: the 2×2 blocks where four squares meet, with each cell's code."""
    size = g // int(round(n**0.5))
    out: list[tuple[Cell, int]] = []
    for j in range(size - 1, g, 2 * size):
        for i in range(size - 1, g, 2 * size):
            for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
                out.append(((i + dx, j + dy), BLOCK_CODE[(dx, dy)]))
    return out


def quadrant(c: Cell, nest: Cell) -> str:
    x, y = c
    if x >= nest[0]:
        return "NE" if y < nest[1] else "SE"
    return "NW" if y < nest[1] else "SW"


def deployment_route(g: int, nest: Cell, cell: Cell) -> tuple[list[Cell], Cell]:
    """Nest → own quadrant's border (learning g) → along the border → Start-Cell."""
    cx, cy = nest
    q = quadrant(cell, nest)
    if q == "NE":  # North along the nest column, East along row 0, South to the cell
        touch = (cx, 0)
        r = lpath(nest, touch) + lpath(touch, cell, x_first=True)
    elif q == "SE":  # East along the nest row, South along column g-1, West
        touch = (g - 1, cy)
        r = lpath(nest, touch) + lpath(touch, cell, x_first=False)
    elif q == "SW":  # South along the nest column, West along row g-1, North
        touch = (cx, g - 1)
        r = lpath(nest, touch) + lpath(touch, cell, x_first=True)
    else:  # NW: West along the nest row, North along column 0, East
        touch = (0, cy)
        r = lpath(nest, touch) + lpath(touch, cell, x_first=False)
    return [nest, *r], touch


def check_hierarchical(name: str, g: int, n: int) -> int:
    if not is_power_of_4(n):
        raise InputError(f"{name} supports --agents 1 or a power of 4 (4, 16, 64, …), not {n}")
    k = int(round(n**0.5))
    if g % 2 or g % k or g // k < 2:
        raise InputError(
            f"{name} with {n} agents needs an even grid size divisible by {k} into squares of "
            f"side ≥ 2 (got g={g})"
        )
    return g // k


def four_agent_deployment(nest: Cell) -> tuple[list[list[Cell]], list[int], list[int]]:
    """n = 4: step from the nest into the 2×2 block around it (codes NW, NE, SW, SE)."""
    cx, cy = nest
    nw, ne, sw = (cx - 1, cy - 1), (cx, cy - 1), (cx - 1, cy)
    routes = [[nest, sw, nw], [nest, ne], [nest, sw], [nest]]
    depart = [1, 1, 2, 1]
    codes = [2, 1, 8, 7]
    return routes, depart, codes


def square_neighbours(owner: list[tuple[int, int]]) -> list[list[int]]:
    idx = {sq: a for a, sq in enumerate(owner)}
    out = []
    for sx, sy in owner:
        out.append(
            [idx[q] for q in ((sx - 1, sy), (sx + 1, sy), (sx, sy - 1), (sx, sy + 1)) if q in idx]
        )
    return out


def hierarchical_plan(
    name: str, g: int, n: int, explore: Callable[[Cell, int, int], list[Cell]]
) -> Plan:
    """Shared by ZigZag and Hilbert: deployment + squares; ``explore(start, code, size)``."""
    size = check_hierarchical(name, g, n)
    nest = nest_of(g)
    if n == 4:
        routes, depart, codes = four_agent_deployment(nest)
        explore_from = [len(r) - 1 for r in routes]
        owner = []
        for r, code in zip(routes, codes, strict=True):
            start = r[-1]
            r.extend(explore(start, code, size)[1:])
            owner.append((start[0] // size, start[1] // size))
        follow_path_comm = name == "zigzag"
    else:
        cells = hierarchical_start_cells(g, n)
        per_q: dict[str, list[tuple[Cell, int, Cell]]] = {}
        for cell, code in cells:
            route, touch = deployment_route(g, nest, cell)
            per_q.setdefault(quadrant(cell, nest), []).append((cell, code, touch))
        routes, depart, explore_from, owner = [], [], [], []
        for q in ("NE", "NW", "SW", "SE"):
            lst = sorted(per_q[q], key=lambda c: (-manhattan(c[0], c[2]), c[0]))
            for rank, (cell, code, _touch) in enumerate(lst):
                r, _ = deployment_route(g, nest, cell)
                explore_from.append(len(r) - 1)
                r.extend(explore(cell, code, size)[1:])
                routes.append(r)
                depart.append(rank + 1)
                owner.append((cell[0] // size, cell[1] // size))
        follow_path_comm = False
    return Plan(
        name,
        g,
        n,
        routes,
        depart,
        explore_from,
        square_neighbours(owner),
        sync=True,
        follow_path_comm=follow_path_comm,
        notes={"size": size},
    )


def single_spiral(g: int) -> list[Cell]:
    """n = 1: square rings around the nest, clipped to the grid, joined along the border."""
    cx, cy = nest_of(g)
    cells: list[Cell] = [(cx, cy)]
    for r in range(1, g):
        ring = [(cx + r, y) for y in range(cy - r + 1, cy + r + 1)]  # East side, South
        ring += [(x, cy + r) for x in range(cx + r - 1, cx - r - 1, -1)]  # South side, West
        ring += [(cx - r, y) for y in range(cy + r - 1, cy - r - 1, -1)]  # West side, North
        ring += [(x, cy - r) for x in range(cx - r + 1, cx + r + 1)]  # North side, East
        cells.extend(c for c in ring if 0 <= c[0] < g and 0 <= c[1] < g)
    return join(cells)


def plan(g: int, n: int) -> Plan:
    if n == 1:
        return Plan("zigzag", g, 1, [single_spiral(g)], [1], [0], [[]])
    return hierarchical_plan("zigzag", g, n, zigzag_route)
