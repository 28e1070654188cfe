"""Sector Loop: Sectors near the nest, Loop Strips in the far field (issue 17, item 3).

Why. The thesis's patterns split into two families. Sectors and Spiral sweep outward from the
nest, so food near the nest is found within a few dozen rounds; but their robots end up spread
around the nest, and once far food is found the word must travel round that ring and the
robots must cross the grid to the food (communication plus the wait for the last robots is
≈ 200–300 rounds at N = 16, against ≈ 90 for Strips). Strips and Loop Strips keep all robots in
one column, so communication is cheap, but they reach the cells near the nest late. Sector Loop
does the first in the near field and the second in the far field:

* **Phase A (near).** Every robot sweeps its Sectors sector (§3.4, Alg. 11–12, the same
  deployment and emission), restricted to the cells at Manhattan distance ``< R`` from the nest.
  All n robots sweep outward at once, so every cell near the nest is found as soon as Sectors
  finds it.
* **Phase B (far).** Loop Strips' sweep (:mod:`.loop_strips`): ``n`` equal horizontal
  strips, each robot loops through its own (first half-strip West from the nest's column,
  second half-strip East across the grid, first half-strip back). A robot takes the strip that
  matches the row where its sector ended (robots sorted by that row, strips top to bottom, so
  the transitions do not cross). All robots start phase B in the same round: one that would
  arrive early steps back and forth in its own sector first. From then on every robot is in
  the same column in every round, which is what keeps Loop Strips' communication short. The
  phase-A diamond is crossed, not skipped: skipping it saved walking but broke the lockstep,
  and communication then cost 200–300 rounds instead of ≈ 100 (docs/foraging.md).

The switch radius ``R`` is what the robots compute from ``g`` and ``n`` (:func:`switch_radius`).

Neighbours (whom a robot tells, ch. 4): the robots of the adjacent sectors (phase A) and of the
adjacent strips (phase B), up to four; the seed rule's rendezvous (:mod:`.comm`) plans the
meetings and crosses off those it learns are informed.

Cost: the same memory as Sectors plus Loop Strips (a function of ``(id, n, g)`` and a step
counter); the phase-B start round is computed from ``(g, n)`` like every other timetable.

Supported: ``n`` a multiple of 8 (Sectors' division) and an even ``g`` divisible by ``n`` into
strips of height ≥ 2 (Loop Strips).
"""

from __future__ import annotations

from swarmex.errors import InputError
from swarmex.missions.foraging import loop_strips, sectors
from swarmex.missions.foraging.grid import join
from swarmex.missions.foraging.plan import Plan

NAME = "sector-loop"


def switch_radius(g: int, n: int) -> int:
    """The Manhattan radius of phase A: 20 % of the corner–nest distance ``D = g``.

    This is the 0–20 % separation band. Of the radii we measured (0, 12, 25, 38, 51 with
    g = 128, n = 16; docs/foraging.md) it has the smallest sum of losses against the best seed
    pattern over the bands: a larger radius delays every far cell by the extra phase-A rounds
    (≈ 2R²/n), a smaller one leaves the near cells to the strips.
    """
    del n
    return g // 5


def plan(g: int, n: int, radius: int | None = None) -> Plan:
    """The Sector Loop plan; ``radius`` overrides :func:`switch_radius` (tests, studies)."""
    if n % 8 or g % 2 or g % n or g < 2 * n:
        raise InputError(
            f"{NAME} supports --agents a multiple of 8 and an even grid size divisible by "
            f"--agents into strips of height ≥ 2 (g={g}, n={n})"
        )
    r = max(0, switch_radius(g, n) if radius is None else radius)

    def near_first(cells: list[tuple[int, int]], lower: bool) -> list[tuple[int, int]]:
        # a sector with no cell inside the diamond still deploys to its Start-Cell
        order = sectors.sweep(cells, lower)
        return [(u, v) for u, v in order if u + v < r] or order[:1]

    base = sectors.plan(g, n, name=NAME, order_fn=near_first)
    routes = [list(rt) for rt in base.routes]
    # robots sorted by the row where phase A leaves them take the strips top to bottom
    order = sorted(range(n), key=lambda a: (routes[a][-1][1], routes[a][-1][0], a))
    h = g // n
    owner = [0] * n
    legs_b = []
    for s, a in enumerate(order):
        owner[a] = s
        loop = loop_strips.loop(g, s * h, h, upper_first=(s % 2 == 0))
        legs_b.append((a, join([loop[0]], start=routes[a][-1]), loop))
    # free-flow round at which each robot would reach its strip; the early ones wait (by
    # stepping back and forth in their own sector) so that all start phase B together
    arrive = {a: base.depart[a] - 1 + len(routes[a]) - 1 + len(w) - 1 for a, w, _ in legs_b}
    latest = max(arrive.values())
    far_from = [0] * n
    for a, walk, loop in legs_b:
        end, prev = routes[a][-1], routes[a][-2]
        pad = [prev, end] * ((latest - arrive[a]) // 2)
        routes[a] = [*routes[a], *pad, *walk[1:]]
        far_from[a] = len(routes[a]) - 1
        routes[a] += loop[1:]
    by_strip = {owner[a]: a for a in range(n)}
    neighbours = []
    for a in range(n):
        near = [by_strip[t] for t in (owner[a] - 1, owner[a] + 1) if t in by_strip]
        neighbours.append(list(dict.fromkeys([*base.neighbours[a], *near])))
    return Plan(
        NAME,
        g,
        n,
        routes,
        depart=list(base.depart),
        explore_from=list(base.explore_from),
        neighbours=neighbours,
        notes={"radius": r, "strip": h, "strip_of": owner, "far_from": far_from},
    )
