"""Strips (thesis §3.1, Algorithms 2–4).

Robots leave the nest West, one per round in id order (robot ``r`` moves first in round
``r + 1``), learn ``g`` at the West border, and walk along the border (column 0) to their
Start-Cell. Start-Cells are Alg. 3's ``(0, i), (0, i + 1)`` for ``i = strip - 1, 3·strip - 1,
…`` (the listing's ``i ← strip - 1`` inside the loop is read as an initialisation), sorted by
decreasing distance from the touch point, so the first robot out takes the farthest. All
robots wait until the last one is in place (T_dep) and then sweep their strip
boustrophedon-style East: a vertical leg is ``strip - 1`` moves (it covers ``strip`` cells;
Alg. 4's ``North(strip)`` would leave the strip), then one move East.

Because neighbouring strips are mirror images started at the same moment, every robot meets
both neighbours on the shared strip borders every two columns: communication needs no detour.

Supported: any ``n`` with ``g % n == 0`` (the thesis's precondition).
"""

from __future__ import annotations

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, lpath, manhattan, nest_of
from swarmex.missions.foraging.plan import Plan


def start_cells(g: int, n: int) -> list[tuple[Cell, int, bool]]:
    """Alg. 3's Start-Cells as ``(cell, strip index, starts at bottom corner)``."""
    strip = g // n
    out: list[tuple[Cell, int, bool]] = []
    i = strip - 1
    s = 0
    while len(out) < n:
        out.append(((0, i), s, True))  # bottom row of strip s
        if len(out) == n:
            break
        out.append(((0, i + 1), s + 1, False))  # top row of strip s + 1
        i += 2 * strip
        s += 2
    return out


def sweep(g: int, strip_index: int, strip: int, bottom: bool) -> list[Cell]:
    """Exploration route of one strip from its Start-Cell (included)."""
    top, bot = strip_index * strip, strip_index * strip + strip - 1
    out: list[Cell] = []
    up = bottom
    for x in range(g):
        ys = range(bot, top - 1, -1) if up else range(top, bot + 1)
        out.extend((x, y) for y in ys)
        up = not up
    return out


def plan(g: int, n: int) -> Plan:
    if g % n:
        raise InputError(f"strips needs the grid size to be a multiple of --agents (g={g}, n={n})")
    strip = g // n
    nest = nest_of(g)
    touch: Cell = (0, nest[1])
    cells = start_cells(g, n)
    order = sorted(cells, key=lambda c: -manhattan(c[0], touch))  # stable on ties
    legs = []
    for cell, s, bottom in order:
        deploy = [nest, *lpath(nest, touch), *lpath(touch, cell, x_first=False)]
        legs.append((s, deploy, sweep(g, s, strip, bottom)))
    return strip_plan("strips", g, n, strip, legs, follow_path_comm=True)


def strip_plan(
    name: str,
    g: int,
    n: int,
    strip: int,
    legs: list[tuple[int, list[Cell], list[Cell]]],
    follow_path_comm: bool,
) -> Plan:
    """A plan of one robot per horizontal strip, robots in departure order.

    ``legs`` holds, per robot, its strip's index, its deployment route from the nest (ending
    at the strip's first cell) and its exploration route (starting there). Neighbours are the
    robots of the adjacent strips, the ones a strip's robot informs (§4.1).
    """
    routes, explore_from, owner = [], [], []
    for s, deploy, explore in legs:
        explore_from.append(len(deploy) - 1)
        routes.append([*deploy, *explore[1:]])
        owner.append(s)
    by_strip = {s: a for a, s in enumerate(owner)}
    neighbours = [[by_strip[t] for t in (s - 1, s + 1) if t in by_strip] for s in owner]
    return Plan(
        name,
        g,
        n,
        routes,
        depart=list(range(1, n + 1)),
        explore_from=explore_from,
        neighbours=neighbours,
        sync=True,
        follow_path_comm=follow_path_comm,
        notes={"strip": strip, "strip_of": owner},
    )
