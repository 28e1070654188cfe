"""How fast can Relay-Food deliver after the discovery? A proven floor and a computed one.

A run's total time is its exploration time E (until a robot first stands on the food) plus Q,
everything after it (communication, overlap, transport). To say how low Q can go for *any*
exploration pattern while the transport (Relay-Food, ch. 5) and the communication rule stay
the seed's, this module gives two numbers per food cell (docs/foraging.md, "Can any pattern
meet the target?"):

* :func:`proven_floor`, a bound that holds for every state the discovery can leave, whatever
  the pattern and whoever is informed, derived from the transport rules alone (its docstring
  has the argument);
* :func:`least_transport`, the least Q of the real transport code (:class:`~.sim.Mission`,
  the compiled tail) over a family of start states that are the best case for Relay-Food:
  every robot already informed and in transport (zero communication) and already on or next
  to the relay path (zero gathering). It is an *upper* estimate of the least Q over all start
  states (the family is searched, not exhausted) and at least :func:`proven_floor`.

A start state (:func:`transport_start`) has every robot in the Transportation phase: relay
robots empty on given path cells (the finder on the food, which any discovery state has),
robots still joining (Relay-Food's gathering: they walk to the food and enter the path there)
on given cells, and robots idle in the nest (which take no part; only a relaxation, since in a
real run every robot is eventually informed and joins, but a floor may only get lower for it).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from swarmex.missions.foraging.grid import Cell, manhattan, nest_of
from swarmex.missions.foraging.sim import IDLE, JOIN, RELAY, TRANSPORT, Mission
from swarmex.missions.foraging.transport import RELAY_FOOD, relay_path

NEVER = 1 << 62  # the cost of a start state the collision rule cannot play


class OffGrid(ValueError):
    """Joining robots on a ray that leaves the grid or crosses the relay path."""


RAYS = ((1, 0), (0, -1), (-1, 0), (0, 1))  # E, N, W, S


@dataclass(frozen=True)
class Start:
    """A start state for Relay-Food: ``relay`` path indices (distinct, 1…d, d the food: the
    finder), ``joining`` robots, the rest idle in the nest. Joining robots stand on the free
    cells nearest the food (``ray`` None: a crowd that arrives at once), or one every
    ``spacing`` cells along a ray leaving the food, from 2 cells away (``ray`` = (direction
    index into :data:`RAYS`, spacing): they arrive one by one, as robots informed one after
    another do)."""

    relay: tuple[int, ...]
    joining: int = 0
    ray: tuple[int, int] | None = None

    def describe(self, n: int) -> str:
        idle = n - len(self.relay) - self.joining
        how = "" if self.ray is None or not self.joining else (
            f" on ray {'ENWS'[self.ray[0]]} every {self.ray[1]}"
        )
        return f"relay at {list(self.relay)}, {self.joining} joining{how}, {idle} idle"


def proven_floor(d: int, n: int, k: int) -> int:
    """A lower bound on Q for Relay-Food with the food ``d`` steps from the nest, n robots, k
    units, from *any* state at the discovery (all k units at the food, nobody carrying).

    Why, from the rules of :mod:`.sim` (nothing else is assumed):

    1. *Flow.* At most one unit is picked up per round (one robot fits on the food cell) and
       at most one is dropped per round (carriers reach the nest only from the path cell next
       to it). A unit moves at most two path cells per round: one by its carrier's move, one
       by a hand-over in the next Look (a robot that has just received cannot hand over in
       that Look, nor can one that has just picked up), and it enters the nest by a move (no
       hand-over is made into the nest). So the first drop is at ``t ≥ ⌊d/2⌋ + 1`` and the
       k-th at ``t ≥ ⌊d/2⌋ + k``.
    2. *Work.* Every unit crosses each of the d path edges once, either carried (its carrier
       moves one cell toward the nest) or by a hand-over. Relay robots never leave the path
       and keep their order along it except by swapping with a neighbour that moves the
       other way, i.e. a carrier with an empty robot. A robot that hands a unit on is then on
       the food side of the unit's holder and can never get to its nest side again (that
       needs a swap with the holder, which carries), so it never holds that unit again: a
       unit has at most n holders and at most n − 1 hand-overs. Hence the carried moves sum
       to at least ``k(d − n + 1)``. A robot moves toward the nest only when carrying and
       toward the food only when empty, and its net move toward the nest is at most d, so
       in T rounds it makes at most ``(T + d)/2`` carried moves. With n robots:
       ``n(T + d)/2 ≥ k(d − n + 1)``, ``T ≥ 2k(d − n + 1)/n − d``.

    The steady-state relay (spacing d/n, ≈ 2(d/n − 1) rounds per unit, docs/foraging.md)
    needs ≈ 2k(d − n)/n: bound 2 is that minus ≈ d, the fill-in and drain it does not count.
    """
    flow = d // 2 + k
    work = math.ceil(2 * k * (d - n + 1) / n - d)
    return max(flow, work)


def transport_start(g: int, food: Cell, n: int, units: int, start: Start) -> Mission:
    """The :class:`~.sim.Mission` (Relay-Food, t = 0 at the discovery) in ``start``: every robot
    informed and transporting; relay robots empty on their path cells, joining robots on the
    free cells nearest the food (ties by cell), the others idle in the nest."""
    nest = nest_of(g)
    path = relay_path(nest, food)
    d = len(path) - 1
    relay = list(start.relay)
    if len(set(relay)) != len(relay) or any(not 1 <= i <= d for i in relay) or d not in relay:
        raise ValueError(f"relay robots need distinct path cells 1…{d}, one on the food")
    if len(relay) + start.joining > n:
        raise ValueError(f"{len(relay)} relay + {start.joining} joining robots > n = {n}")
    taken = {path[i] for i in relay} | {nest}
    if start.ray is None:
        r = n + 2  # n joining robots fit in the diamond of radius n + 2 round the food
        around = (
            (food[0] + dx, food[1] + dy)
            for dx in range(-r, r + 1)
            for dy in range(-r + abs(dx), r - abs(dx) + 1)
        )
        free = sorted(
            (c for c in around if 0 <= c[0] < g and 0 <= c[1] < g and c not in taken),
            key=lambda c: (manhattan(c, food), c),
        )
        joining = free[: start.joining]
    else:
        (dx, dy), step = RAYS[start.ray[0]], start.ray[1]
        joining = [
            (food[0] + dx * (2 + step * j), food[1] + dy * (2 + step * j))
            for j in range(start.joining)
        ]
        if any(not (0 <= x < g and 0 <= y < g) or (x, y) in taken for x, y in joining):
            raise OffGrid("the ray leaves the grid or crosses a relay robot")
    idle = n - len(relay) - len(joining)
    cells = [path[i] for i in relay] + joining + [nest] * idle
    m = Mission(g, nest, food, units, RELAY_FOOD, cells, t=0, timed=None)
    for a in range(n):
        m.mode[a] = TRANSPORT
        m.informed[a] = True
        m.informed_at[a] = 0
        m.comm_done[a] = 0
        if a < len(relay):
            m.tmode[a] = RELAY
            m.pidx[a] = relay[a]
        elif a < len(relay) + len(joining):
            m.tmode[a] = JOIN
            m.join_at[a] = d
        else:
            m.tmode[a] = IDLE
    return m


def transport_time(g: int, food: Cell, n: int, units: int, start: Start) -> int | None:
    """Rounds from the discovery until the k-th unit is home, from ``start`` (the real run,
    compiled); None if its ray does not fit. (Such start states first showed that an idle
    robot hemmed in by robots walking to the food had no answer in Alg. 1's resolution; the
    rule's last resort, :func:`~.resolve.resolve`, now covers them.)"""
    try:
        m = transport_start(g, food, n, units, start)
    except OffGrid:
        return None
    m.run(record=False)
    return m.t


def candidates(d: int, n: int, spacings: int = 8) -> Iterator[Start]:
    """The formations searched first: relay robots every s cells down from the food
    (s = 1 … ``spacings``, as many as fit, at most n), the rest joining near the food or
    idle; the gathered state Relay-Food itself produces (the finder on the food, all others
    next to it); and, when the path is shorter than the team, the path's top cells full with
    the rest arriving one by one along a ray (every direction, 1 to 3 cells apart)."""
    for s in range(1, min(d, spacings) + 1):
        relay = tuple(d - j * s for j in range(min(n, (d - 1) // s + 1)))
        yield Start(relay)
        if len(relay) < n:
            yield Start(relay, n - len(relay))
    yield Start((d,), n - 1)
    for top in range(d, max(0, d - 3), -1):
        relay = tuple(range(d, d - top, -1))
        if len(relay) < n:
            for ray in range(len(RAYS)):
                for step in (1, 2, 3):
                    yield Start(relay, n - len(relay), (ray, step))


def _neighbours(start: Start, d: int, n: int) -> Iterable[Start]:
    """One robot moved one or two path cells, turned from relay to joining or back, or
    added from / sent to the idle ones (the finder stays on the food)."""
    relay, ray = set(start.relay), start.ray
    for i in sorted(relay - {d}):
        for j in (i - 2, i - 1, i + 1, i + 2):
            if 1 <= j < d and j not in relay:
                yield Start(tuple(sorted(relay - {i} | {j}, reverse=True)), start.joining, ray)
        rest = tuple(sorted(relay - {i}, reverse=True))
        yield Start(rest, start.joining + 1, ray)
        yield Start(rest, start.joining, ray)
    if start.joining:
        yield Start(start.relay, start.joining - 1, ray)
    if len(relay) + start.joining < n:
        yield Start(start.relay, start.joining + 1, ray)
        for j in range(d - 1, 0, -1):
            if j not in relay:
                yield Start(tuple(sorted(relay | {j}, reverse=True)), start.joining, ray)
                break


def least_transport(
    g: int, food: Cell, n: int, units: int, budget: int = 120
) -> tuple[int, Start]:
    """The least transport time over :func:`candidates`, then improved by a first-improvement
    local search (:func:`_neighbours`) until no neighbour is better or ``budget`` more runs
    were made. Deterministic."""
    d = manhattan(nest_of(g), food)
    seen: dict[Start, int] = {}

    def cost(s: Start) -> int:
        if s not in seen:
            t = transport_time(g, food, n, units, s)
            seen[s] = NEVER if t is None else t
        return seen[s]

    best = min(candidates(d, n), key=lambda s: (cost(s), s.relay, s.joining, s.ray or (-1, 0)))
    runs = 0
    improved = True
    while improved and runs < budget:
        improved = False
        for s in _neighbours(best, d, n):
            if s in seen:
                continue
            runs += 1
            if cost(s) < cost(best):
                best, improved = s, True
                break
            if runs >= budget:
                break
    return cost(best), best
