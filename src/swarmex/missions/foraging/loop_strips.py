"""Loop Strips: our stronger strategy — Strips' lockstep sweep without the trip to the border.

Why. In the thesis's data and ours, Strips has the cheapest communication and the cheapest
transport start-up: its robots sweep in lockstep, all in the same column, so when the food is
found every robot is near the finder and near the food's column. Its price is the deployment:
every robot first walks to the West border and along it (T_dep ≈ g), and the region near the
nest is explored only halfway through. Loop Strips keeps the lockstep and removes that walk.

* The grid is cut into ``n`` horizontal strips of height ``h = g/n`` as in Strips, and each strip
  into two halves. A robot starts on the column next to the nest, at the middle of its strip,
  and sweeps (boustrophedon, vertical legs) its *first* half going West to the border, steps
  into the *second* half and sweeps it East across the whole grid, steps back into the first
  half and sweeps its East part going West to the nest's column: every cell exactly once.
* Deployment is a walk of at most ``g/2`` along the column next to the nest (one robot per
  round, farthest first, so nobody passes a parked robot): T_dep ≈ g/2 instead of ≈ g.
* All robots start together and have the same schedule, so at any time they are in the same
  column. Even strips take the upper half first, odd strips the lower half (mirror images), so
  in every phase half of the neighbouring pairs meet on their shared border every two columns,
  exactly as in Strips, and the other pairs are ``h`` rows apart in the same column: a short
  detour (ch. 4 rendezvous rule).

Supported: even ``g`` divisible by ``n`` with strips of height ≥ 2.
"""

from __future__ import annotations

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, lpath, nest_of
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.strips import strip_plan


def legs(xs: range, rows: list[int], first_down: bool) -> list[Cell]:
    """Boustrophedon over ``rows`` (top→bottom order) for the columns ``xs`` in order."""
    out: list[Cell] = []
    down = first_down
    for x in xs:
        out.extend((x, y) for y in (rows if down else rows[::-1]))
        down = not down
    return out


def loop(g: int, top: int, h: int, upper_first: bool) -> list[Cell]:
    """One strip's loop: first half West, second half East, first half back West."""
    c = g // 2
    up_rows = list(range(top, top + (h + 1) // 2))
    low_rows = list(range(top + (h + 1) // 2, top + h))
    first, second = (up_rows, low_rows) if upper_first else (low_rows[::-1], up_rows[::-1])
    # phase 1 must end on the row next to the second half, so pick its first direction
    west = range(c - 1, -1, -1)
    p1 = legs(west, first, first_down=True)
    if p1[-1][1] != first[-1]:
        p1 = legs(west, first, first_down=False)
    p2 = legs(range(0, g), second, first_down=True)  # starts next to the first half
    back = legs(range(g - 1, c - 1, -1), first[::-1], first_down=True)
    return p1 + p2 + back


def plan(g: int, n: int) -> Plan:
    if g % 2 or g % n or g // n < 2:
        raise InputError(
            f"loop-strips needs an even grid size divisible by --agents into strips of height "
            f"≥ 2 (g={g}, n={n})"
        )
    h = g // n
    nest = nest_of(g)
    cx = nest[0]
    strips = []
    for s in range(n):
        cells = loop(g, s * h, h, upper_first=(s % 2 == 0))
        strips.append((s, cells))
    strips.sort(key=lambda e: (-abs(e[1][0][1] - nest[1]), e[1][0][1]))
    first_step = (cx - 1, nest[1])
    legs = [
        (s, [nest, first_step, *lpath(first_step, cells[0], x_first=False)], cells)
        for s, cells in strips
    ]
    return strip_plan("loop-strips", g, n, h, legs, follow_path_comm=False)
