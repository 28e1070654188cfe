"""Collision avoidance for one synchronous round (thesis §1.3.3, Algorithm 1).

Alg. 1 lets robot A take a cell C that brings it closer to its target unless a *contender* —
a robot next to C — has a larger ``(x, y)``. Read literally, contenders are robots merely
standing next to C whatever they intend, which stalls robots walking back-to-back on the
relay path (the thesis's own transport analysis has them do exactly that). Every robot's
next move is a deterministic function of what it sees within distance 2, so we read
contenders as the robots that *want* C in this round (including one that stays in C). The
rule is then:

* each robot offers an ordered list of cells: its distance-reducing moves (x first, as
  Alg. 1 enumerates them), then staying put; an idle robot offers staying put first and then
  its free neighbours, so it steps aside when a moving robot needs its cell;
* among robots that want the same non-nest cell the lexicographically larger ``(x, y)`` wins
  (ties, possible only in the nest, by smaller id); robots still following their exploration
  route rank above everyone, because those routes are designed to be collision-free and the
  other robots can compute them (ch. 4);
* a robot that cannot leave its cell keeps it; losers fall back to their next option, and
  the process repeats until no cell outside the nest is claimed twice;
* every robot's last resort is its own cell, even when its list does not end there (an idle
  robot's list ends with its side cells): an idle robot that was asked to step aside and
  finds every side cell kept stays put, and the robot that wanted its cell yields instead.
  Without that the rule had no answer, e.g. for an idle robot on a food cell in a grid
  corner hemmed in by robots still walking to the food (``swarmex.run("foraging", grid=16,
  agents=8, food=[15, 0], food_units=3, algorithm="spiral", transport="relay-path")``);
  it changes no run that had one.

Swaps of two adjacent robots (Fig. 3) and rotations are legal outcomes; two robots never end
a round in one non-nest cell. Robots that lose every option wait and retry next round.
"""

from __future__ import annotations

from swarmex.missions.foraging.grid import Cell

NEIGH: tuple[Cell, ...] = ((1, 0), (0, -1), (-1, 0), (0, 1))


def toward(p: Cell, q: Cell) -> list[Cell]:
    """Alg. 1's possible moves from ``p`` to ``q``: the x move first, then the y move."""
    out: list[Cell] = []
    if q[0] != p[0]:
        out.append((p[0] + (1 if q[0] > p[0] else -1), p[1]))
    if q[1] != p[1]:
        out.append((p[0], p[1] + (1 if q[1] > p[1] else -1)))
    return out


def sidesteps(p: Cell, g: int) -> list[Cell]:
    """The neighbours of ``p`` (a cell of the g×g grid) in :data:`NEIGH` order: E, N, W, S.
    Written out rather than as a loop over NEIGH: it is called for every idle or displaced
    robot every round (a third of a hooked Python round's cost as a comprehension)."""
    x, y = p
    out = []
    if x + 1 < g:
        out.append((x + 1, y))
    if y > 0:
        out.append((x, y - 1))
    if x > 0:
        out.append((x - 1, y))
    if y + 1 < g:
        out.append((x, y + 1))
    return out


def priority(
    cur: list[Cell], route_following: list[bool], opts: list[list[Cell]] | None = None
) -> list[int]:
    """Robots in decreasing priority: route followers, then larger (x, y), then smaller id.

    Two robots that want each other's cells (a swap, Fig. 3) go first: a third robot that
    grabbed one of the two cells would otherwise freeze both of them, and itself, for good.
    """
    n = len(cur)
    swap = [False] * n
    if opts is not None:
        where = {c: a for a, c in enumerate(cur)}
        for a in range(n):
            b = where.get(opts[a][0])
            if b is not None and b != a and opts[b][0] == cur[a]:
                swap[a] = True
    return sorted(
        range(n), key=lambda a: (not swap[a], not route_following[a], -cur[a][0], -cur[a][1], a)
    )


def resolve(cur: list[Cell], opts: list[list[Cell]], order: list[int], nest: Cell) -> list[Cell]:
    """Choose one option per robot so that no non-nest cell holds two robots.

    The rule is a pass over the robots in ``order`` that, at the first cell claimed twice,
    moves one robot to its next option and starts the pass again. A restarted pass repeats
    every claim made before the bumped robot's place unchanged, so instead of starting from
    the top the pass rolls back to that place (same result, without the O(n) restart per
    bump that made a round quadratic in a large swarm).
    """
    ch = [0] * len(cur)
    # the last resort, own cell, is one option past the list unless the list ends there
    last = [len(o) - 1 + (o[-1] != p) for o, p in zip(opts, cur, strict=True)]
    place = {a: i for i, a in enumerate(order)}
    claimed: list[Cell | None] = [None] * len(order)  # the cell the i-th robot claimed
    owner: dict[Cell, int] = {}
    i = 0
    while i < len(order):
        a = order[i]
        c = opts[a][ch[a]] if ch[a] < len(opts[a]) else cur[a]
        if c == nest:
            i += 1
            continue
        b = owner.get(c)
        if b is None:
            owner[c] = a
            claimed[i] = c
            i += 1
            continue
        stayer = a if c == cur[a] else b if c == cur[b] else -1
        if stayer >= 0:
            other = b if stayer == a else a
            bumped = stayer if ch[stayer] < last[stayer] else other
        else:
            bumped = a  # both move in: the later (lower-priority) one yields
        # never past the last resort: a robot there is a stayer with nothing left, so the
        # robot moving into its cell is bumped, and that one's last resort is elsewhere
        ch[bumped] += 1
        back = place[bumped]
        for k in range(back, i):  # undo the claims from the bumped robot's place on
            cell = claimed[k]
            if cell is not None:
                del owner[cell]
                claimed[k] = None
        i = back
    return [opts[a][ch[a]] if ch[a] < len(opts[a]) else cur[a] for a in range(len(cur))]
