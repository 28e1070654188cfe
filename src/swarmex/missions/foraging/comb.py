"""Comb: all robots side by side, one row each, sweeping the grid as one block (issue 17.3).

Why. After the food is found, what separates the patterns is how long the word takes to reach
every robot and how far the robots then are from the food: Strips' robots are spread over all
g rows, Sectors' and Spiral's round the nest. A *comb* keeps the n robots in n adjacent rows,
and its route wastes almost no move, so it explores at nearly the n-new-cells-per-round limit.

A comb that sweeps the grid band by band (bands of n rows) usually pays for each turn: at the
end of a pass every robot must shift n rows. Here the turn is a **staircase** that costs
nothing: the robot nearest the next band turns n − 1 columns before the border, the next one
n − 2 columns before, …, the farthest at the border, each walking its column to its row of the
next band (the order of the robots in the comb flips). The turn's 2n × n cells are covered
exactly once (robot i walks 4i + 2 of them).
The price is a shear: the robots leave the turn up to 4(n − 1) rounds apart, a diagonal line,
and are level again only after the next turn, where their roles swap.

Route. Bands of n rows, each split into a West and an East half. The comb deploys up the column
next to the nest into the band just above the nest's row (≈ n rounds: one robot per round
leaves the nest, farthest row first) and visits the 2g/n half-bands in one loop: the West
halves upward to the North border, the East halves down to the South border, the West halves
back up to the nest's row. A pass that ends on the middle column runs straight on into the
other half; that does not swap the roles, so there the robots that are ahead step back and
forth until the comb is level. After the deployment every cell is explored by one robot, once,
apart from those levelling steps; the
mean discovery time of a uniformly placed food is ≈ T_dep + g²/(2n) + the levelling
(g = 128: 559 rounds with 16 robots, 1046 with 8; Strips 632 / 1135, Sectors 535 / 1047).

Communication: a robot's neighbours are the robots of the adjacent rows (a chain), met by the
seed rule's rendezvous. Because of the shear, a robot often has to wait for the neighbour ahead
of it to come back from the next turn; that is what makes its communication slower than
Strips' (docs/foraging.md).

Supported: ``g`` a multiple of ``4n`` (an even number of bands in each half of the grid, so the
loop closes on the nest's row).
"""

from __future__ import annotations

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, nest_of
from swarmex.missions.foraging.plan import Plan

NAME = "comb"


def passes(g: int, n: int) -> list[tuple[int, int, int, int]]:
    """The comb's passes in order: ``(band, first column, last column, direction)``.

    A pass that ends on the middle column and is followed by the same band's other half is
    merged with it (the comb runs straight on); every other pass ends with a staircase turn to
    the next band.
    """
    b_count = g // n
    half = g // 2
    mid = b_count // 2
    order: list[tuple[int, str]] = []
    order += [(b, "W") for b in range(mid - 1, -1, -1)]
    order += [(b, "E") for b in range(b_count)]
    order += [(b, "W") for b in range(b_count - 1, mid - 1, -1)]
    out: list[tuple[int, int, int, int]] = []
    direction = -1  # the first pass goes West from the middle column
    for band, side in order:
        lo, hi = (0, half - 1) if side == "W" else (half, g - 1)
        if out and out[-1][0] == band:  # straight on into the other half, same direction
            b, first, _, d = out[-1]
            out[-1] = (b, first, hi if d > 0 else lo, d)
            continue
        if out:
            direction = -direction  # a staircase turn reverses the direction
        first, last = (hi, lo) if direction < 0 else (lo, hi)
        out.append((band, first, last, direction))
    return out


def routes_of(g: int, n: int) -> tuple[list[list[Cell]], list[int]]:
    """Each robot's exploration route (from its first cell) and its initial row.

    A staircase turn leaves robot i of the comb (i rows from the next band) ``4i + 2`` rounds
    behind the first; the next turn swaps the roles and levels the comb again. A run straight
    on into the other half does not swap them, so there the robots that are ahead step back and
    forth until the comb is level (≈ 2(n − 1) rounds on average, twice per sweep).
    """
    ps = passes(g, n)
    half = g // 2
    band0 = ps[0][0]
    rows = [band0 * n + r for r in range(n)]  # robot a starts on row band0·n + a
    col = [ps[0][1]] * n
    out: list[list[Cell]] = [[(col[a], rows[a])] for a in range(n)]
    for j, (band, first, last, d) in enumerate(ps):
        crossing = abs(last - first) >= half  # this pass runs through both halves
        if crossing:  # level the comb on the middle column before running on
            mid = half - 1 if d > 0 else half
            for a in range(n):
                out[a].extend((x, rows[a]) for x in _span(col[a], mid, d)[1:])
                col[a] = mid
            level = max(len(r) for r in out)
            for a in range(n):
                back = (mid - d, rows[a])
                out[a].extend([back, (mid, rows[a])] * ((level - len(out[a])) // 2))
        nxt = ps[j + 1] if j + 1 < len(ps) else None
        if nxt is None:
            for a in range(n):
                out[a].extend((x, rows[a]) for x in _span(col[a], last, d)[1:])
            break
        v = nxt[0] - band  # -1: the next band is above, +1: below
        edge = band * n if v < 0 else band * n + n - 1
        for a in range(n):
            i = abs(rows[a] - edge)  # 0 for the robot nearest the next band
            turn = last - d * (n - 1 - i)
            out[a].extend((x, rows[a]) for x in _span(col[a], turn, d)[1:])
            new_row = edge + v * (1 + i)
            step = 1 if new_row > rows[a] else -1
            out[a].extend((turn, y) for y in range(rows[a] + step, new_row + step, step))
            rows[a], col[a] = new_row, turn
    return out, [band0 * n + r for r in range(n)]


def _span(a: int, b: int, d: int) -> list[int]:
    return list(range(a, b + d, d)) if (b - a) * d >= 0 else [a]


def plan(g: int, n: int) -> Plan:
    if g % (4 * n):
        raise InputError(
            f"{NAME} needs the grid size to be a multiple of 4 × --agents (g={g}, n={n})"
        )
    return deployed(NAME, g, n, *routes_of(g, n))


def deployed(name: str, g: int, n: int, explore: list[list[Cell]], rows: list[int]) -> Plan:
    """The plan of a comb whose robot ``a`` explores ``explore[a]`` from row ``rows[a]``: the
    deployment up the column next to the nest, the synchronised start and the chain of
    neighbours. Comb's own routes, or another comb's (bench/foraging_level_comb.py)."""
    nest = nest_of(g)
    step_out = (nest[0] - 1, nest[1])
    routes, explore_from = [], []
    for a in range(n):
        start = explore[a][0]
        deploy = [nest, step_out, *[(step_out[0], y) for y in range(nest[1] - 1, start[1] - 1, -1)]]
        explore_from.append(len(deploy) - 1)
        routes.append([*deploy, *explore[a][1:]])
    # farthest row first, one robot per round, so nobody passes a robot already in place
    order = sorted(range(n), key=lambda a: rows[a])
    depart = [0] * n
    for k, a in enumerate(order):
        depart[a] = k + 1
    neighbours = [[b for b in (a - 1, a + 1) if 0 <= b < n] for a in range(n)]
    return Plan(
        name,
        g,
        n,
        routes,
        depart=depart,
        explore_from=explore_from,
        neighbours=neighbours,
        sync=True,
        follow_path_comm=False,
        notes={"passes": len(passes(g, n)), "rows": rows},
    )
