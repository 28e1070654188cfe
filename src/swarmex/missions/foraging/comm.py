"""Communication phase (thesis ch. 4): who tells whom, in which order, where they meet.

Two rules, chosen by the foraging option ``comm`` (``--comm``):

``seed`` (the default): what seed 002 and its author's simulator do, with no robot knowing
anything it was not told or cannot see.

* *Learning.* A robot learns the food cell by standing on it (the finder) or from a robot
  at distance 1 that knows it, one hop per round (§1.3.2; the simulator passes it every tick
  to every informed robot's neighbours, ``updateFoodFlagsAccTo``).
* *Whom to tell* (§4.1, §4.2, §4.4): the finder tells all its pattern neighbours
  (``Plan.neighbours``), any other robot all but the one that told it. The list is fixed when
  the robot learns; it shrinks only by what the robot itself observes (:func:`cross_off`):
  a listed neighbour is crossed off when the two stand at distance 1 (they have exchanged
  the location: the teller crosses off the robot it told, as the simulator's
  ``tlist.remove(y)`` does), or when the robot stands next to the cell where that
  neighbour's pattern puts it and the neighbour is not there nor next to it: only a robot
  that knows the food leaves its route, so it already knows.
* *Where to meet* (§4, §4.2): a neighbour's position is predicted from its pattern alone
  (:func:`predicted`; the route is a function of its id, n and g, shifted by the rounds it
  was held up), never from whether it knows. The robot tries every order of its remaining
  neighbours (at most 4! = 24) and keeps the one with the earliest completion; for each it
  computes the earliest round at which it can stand next to the neighbour's predicted
  position, walks there by Alg. 1 and re-plans every round (:func:`meet_goal`).
* *When to detour* (:func:`keeps_route`): Strips (§4.1), ZigZag, and Hilbert with 16 or more
  robots (§4.2; the simulator's ``getNextCOMMmove`` walks the rest of the exploration route
  first, then goes to the neighbours' last cells) keep following their exploration route and
  detour only when it ends; Sectors and Spiral (§4.4; ``SecCom`` plans the meeting at once)
  and Hilbert with 4 robots detour at once. Why Hilbert with 4 differs from the simulator:
  §4.2 gives "keeps following its exploration path" only for *ZigZag* with four robots (their
  symmetric routes meet regularly), every other robot "takes the shortest possible path to
  reach its neighbor" (ch. 4), §7.1 finds "Zigzag and Hilbert have fast communication when
  there are only 4 agents", and Figs. 78–79 give Hilbert-4 a non-zero COMM+TRANS (its robots
  do not enter transport together). Route-first gave Hilbert-4 2–5× the thesis's
  communication time and no COMM+TRANS at all (docs/foraging.md). At 16 robots route-first
  matches the figures (communication within 10 % in four bands of five), so it stays.
* A robot whose list is empty enters Transportation.

``omniscient`` (the rule before 25 Nov 2026, kept so that older records can be reproduced):
the message carries the discovery round, the whole run is deterministic from there, so an
informed robot is taken to know where every robot is and *whether it already knows*: it
drops a neighbour from its list as soon as anyone has informed it, predicts robots that left
their route at their true cell, and only Strips and ZigZag with 4 robots keep to their route.

The functions below are the rule's entry points; :class:`~.sim.Mission` calls them every
round, and a faster round loop (the PettingZoo environment's) can call the same ones. A plain
run plays them compiled: :func:`~.fastloop.comm_rounds` is their line-by-line port (the word
as bit sets), so a change to a rule here must be made there too;
``tests/missions/foraging/test_loops_agree.py`` compares the two on many runs.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import permutations

import numpy as np

from swarmex.missions.foraging.grid import Cell, manhattan

SEED = "seed"
OMNISCIENT = "omniscient"
COMM_RULES = (SEED, OMNISCIENT)
# patterns whose informed robots finish their exploration route before detouring (seed rule),
# with the fewest robots for which they do (Hilbert with 4 detours at once: see above)
ROUTE_FIRST = {"zigzag": 1, "hilbert": 16}
SHORT_FUTURE = 16  # meet() scans futures up to this many rows without numpy


def meet(me: Cell, future: np.ndarray) -> int:
    """Earliest τ ≥ 0 at which a robot now at ``me`` can be next to ``future[τ]``.

    ``future`` is the neighbour's predicted position for τ = 0, 1, …; it stays at the last
    entry afterwards. A short future (a finished route is one row, most of a communication
    phase's calls) is scanned in plain Python, where numpy's per-call cost would be most of
    the round's; the same rule either way.
    """
    if 0 < len(future) <= SHORT_FUTURE:
        mx, my = me
        d = 0
        for tau, (x, y) in enumerate(future.tolist()):
            d = abs(x - mx) + abs(y - my) - 1
            if d <= tau:
                return tau
        return max(len(future) - 1, d)
    d = np.abs(future[:, 0] - me[0]) + np.abs(future[:, 1] - me[1]) - 1
    ok = d <= np.arange(len(future))
    if ok.any():
        return int(np.argmax(ok))
    return int(max(len(future) - 1, d[-1]))


def best_order(
    me: Cell, t: int, targets: list[int], future_of: Callable[[int, int], np.ndarray]
) -> tuple[list[int], int]:
    """Order of ``targets`` with the earliest completion; ``future_of(b, t)`` predicts ``b``."""
    best: tuple[int, list[int]] | None = None
    for perm in permutations(targets):
        tc, p = t, me
        for b in perm:
            fut = future_of(b, tc)
            tau = meet(p, fut)
            tc += tau
            last = fut[min(tau, len(fut) - 1)]
            p = (int(last[0]), int(last[1]))
        if best is None or tc < best[0]:
            best = (tc, list(perm))
    assert best is not None
    return best[1], best[0]


def keeps_route(
    rule: str, algorithm: str, follow_path_comm: bool, exploring: bool, n: int
) -> bool:
    """Whether a robot that has just learned the food keeps following its route (and detours
    to the neighbours still on its list only when the route ends). ``follow_path_comm`` is the
    pattern's own flag (Strips; ZigZag with 4 robots); the seed rule adds ZigZag robots, and
    Hilbert robots of a team of 16 or more, that have started exploring (``exploring``: one
    told while still deploying has no regular meetings to wait for, and the simulator never
    informs one then, as it senses the food only while exploring)."""
    if follow_path_comm:
        return True
    least = ROUTE_FIRST.get(algorithm)
    return rule == SEED and least is not None and n >= least and exploring


def first_targets(
    rule: str,
    neighbours: Sequence[int],
    teller: int | None,
    informed: Sequence[bool],
    one_way: bool = False,
) -> list[int]:
    """The list of a robot that has just learned the food from ``teller`` (None: it found it):
    its pattern neighbours but the teller. ``one_way`` (seed rule, :func:`one_way`): a finder
    tells only its last listed neighbour, its successor on the ring. The omniscient rule also
    leaves out robots that already know."""
    if rule == SEED and one_way and teller is None and neighbours:
        return [neighbours[-1]]
    todo = [b for b in neighbours if b != teller]
    if rule == OMNISCIENT:
        todo = [b for b in todo if not informed[b]]
    return todo


def one_way(rule: str, algorithm: str, n: int) -> bool:
    """Whether the word goes round the ring one way (seed rule): Spiral with 4 or 8 robots,
    whose finder in the simulator tells only its successor (``Agent.setReceivedFrom`` for
    ``LOPEZ_ORTIZ4/8``: ``transmitTo = id + 1``), each robot then the neighbour it did not
    hear from. §4.4 says the finder tells both; the simulator's 16-robot Spiral and Sectors
    do that (``SecCom``), and so do we there."""
    return rule == SEED and algorithm == "spiral" and n in (4, 8)


def predicted(pos: np.ndarray, t_end: int, delay: int, t: int) -> Cell:
    """Where a robot's pattern puts it at round ``t``: its timetable column ``pos`` (rounds
    ``0 … t_end``, halted at the end) shifted by the ``delay`` rounds it was held up."""
    p = pos[min(max(0, t - delay), t_end)]
    return (int(p[0]), int(p[1]))


def absent(me: Cell, there: Cell, expected: Cell) -> bool:
    """Seen from ``me``: a robot whose pattern puts it at ``expected`` is not there nor next to
    it (it stands at ``there``), while ``me`` is close enough to see (distance ≤ 1 from
    ``expected``, so the robot would be within the 2-hop visibility)."""
    return manhattan(me, expected) <= 1 and manhattan(there, expected) > 1


class Word:
    """Who knows the food, as each robot knows it (the seed rule's only knowledge of others).

    A robot's message carries the food cell and what the robot knows of the others: which
    robots it knows to be informed, each with the round it learned and the list it then had
    to tell (the neighbour lists the robots exchange). ``know[a]`` is robot ``a``'s set, as a
    bit mask; ``rank`` and ``lists`` are those facts, fixed when a robot learns, and a robot
    reads them only for robots in its own set. Knowledge moves one hop per round, with the
    location: a robot that learns gets its teller's set, and two informed robots at
    distance 1 merge theirs (:meth:`exchange`).
    """

    def __init__(self, n: int) -> None:
        self.know = [0] * n
        self.rank: list[tuple[int, int] | None] = [None] * n  # (round learned, id)
        self.holders: list[list[int]] = [[] for _ in range(n)]  # robots that listed b

    def learn(self, a: int, t: int, teller: int | None, todo: Sequence[int]) -> None:
        """Robot ``a`` learns the food in round ``t`` from ``teller`` (None: it found it) and
        has ``todo`` to tell; the teller now knows that ``a`` knows."""
        self.rank[a] = (t, a)
        self.know[a] |= (self.know[teller] if teller is not None else 0) | (1 << a)
        if teller is not None:
            self.know[teller] |= 1 << a
        for b in todo:
            self.holders[b].append(a)

    def exchange(self, pairs: Sequence[tuple[int, int]]) -> None:
        """Informed robots ``a``, ``b`` at distance 1 merge what they knew before this Look."""
        snap = list(self.know)
        for a, b in pairs:
            self.know[a] |= snap[b]
            self.know[b] |= snap[a]

    def knows(self, a: int, b: int) -> bool:
        return bool(self.know[a] >> b & 1)

    def settled(self, a: int, b: int) -> bool:
        """Whether ``a`` may cross ``b`` off: it knows ``b`` knows, or it knows that a robot
        informed before it (earlier round, or the same round and a smaller id) had ``b`` on
        its list. That robot keeps ``b`` until it knows ``b`` knows (the earliest such robot
        never hands the duty on), so ``b`` is still told; this is how the thesis's §4.2
        example ends with all four ZigZag robots entering transport together."""
        if self.know[a] >> b & 1:
            return True
        ra = self.rank[a]
        assert ra is not None
        k = self.know[a]
        return any(x != a and k >> x & 1 and self.rank[x] < ra for x in self.holders[b])  # type: ignore[operator]


def adjacent_pairs(pos: Sequence[Cell], who: Sequence[int]) -> list[tuple[int, int]]:
    """Pairs of robots of ``who`` at distance 1 (cells are distinct outside the nest; two
    robots in the nest cell are at distance 0 and count too)."""
    at: dict[Cell, list[int]] = {}
    for a in who:
        at.setdefault(pos[a], []).append(a)
    out: list[tuple[int, int]] = []
    get = at.get
    for (x, y), here in at.items():  # a cell holds one robot, but in the nest
        if len(here) > 1:
            out.extend((a, b) for i, a in enumerate(here) for b in here[i + 1 :])
        for c in ((x + 1, y), (x, y + 1)):
            there = get(c)
            if there is not None:
                out.extend([(a, b) for b in there for a in here])
    return out


def cross_off(
    rule: str,
    targets: list[list[int]],
    informed: Sequence[bool],
    pos: Sequence[Cell],
    expected: Callable[[int], Cell],
    active: Sequence[int],
    word: Word | None = None,
) -> None:
    """One Look's update of the lists of the robots in ``active`` (those telling), in place.

    ``seed``: robot ``a`` crosses off a listed neighbour ``b`` that :meth:`Word.settled`
    allows (it knows ``b`` knows, from meeting it or from a message, or an earlier robot has
    ``b`` on its list) or that is :func:`absent` from where its pattern puts it
    (``expected(b)``). ``omniscient``: ``a`` drops every neighbour that knows.
    """
    for a in active:
        todo = targets[a]
        if not todo:
            continue
        if rule == OMNISCIENT:
            targets[a] = [b for b in todo if not informed[b]]
            continue
        assert word is not None
        me = pos[a]
        targets[a] = [
            b for b in todo if not (word.settled(a, b) or absent(me, pos[b], expected(b)))
        ]


def meet_goal(me: Cell, there: Cell, future: np.ndarray) -> Cell:
    """The cell a robot at ``me`` walks toward to meet a neighbour whose pattern puts it at
    ``future[τ]`` for τ = 0, 1, … (seed rule): that position at the earliest meeting round;
    when the meeting is now and the neighbour is seen next to its expected cell (``there``,
    e.g. a halted robot that stepped aside), the neighbour itself."""
    tau = meet(me, future)
    q = future[min(tau, len(future) - 1)]
    goal = (int(q[0]), int(q[1]))
    if tau == 0 and manhattan(there, goal) <= 1:
        return there
    return goal
