"""The foraging run: synchronous Look-Compute-Move rounds until all k units are home.

Time ``t`` is the state after ``t`` rounds (everyone in the nest at ``t = 0``). In the Look of
round ``t + 1`` a robot senses food in its cell, exchanges the location with robots at distance
≤ 1, and picks up / drops / hands over food; in Compute it chooses its move; the moves of all
robots are made collision-free together (:mod:`.resolve`) and applied. Events seen in the Look
of round ``t + 1`` are stamped ``t`` (they are about the state at ``t``), so a unit dropped by a
robot that walked into the nest in round ``t`` counts at ``t``, and the mission's makespan is the
round at which the k-th unit arrives.

Frames: given ``on_frame``, :func:`run_mission` calls it once per round ``t = 0 … makespan``
with a :class:`Frame`, the state after that round's Look (row ``t`` of the record's
trajectories), as the run plays it: the timetable's rounds before the discovery, then each
round of the compiled communication phase and of the compiled transport tail (played one
round per call, so the result is the very same), or of this loop with ``fast=False``.
Raising :class:`~swarmex.missions.base.StopRun` from ``on_frame`` ends the run at that round:
the outcome holds rounds ``0 … t`` and is incomplete unless the k-th unit was already home.

Until the food is found the run is the pattern's timetable (:mod:`.timed`); from the discovery
round on, this loop takes over. Robots still exploring keep following the timetable (shifted by
the rounds they were made to wait), informed robots communicate (:mod:`.comm`) and then
transport (:mod:`.transport`). A run without ``decide`` plays these rounds in compiled ports
of this loop, the same rules with the same result: the communication phase in
:func:`~.fastloop.comm_rounds` (:meth:`Mission._comm_phase`), then the pure-transport tail in
:func:`~.fastloop.transport_tail` (with ``on_frame``, both one round per call);
``fast=False`` plays them here, the reference.

Decision hook (for :mod:`swarmex.envs.foraging_v0`): a *hooked* run (:func:`decided_rounds`,
or :func:`run_mission` given ``decide``) plays every round of this loop from round 0 (the
timetable's rounds too: robots on their routes make the timetable's moves, which resolve
without conflict, so the rounds are the same) and never hands the tail to the compiled loop
:func:`~.fastloop.transport_tail`, which plays many rounds per call. Two phases of it are
played one round per call by compiled ports of :meth:`Mission.hooked_step` instead, when no
``on_frame`` asks for frames: the rounds before anyone knows the food
(:func:`~.fastloop.explore_round`, until a robot stands on the food: its Look and the
communication rules are this loop's) and the rounds once everyone transports
(:func:`~.fastloop.hooked_round`); after each, the Mission's lists are brought up to date, and
a test compares both with this loop round by round. Each round's Compute is handed out
(:mod:`.hook`): the run yields a :class:`Compute` with every robot's seed move and takes every
robot's move back; the seed's moves give the seed's run. A
robot on its route that stays when its route moves it waits, as a blocked robot does (its
timetable shifts by a round). Three rules only a hook can reach (the
seed's robots never do these): a robot on its route that moves anywhere but where its route
goes has left its pattern (it is *displaced*, as a robot pushed off a finished route is); a
displaced robot that was telling its neighbours along its route walks to them instead; a relay
robot that steps off the relay path walks back to its nearest path cell and re-joins there
(without a hook it would go idle).
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from swarmex.missions.base import StopRun
from swarmex.missions.foraging.comm import (
    OMNISCIENT,
    SEED,
    Word,
    adjacent_pairs,
    best_order,
    cross_off,
    first_targets,
    keeps_route,
    meet,
    meet_goal,
    one_way,
    predicted,
)
from swarmex.missions.foraging.grid import Cell, manhattan
from swarmex.missions.foraging.hook import drive, hooked_options, seed_moves
from swarmex.missions.foraging.resolve import priority, resolve, sidesteps, toward
from swarmex.missions.foraging.timed import Timed
from swarmex.missions.foraging.transport import (
    END_TO_END,
    RELAY_FOOD,
    RELAY_PATH,
    entry_cell,
    relay_path,
)

EXPLORE, FOLLOW, COMM, TRANSPORT = 0, 1, 2, 3
JOIN, RELAY, E2E, IDLE = 0, 1, 2, 3


def round_limit(t: int, g: int, k: int) -> int:
    """The last round of a run started at round ``t``.

    Far beyond any run that finishes, so one that reaches it is locked for good (a crowded
    End-to-End team, docs/foraging.md): it ends there as an incomplete run whose record says
    ``stalled`` (the round), not as an exception that would lose the record."""
    return t + 200 * g * (k + g) + 10_000


@dataclass(frozen=True)
class Frame:
    """One round of a run as ``on_frame`` sees it: the state after the Look of round ``t``.

    ``positions[a]`` is robot ``a``'s cell ``(x, y)`` (the record's trajectory row ``t``);
    ``carrying[a]`` whether it holds a unit, ``informed[a]`` whether it knows where the food
    is; ``delivered`` units are in the nest and ``food_left`` still at the food. The arrays are
    copies: a callback may keep them. This is what the ``--render`` animation draws per frame
    (robots filled while carrying, the food square shrinking, the counts).
    """

    t: int
    positions: np.ndarray  # (n, 2) int
    carrying: np.ndarray  # (n,) bool
    informed: np.ndarray  # (n,) bool
    delivered: int
    food_left: int


FrameSink = Callable[[Frame], object]


@dataclass(frozen=True)
class Compute:
    """A hooked run's request, at the Compute of round ``t`` (the state after its Look):
    ``builtin[a]`` is robot ``a``'s seed move (a :mod:`.hook` move code); the answer is an
    (n,) array of every robot's move. ``mission`` is the run's state (read-only);
    ``positions`` its robots' cells as an array (what a caller that works on arrays wants,
    without converting ``mission.pos``)."""

    mission: Mission
    t: int
    builtin: np.ndarray  # (n,) int64
    positions: np.ndarray  # (n, 2) int64: every robot's cell after the Look (a copy)


Decide = Callable[[Compute], np.ndarray]  # decide(request) -> every robot's move
Rounds = Generator[Compute, np.ndarray, None]  # a hooked run's rounds (module docstring)


@dataclass
class Outcome:
    positions: np.ndarray  # (makespan + 1, n, 2)
    jobs: list[list[tuple[int, int, int, str]]]  # per robot: (t, x, y, "pickup"|"drop")
    handovers: list[int]
    discovery: int | None  # None: the run was stopped before the food was found
    finders: list[int]
    informed_at: list[int | None]
    comm_done: list[int | None]
    makespan: int
    delivered: int
    complete: bool
    extra: dict[str, object] = field(default_factory=dict)


class Mission:
    """State of one run from a given moment on; :meth:`step` plays one round."""

    def __init__(
        self,
        g: int,
        nest: Cell,
        food: Cell,
        units: int,
        transport: str,
        start: list[Cell],
        t: int = 0,
        timed: Timed | None = None,
        hooked: bool = False,
        comm: str = SEED,
    ) -> None:
        if comm not in (SEED, OMNISCIENT):
            raise ValueError(comm)
        self.g, self.nest, self.food = g, nest, food
        self.comm = comm  # the communication rule (:mod:`.comm`)
        self.word = Word(len(start)) if comm == SEED else None  # who knows, as each knows
        self.units = units
        self.k = units
        self.transport = transport
        self.n = len(start)
        self.t = t
        self.timed = timed
        n = self.n
        self.pos: list[Cell] = list(start)
        self.mode = [EXPLORE] * n
        self.delay = [0] * n
        self.displaced = [False] * n
        self.informed = [False] * n
        self.informed_at: list[int | None] = [None] * n
        self.targets: list[list[int]] = [[] for _ in range(n)]
        self.carrying = [False] * n
        self.tmode = [JOIN] * n
        self.pidx = [-1] * n
        self.comm_done: list[int | None] = [None] * n
        self.jobs: list[list[tuple[int, int, int, str]]] = [[] for _ in range(n)]
        self.handovers = [0] * n
        self.delivered = 0
        self.path = relay_path(nest, food)
        self.path_index = {c: i for i, c in enumerate(self.path)}
        self.neighbours = timed.plan.neighbours if timed else [[] for _ in range(n)]
        self.follow_comm = bool(timed and timed.plan.follow_path_comm)
        self.one_way = bool(timed and one_way(comm, timed.plan.algorithm, n))
        self.history: list[list[Cell]] = []
        self.join_at: dict[int, int] = {}
        self.tail_chunks: list[np.ndarray] = []
        # a hooked run's compiled phases: rows so far in round order, the open (chunk, state)
        self.segments: list[np.ndarray] = []
        self._live: tuple[np.ndarray, np.ndarray] | None = None
        # the transport state after the last Look, to spot a frozen crowd (see step); in the
        # mixed phase (someone informed, not everyone transporting) the whole state's key
        self._last_key: tuple | None = None
        self._mixed_keys: tuple[tuple | None, tuple | None] = (None, None)  # last, one before
        self._frozen = False
        self.stopped = False  # on_frame raised StopRun
        self.stalled: int | None = None  # the round limit was reached then: a locked team
        self.hooked = hooked  # every Compute is handed out (module docstring)

    # ------------------------------------------------------------------ prediction
    def on_route(self, a: int) -> bool:
        if self.timed is None or self.displaced[a]:
            return False
        return self.mode[a] in (EXPLORE, FOLLOW)

    def route_pos(self, a: int, t: int) -> Cell:
        assert self.timed is not None
        p = self.timed.at(t - self.delay[a])[a]
        return (int(p[0]), int(p[1]))

    def future(self, b: int, t: int) -> np.ndarray:
        """Predicted positions of robot ``b`` from time ``t`` on (it stays at the last one)."""
        if self.on_route(b):
            assert self.timed is not None
            i = max(0, t - self.delay[b])
            seg = self.timed.pos[min(i, self.timed.t_end) :, b]
            return seg if len(seg) else self.timed.pos[-1:, b]
        return np.asarray([self.pos[b]], dtype=np.int64)

    def expected(self, b: int) -> Cell:
        """Where ``b``'s pattern puts it now (the seed rule's prediction: its timetable shifted
        by the rounds it was held up, whatever it knows); without a timetable, its cell."""
        if self.timed is None:
            return self.pos[b]
        return predicted(self.timed.pos[:, b], self.timed.t_end, self.delay[b], self.t)

    def expected_future(self, b: int, t: int) -> np.ndarray:
        """``b``'s pattern positions from round ``t`` on (the seed rule's :meth:`future`)."""
        if self.timed is None:
            return np.asarray([self.pos[b]], dtype=np.int64)
        i = min(max(0, t - self.delay[b]), self.timed.t_end)
        return self.timed.pos[i:, b]

    def _t_end(self) -> int:
        """The timetable's last round (only robots that follow one ask)."""
        assert self.timed is not None
        return self.timed.t_end

    # ------------------------------------------------------------------ phases
    def inform(self, a: int, teller: int | None) -> None:
        self.informed[a] = True
        self.informed_at[a] = self.t
        todo = first_targets(
            self.comm, self.neighbours[a], teller, self.informed, self.one_way
        )
        self.targets[a] = todo
        if self.word is not None:
            self.word.learn(a, self.t, teller, todo)
        if not todo:
            self.enter_transport(a)
        elif self.keeps_route(a) and self.on_route(a):
            self.mode[a] = FOLLOW
        else:
            self.start_comm(a)

    def keeps_route(self, a: int) -> bool:
        """Whether informed robot ``a`` keeps to its route (:func:`.comm.keeps_route`); it is
        exploring once its timetable has passed the synchronised start."""
        if self.timed is None:
            return False
        exploring = self.t - self.delay[a] >= self.timed.t_sync
        return keeps_route(self.comm, self.timed.plan.algorithm, self.follow_comm, exploring,
                           self.n)

    def start_comm(self, a: int) -> None:
        self.mode[a] = COMM
        predict = self.future if self.comm == OMNISCIENT else self.expected_future
        self.targets[a], _ = best_order(self.pos[a], self.t, self.targets[a], predict)

    def enter_transport(self, a: int) -> None:
        self.mode[a] = TRANSPORT
        self.comm_done[a] = self.t
        if self.transport == END_TO_END:
            self.tmode[a] = E2E
            return
        self.tmode[a] = JOIN
        if self.transport == RELAY_FOOD:
            self.join_at[a] = len(self.path) - 1
        else:
            self.join_at[a] = entry_cell(self.path, self.pos[a])
        self.try_join(a)

    def try_join(self, a: int) -> None:
        if self.tmode[a] == JOIN and self.pos[a] == self.path[self.join_at[a]]:
            self.tmode[a] = RELAY
            self.pidx[a] = self.join_at[a]

    # ------------------------------------------------------------------ look
    def look(self) -> None:
        n, t = self.n, self.t
        for a in range(n):
            if not self.informed[a] and self.pos[a] == self.food:
                self.inform(a, None)
        # who tells an uninformed robot: the lowest-id informed robot at distance <= 1, found
        # through the cells (its own and the 4 neighbours) rather than by scanning every
        # informed robot, which cost O(n^2) per round with a large swarm
        at: dict[Cell, int] = {}
        for b in range(n):
            if self.informed[b]:
                at.setdefault(self.pos[b], b)  # ascending ids: the lowest one per cell
        new: list[tuple[int, int]] = []
        if at:
            for a in range(n):
                if self.informed[a]:
                    continue
                x, y = self.pos[a]
                tellers = [w for c in ((x, y), (x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1))
                           if (w := at.get(c)) is not None]
                if tellers:
                    new.append((a, min(tellers)))
        for a, b in new:
            self.inform(a, b)
        if self.word is not None:
            knowing = [a for a in range(n) if self.informed[a]]
            self.word.exchange(adjacent_pairs(self.pos, knowing))
        telling = [a for a in range(n) if self.mode[a] in (FOLLOW, COMM)]
        cross_off(
            self.comm, self.targets, self.informed, self.pos, self.expected, telling, self.word
        )
        for a in telling:
            if not self.targets[a]:
                self.enter_transport(a)
            elif self.mode[a] == FOLLOW and (
                self.displaced[a] or t - self.delay[a] >= self._t_end()
            ):
                self.start_comm(a)
        self.transport_look()

    def transport_look(self) -> None:
        t = self.t
        active = [a for a in range(self.n) if self.mode[a] == TRANSPORT]
        if self.transport != END_TO_END:
            for a in active:
                self.try_join(a)
            at = {self.pos[a]: a for a in active if self.tmode[a] == RELAY}
            was = list(self.carrying)
            busy: set[int] = set()
            for b in active:
                if self.tmode[b] != RELAY or not was[b] or self.pidx[b] < 2:
                    continue
                c = at.get(self.path[self.pidx[b] - 1])
                if c is None or was[c] or c in busy or b in busy:
                    continue
                self.carrying[c], self.carrying[b] = True, False
                self.handovers[b] += 1
                busy.update((c, b))
        for a in active:
            if self.tmode[a] not in (RELAY, E2E):
                continue
            if self.carrying[a] and self.pos[a] == self.nest:
                self.carrying[a] = False
                self.delivered += 1
                self.jobs[a].append((t, *self.nest, "drop"))
            elif not self.carrying[a] and self.pos[a] == self.food and self.units > 0:
                self.carrying[a] = True
                self.units -= 1
                self.jobs[a].append((t, *self.food, "pickup"))

    # ------------------------------------------------------------------ compute + move
    def options(self, a: int) -> tuple[list[Cell], bool]:
        """Ordered cells robot ``a`` would like to be in next, and whether it follows a route."""
        p = self.pos[a]
        m = self.mode[a]
        if m in (EXPLORE, FOLLOW) and self.on_route(a):
            nxt = self.route_pos(a, self.t + 1)
            if nxt != p:
                return [nxt, p], True
            if self.t + 1 - self.delay[a] > self.timed.t_end:  # type: ignore[union-attr]
                return [p, *sidesteps(p, self.g)], False
            return [p], True
        if m == EXPLORE:  # pushed off its route after finishing it
            return [p, *sidesteps(p, self.g)], False
        if m == COMM and self.comm == SEED:
            b = self.targets[a][0]
            if manhattan(p, self.pos[b]) <= 1:  # they exchange in the next Look
                return [p], False
            goal_c = meet_goal(p, self.pos[b], self.expected_future(b, self.t))
            if p == goal_c:
                return [p], False
            return [*toward(p, goal_c), p], False
        if m == COMM:
            b = self.targets[a][0]
            fut = self.future(b, self.t)
            tau = meet(p, fut)
            goal = fut[min(tau, len(fut) - 1)]
            goal_c = (int(goal[0]), int(goal[1]))
            if manhattan(p, self.pos[b]) <= 1 or p == goal_c:
                return [p], False
            return [*toward(p, goal_c), p], False
        # transport
        tm = self.tmode[a]
        if tm == E2E:
            if not self.carrying[a] and self.units == 0:
                return [p, *sidesteps(p, self.g)], False
            goal = self.nest if self.carrying[a] else self.food
            moves = toward(p, goal)
            if self._frozen and moves:  # break a frozen crowd: any free side will do
                moves += [c for c in sidesteps(p, self.g) if c not in moves]
            return [*moves, p], False
        if tm == JOIN:
            return [*toward(p, self.path[self.join_at[a]]), p], False
        if tm == RELAY:
            i = self.pidx[a]
            if self.carrying[a]:
                return ([self.path[i - 1], p] if i > 0 else [p]), False
            if i < len(self.path) - 1:
                return [self.path[i + 1], p], False
            if self.units == 0:
                self.tmode[a] = IDLE
                return [p, *sidesteps(p, self.g)], False
            return [p], False
        return [p, *sidesteps(p, self.g)], False

    def _exploring(self) -> bool:
        """Whether nobody knows the food yet (the phase :meth:`_hooked_explore` plays
        compiled; once someone is informed, someone stays so)."""
        return self.timed is not None and not any(self.informed)

    def transport_key(self) -> tuple | None:
        """Everything a transport round's moves depend on (None while anyone explores or
        communicates: their routes depend on the clock)."""
        if any(m != TRANSPORT for m in self.mode):
            return None
        return (
            tuple(self.pos),
            tuple(self.carrying),
            tuple(self.tmode),
            tuple(self.pidx),
            self.units,
            self.delivered,
        )

    def mixed_key(self) -> tuple | None:
        """Everything a round of the mixed phase depends on (someone is informed and not
        everyone transports; None otherwise), for the frozen-crowd rule of :meth:`step`.

        The clock enters a round only through ``t - delay[a]`` clamped to ``0 … t_end``
        (``route_pos``, ``expected``, ``expected_future``, ``future``, the end-of-route and
        ``keeps_route`` checks), so the key holds that *clock* per robot and not ``t``. A
        robot's list and the seed rule's word are summarised by counts: while no mode
        changes (modes only ever advance, so equal modes mean none changed in between) a list
        only loses names (cross-off) and a robot's set only gains them (exchange), so equal
        counts one or two rounds apart mean equal lists and sets; ranks and holders change
        only when someone learns (``informed`` differs then). ``informed_at``, ``comm_done``
        and the jobs are stamps no round reads back (a job comes with a change of load)."""
        if not any(self.informed) or all(m == TRANSPORT for m in self.mode):
            return None
        t_end = self.timed.t_end if self.timed is not None else 0
        clock = tuple(min(max(0, self.t - d), t_end) for d in self.delay)
        known = sum(k.bit_count() for k in self.word.know) if self.word is not None else 0
        relay = self.transport != END_TO_END
        joins = tuple(
            self.join_at.get(a, -1) if relay and self.mode[a] == TRANSPORT else -1
            for a in range(self.n)
        )
        return (
            tuple(self.pos),
            tuple(self.carrying),
            tuple(self.mode),
            tuple(self.tmode),
            tuple(self.pidx),
            joins,
            tuple(self.displaced),
            tuple(self.informed),
            clock,
            tuple(len(x) for x in self.targets),
            known,
            self.units,
            self.delivered,
        )

    def step(self) -> None:
        """One round's Compute and Move (after ``look``), the seed's decisions (a hooked
        run's rounds go through :meth:`hooked_step` instead).

        A crowd can freeze: End-to-End robots near the food that each want the next one's
        cell while a fourth takes one of those cells first all wait, and since a transport
        round depends only on this state, every later round would be the same. When the
        state after Look equals the previous round's, robots that want to move may also
        step to a free side cell for this round. Runs that never freeze (every run that
        completes without this rule) are unchanged.

        The same holds while some robots still explore or communicate (the *mixed* phase,
        30 Nov 2026), where a crowd at the food can block the nest's exits for robots that
        must leave to tell others. There the rule fires when :meth:`mixed_key` (the whole
        state a round depends on, with each robot's clock ``t - delay`` clamped to the
        timetable, which is all a round reads of the time) equals that of the previous round
        or of the round before it. It is exact: a round is a fixed function of that key
        (rounds do not read ``t`` otherwise), so a key that repeats after one or two rounds
        repeats for ever without the rule, delivering nothing more; the rule fires only in
        runs that would never finish, and at the first such round. Period 2 is the
        freeze plus two seed-rule messengers that chase each other across a diagonal (each
        steps to where the other was); positions and time are not enough (a seed-rule goal
        follows the target's timetable, which moves while everyone stands still, until the
        clamp), hence the key. As in the transport phase, only End-to-End robots that want
        to move take the side cells; messengers blocked in the nest need nothing more.
        """
        opts, following = self._compute()
        self._move(opts, following, opts, following)

    def hooked_step(self) -> Rounds:
        """:meth:`step` with the Compute handed out: yields a :class:`Compute` and takes every
        robot's move back (:mod:`.hook`)."""
        opts, following = self._compute()
        builtin = seed_moves(self.pos, opts)
        here = np.array(self.pos, dtype=np.int64).reshape(self.n, 2)
        moves = yield Compute(self, self.t, builtin, here)
        chosen, ranked = hooked_options(self.pos, opts, following, builtin, moves, self.g)
        self._move(opts, following, chosen, ranked)

    def _compute(self) -> tuple[list[list[Cell]], list[bool]]:
        """Every robot's ordered wishes and route-follower flag (the seed's Compute)."""
        key = self.transport_key()
        self._frozen = key is not None and key == self._last_key
        self._last_key = key
        mixed = None if key is not None else self.mixed_key()
        if mixed is not None:
            self._frozen = mixed in self._mixed_keys
            self._mixed_keys = (mixed, self._mixed_keys[0])
        else:
            self._mixed_keys = (None, None)
        n = self.n
        opts, following = [], []
        for a in range(n):
            o, f = self.options(a)
            opts.append(o)
            following.append(f)
        return opts, following

    def _move(
        self,
        opts: list[list[Cell]],
        following: list[bool],
        chosen: list[list[Cell]],
        ranked: list[bool],
    ) -> None:
        """Resolve the ``chosen`` wishes (``ranked``: route-follower ranks) collision-free and
        move; ``opts``/``following`` are the seed's, to tell waiting from leaving a route."""
        n = self.n
        new = resolve(self.pos, chosen, priority(self.pos, ranked, chosen), self.nest)
        for a in range(n):
            if self.on_route(a):
                want = opts[a][0]
                if new[a] != want and want != self.pos[a] and new[a] == self.pos[a]:
                    self.delay[a] += 1
                elif new[a] != self.pos[a] and (not following[a] or new[a] != want):
                    self.displaced[a] = True  # (new != want: only a hook's move does that)
            elif self.mode[a] == TRANSPORT and self.tmode[a] == RELAY:
                i = self.pidx[a]
                if new[a] != self.pos[a]:
                    j = self.path_index.get(new[a])
                    if j is not None and abs(j - i) == 1:
                        self.pidx[a] = j
                    elif self.hooked:  # a hook's move off the path: re-join it
                        self.tmode[a] = JOIN
                        self.join_at[a] = entry_cell(self.path, new[a])
                    else:
                        self.tmode[a] = IDLE
        self.pos = new
        self.t += 1

    def frame(self) -> Frame:
        """The current state (after this round's Look) as a :class:`Frame`."""
        return Frame(
            self.t,
            np.asarray(self.pos, dtype=np.int64).reshape(self.n, 2),
            np.asarray(self.carrying, dtype=bool),
            np.asarray(self.informed, dtype=bool),
            self.delivered,
            self.units,
        )

    def run(
        self,
        record: bool = True,
        limit: int | None = None,
        fast: bool = True,
        on_frame: FrameSink | None = None,
        decide: Decide | None = None,
    ) -> None:
        """Play rounds until all k units are home (:meth:`rounds`), answering a hooked run's
        Computes with ``decide``."""
        drive(self.rounds(record, limit, fast, on_frame), decide)

    def rounds(
        self,
        record: bool = True,
        limit: int | None = None,
        fast: bool = True,
        on_frame: FrameSink | None = None,
        stop_at: int | None = None,
    ) -> Rounds:
        """Play rounds until all k units are home; ``fast`` hands rounds to the compiled
        loops of :mod:`.fastloop` (same rules, same result): a plain run's communication
        phase to :meth:`_comm_phase` and its pure-transport tail to :meth:`_tail`; for a
        hooked run without ``on_frame`` the tail to :meth:`_hooked_tail` and the rounds
        before anyone is informed to :meth:`_hooked_explore`. ``on_frame`` gets each
        round's :class:`Frame`; if it raises StopRun the run stops there (``self.stopped``),
        and so it does at round ``stop_at`` (the same stop without a frame per round). A
        generator: a hooked run yields each Compute (module docstring); any other never
        yields."""
        limit = limit or round_limit(self.t, self.g, self.k)
        if fast and not self.hooked and stop_at is None and self._fresh():
            self._comm_phase(record, limit, on_frame)
            if self.stopped or self.stalled is not None or self.delivered >= self.k:
                return
        while True:
            if fast and all(m == TRANSPORT for m in self.mode):
                if not self.hooked:
                    self._tail(record, limit, on_frame)
                    return
                if on_frame is None:
                    yield from self._hooked_tail(record, limit, stop_at)
                    return
            if fast and self.hooked and on_frame is None and self._exploring():
                ended = yield from self._hooked_explore(record, limit, stop_at)
                if ended:  # stopped there; else a robot stands on the food: its Look follows
                    return
            self.look()
            if record:
                self.history.append(list(self.pos))
            if on_frame is not None:
                try:
                    on_frame(self.frame())
                except StopRun:
                    self.stopped = True
                    return
            if stop_at is not None and self.t >= stop_at:
                self.stopped = True
                return
            if self.delivered >= self.k:
                return
            if self.t >= limit:
                self.stalled = self.t
                return
            if self.hooked:
                yield from self.hooked_step()
            else:
                self.step()

    # ------------------------------------------------------------------ compiled plain rounds
    def _fresh(self) -> bool:
        """Whether this is a plain run at its discovery round: it follows a timetable and
        nobody knows the food yet (where :meth:`_comm_phase` starts)."""
        return self.timed is not None and not any(self.informed)

    def _comm_phase(self, record: bool, limit: int, on_frame: FrameSink | None = None) -> None:
        """A plain run's rounds from the discovery until every robot transports (or the run
        ends), in the compiled :func:`~.fastloop.comm_rounds`: the same rounds as this
        loop's :meth:`look` and :meth:`step`, much faster with many robots. The rows go to
        ``tail_chunks`` (``history`` stays empty); afterwards this Mission's lists (and the
        seed rule's word) are the run's state, as the Python rounds would have left them, and
        :meth:`rounds` goes on with the compiled transport tail. With ``on_frame`` the kernel
        plays one round per call and stops after its Look (the Compute and Move wait for the
        next call), so each :class:`Frame` and a StopRun's state are this loop's."""
        from swarmex.missions.foraging import fastloop as fl

        assert self.timed is not None and not any(self.informed)
        n, plan = self.n, self.timed.plan
        a = self._comm_arrays(limit)
        path, path_of = self._path_arrays
        flags = np.asarray(
            [self.comm == OMNISCIENT, self.one_way,
             keeps_route(self.comm, plan.algorithm, self.follow_comm, True, n),
             keeps_route(self.comm, plan.algorithm, self.follow_comm, False, n),
             self.transport == RELAY_FOOD, self.timed.t_sync],
            dtype=np.int64,
        )  # fmt: skip
        route = np.ascontiguousarray(self.timed.pos, dtype=np.int32)
        nest = np.asarray(self.nest, dtype=np.int64)
        food = np.asarray(self.food, dtype=np.int64)
        size = 1 if on_frame else max(16, min(4096, (1 << 21) // n))  # 16 MB of int32 at most
        chunk = np.empty((size, n, 2), dtype=np.int32)
        state = a["state"]
        while True:
            rows = fl.comm_rounds(
                a["pos"], a["mode"], a["delay"], a["displaced"], a["informed_at"],
                a["targets"], a["ntarg"], a["know"], a["hold_head"], a["hold_next"],
                a["hold_who"], a["hold_of"], a["comm_done"], a["carrying"], a["tmode"],
                a["pidx"], a["join_at"], a["handovers"], state, flags,
                self.transport != END_TO_END, a["nb_start"], a["nb_flat"], path, path_of,
                route, self.timed.t_end, nest, food, a["jobs"], a["memo"], a["mixed"], chunk,
                self._cells,
            )  # fmt: skip
            if record:
                self.tail_chunks.append(chunk[:rows].copy())
            if on_frame is not None and rows:
                frame = Frame(
                    int(state[0]), chunk[0].astype(np.int64), a["carrying"].copy(),
                    a["informed_at"] >= 0, int(state[2]), int(state[1]),
                )  # fmt: skip
                try:
                    on_frame(frame)
                except StopRun:
                    self.stopped = True
                    break
            if state[6] != fl.GOING:
                break
        self._take_comm_arrays(a)
        if state[6] == fl.STALLED and not self.stopped:
            self.stalled = self.t

    def _comm_arrays(self, limit: int) -> dict[str, np.ndarray]:
        """:func:`~.fastloop.comm_rounds`' state arrays at the discovery (nobody informed):
        a robot's list is a row of ``targets`` (as wide as the longest neighbour list, the
        most it can hold), its neighbours ``nb_flat[nb_start[a]:nb_start[a + 1]]``."""
        from swarmex.missions.foraging import fastloop as fl

        n = self.n
        lengths = [len(nb) for nb in self.neighbours]
        nb_start = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(lengths, out=nb_start[1:])
        holds = max(1, int(nb_start[-1]))  # a robot lists each neighbour once at most
        return {
            "pos": np.asarray(self.pos, dtype=np.int64).reshape(n, 2),
            "mode": np.asarray(self.mode, dtype=np.int64),
            "delay": np.asarray(self.delay, dtype=np.int64),
            "displaced": np.asarray(self.displaced, dtype=np.bool_),
            "informed_at": np.full(n, -1, dtype=np.int64),
            "comm_done": np.full(n, -1, dtype=np.int64),
            "targets": np.zeros((n, max([1, *lengths])), dtype=np.int64),
            "ntarg": np.zeros(n, dtype=np.int64),
            "nb_start": nb_start,
            "nb_flat": np.asarray([b for nb in self.neighbours for b in nb] or [0], np.int64),
            "know": np.zeros((n, (n + 63) // 64), dtype=np.uint64),
            "hold_head": np.full(n, -1, dtype=np.int64),
            "hold_next": np.zeros(holds, dtype=np.int64),
            "hold_who": np.zeros(holds, dtype=np.int64),
            "hold_of": np.zeros(holds, dtype=np.int64),
            "carrying": np.zeros(n, dtype=np.bool_),
            "tmode": np.full(n, fl.NOT_YET, dtype=np.int64),
            "pidx": np.full(n, -1, dtype=np.int64),
            "join_at": np.zeros(n, dtype=np.int64),
            "handovers": np.zeros(n, dtype=np.int64),
            "jobs": np.zeros((2 * self.k + 2, 3), dtype=np.int64),
            "memo": fl.transport_memo(self._last_key, n),
            "mixed": fl.mixed_memo(n),
            "state": np.asarray(
                [self.t, self.units, self.delivered, self.k, 0, 0, 0, limit, 0, 0], np.int64
            ),
        }

    def _take_comm_arrays(self, a: dict[str, np.ndarray]) -> None:
        """This Mission's lists from :func:`~.fastloop.comm_rounds`' arrays (the inverse of
        :meth:`_comm_arrays`)."""
        from swarmex.missions.foraging import fastloop as fl

        state = a["state"]
        self.t, self.units, self.delivered = state[:3].tolist()
        self.pos = [(x, y) for x, y in a["pos"].tolist()]
        self.mode = a["mode"].tolist()
        self.delay = a["delay"].tolist()
        self.displaced = a["displaced"].tolist()
        told = a["informed_at"].tolist()
        self.informed = [t >= 0 for t in told]
        self.informed_at = [t if t >= 0 else None for t in told]
        self.comm_done = [t if t >= 0 else None for t in a["comm_done"].tolist()]
        lists = zip(a["targets"].tolist(), a["ntarg"].tolist(), strict=True)
        self.targets = [row[:k] for row, k in lists]
        self.carrying = a["carrying"].tolist()
        self.tmode = [JOIN if m == fl.NOT_YET else m for m in a["tmode"].tolist()]
        self.pidx = a["pidx"].tolist()
        self.handovers = a["handovers"].tolist()
        if self.transport != END_TO_END:
            joined = enumerate(a["join_at"].tolist())
            self.join_at = {r: j for r, j in joined if self.mode[r] == TRANSPORT}
        for t, r, kind in a["jobs"][: state[4]].tolist():
            cell = self.nest if kind == 1 else self.food
            self.jobs[r].append((t, *cell, "drop" if kind == 1 else "pickup"))
        if self.word is not None:
            used = int(state[fl.C_HOLDS])
            self._word_from(a["know"], a["hold_who"][:used], a["hold_of"][:used])
        self._last_key = fl.memo_key(a["memo"], self.n)

    def _word_from(self, know: np.ndarray, who: np.ndarray, of: np.ndarray) -> None:
        """The seed rule's :class:`~.comm.Word` from :func:`~.fastloop.comm_rounds`' arrays:
        bit sets to ints, ranks from ``informed_at``, holders in the order listed."""
        assert self.word is not None
        for a in range(self.n):
            self.word.know[a] = int.from_bytes(know[a].astype("<u8").tobytes(), "little")
            t = self.informed_at[a]
            self.word.rank[a] = None if t is None else (t, a)
        for a, b in zip(who.tolist(), of.tolist(), strict=True):
            self.word.holders[b].append(a)

    # ------------------------------------------------------------------ compiled hooked rounds
    @cached_property
    def _path_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The relay path's cells and the g x g index of them (-1: off the path), for the
        compiled rounds (they only read them), made once per run."""
        path = np.asarray(self.path, dtype=np.int64)
        path_of = np.full((self.g, self.g), -1, dtype=np.int64)
        path_of[path[:, 0], path[:, 1]] = np.arange(len(path))
        return path, path_of

    @cached_property
    def _cells(self) -> np.ndarray:
        """The compiled rounds' g x g cell index (robot per cell, -1: none; all -1 between
        kernel calls), made once per run."""
        return np.full((self.g, self.g), -1, dtype=np.int64)

    def _compiled_rows(self, record: bool, state: np.ndarray) -> np.ndarray:
        """Start a compiled phase of a hooked run: the rows played so far in Python go to
        ``segments`` (the trajectory stays in round order), and a chunk is opened for the
        compiled rounds' positions (``state[ROW]`` its next row)."""
        if self.history:
            self.segments.append(np.asarray(self.history, dtype=np.int32).reshape(-1, self.n, 2))
            self.history = []
        chunk = np.empty((4096 if record else 1, self.n, 2), dtype=np.int32)
        self._live = (chunk, state)
        return chunk

    def _full_chunk(self, record: bool, chunk: np.ndarray, state: np.ndarray) -> np.ndarray:
        """After a compiled round: a full chunk is kept (when recording) and a new one
        opened; returns the chunk to write to."""
        if state[5] < len(chunk):  # fastloop.ROW: the next row to write
            return chunk
        state[5] = 0
        if not record:
            return chunk
        self.segments.append(chunk)
        chunk = np.empty_like(chunk)
        self._live = (chunk, state)
        return chunk

    def _close_rows(self, record: bool) -> None:
        """End a compiled phase that hands the run back to the Python loop."""
        if self._live is not None:
            chunk, state = self._live
            if record:
                self.segments.append(chunk[: int(state[5])])
            self._live = None

    def _bad_move(self, a: int, moves: np.ndarray) -> ValueError:
        """:func:`~.hook.hooked_options`'s error for robot ``a``'s move."""
        m, p = int(moves[a]), self.pos[a]
        if not 0 <= m < 5:
            return ValueError(f"robot {a}: move {m} is not a move code (0..4)")
        return ValueError(f"robot {a}: move {m} from {p} leaves the {self.g}×{self.g} grid")

    def _state(self, limit: int, stop_at: int | None) -> np.ndarray:
        """The compiled rounds' state vector (:data:`~.fastloop.T` … ``MOVED``)."""
        never = np.iinfo(np.int64).max
        return np.asarray(
            [self.t, self.units, self.delivered, self.k, 0, 0,
             never if stop_at is None else stop_at, limit, 0],
            dtype=np.int64,
        )  # fmt: skip

    def _hooked_explore(
        self, record: bool, limit: int, stop_at: int | None
    ) -> Generator[Compute, np.ndarray, bool]:
        """The rounds of a hooked run before anyone knows where the food is, in the compiled
        :func:`~.fastloop.explore_round` (one call per round: the pending Move with the
        caller's moves, then the next Look and Compute). In that phase the Look is empty
        (nobody is informed, so nobody tells, crosses off or transports) until a robot
        stands on the food; then the kernel stops after the Move and this returns False: the
        Python loop plays that Look (the finder learns, :mod:`.comm`'s rules start) and the
        rounds after. Returns True when the run ended here (stopped or stalled). After each
        round ``pos``, ``delay``, ``displaced`` and ``t`` are brought up to date."""
        from swarmex.missions.foraging import fastloop as fl

        assert self.timed is not None
        n, g = self.n, self.g
        pos = np.asarray(self.pos, dtype=np.int64).reshape(n, 2)
        delay = np.asarray(self.delay, dtype=np.int64)
        displaced = np.asarray(self.displaced, dtype=np.bool_)
        route = np.ascontiguousarray(self.timed.pos, dtype=np.int32)
        nest = np.asarray(self.nest, dtype=np.int64)
        food = np.asarray(self.food, dtype=np.int64)
        state = self._state(limit, stop_at)
        opts = np.empty((n, fl.MAXOPT, 2), dtype=np.int64)
        nopt = np.zeros(n, dtype=np.int64)
        following = np.zeros(n, dtype=np.bool_)
        builtin = np.zeros(n, dtype=np.int64)
        moves = np.zeros(n, dtype=np.int64)
        chunk = self._compiled_rows(record, state)
        t_end = self.timed.t_end
        while True:
            status = fl.explore_round(
                pos, delay, displaced, state, route, t_end, g, nest, food, opts, nopt,
                following, builtin, moves, chunk, self._cells,
            )  # fmt: skip
            if status < 0:
                raise self._bad_move(-status - 1, moves)
            self.t = int(state[fl.T])
            xs, ys = pos.T.tolist()
            self.pos = list(zip(xs, ys, strict=True))
            self.delay = delay.tolist()
            self.displaced = displaced.tolist()
            chunk = self._full_chunk(record, chunk, state)
            if status == fl.HANDOFF:
                self._close_rows(record)
                return False
            if status == fl.STOPPED:
                self.stopped = True
                return True
            if status == fl.STALLED:
                self.stalled = self.t
                return True
            answer = yield Compute(self, self.t, builtin.copy(), pos.copy())
            moves[:] = answer
            state[fl.MOVED] = 1

    def _hooked_tail(self, record: bool, limit: int, stop_at: int | None) -> Rounds:
        """The rounds of a hooked run once every robot transports, in the compiled
        :func:`~.fastloop.hooked_round` (one call per round: the pending Move with the
        caller's moves, then the next Look and Compute). The Transportation phase is
        absorbing and every robot is informed, so no one learns, tells or crosses off any
        more: what remains is the arrays' rounds, the same as :meth:`hooked_step`'s. After
        each round the lists of this Mission (``pos``, ``carrying``, ``tmode``, ``pidx``,
        ``join_at``, ``handovers``, ``jobs``, the counts) are brought up to date, so it stays
        the run's state for every reader; the positions after each Look go to
        ``segments`` (:meth:`trajectory`)."""
        from swarmex.missions.foraging import fastloop as fl

        n = self.n
        pos = np.asarray(self.pos, dtype=np.int64).reshape(n, 2)
        carrying = np.asarray(self.carrying, dtype=np.bool_)
        tmode = np.asarray(self.tmode, dtype=np.int64)
        pidx = np.asarray(self.pidx, dtype=np.int64)
        join_at = np.asarray([self.join_at.get(a, 0) for a in range(n)], dtype=np.int64)
        handovers = np.asarray(self.handovers, dtype=np.int64)
        path, path_of = self._path_arrays
        nest = np.asarray(self.nest, dtype=np.int64)
        food = np.asarray(self.food, dtype=np.int64)
        relay = self.transport != END_TO_END
        state = self._state(limit, stop_at)
        jobs = np.zeros((2 * self.k + 2, 3), dtype=np.int64)
        opts = np.empty((n, fl.MAXOPT, 2), dtype=np.int64)
        nopt = np.zeros(n, dtype=np.int64)
        builtin = np.zeros(n, dtype=np.int64)
        moves = np.zeros(n, dtype=np.int64)
        memo = fl.transport_memo(self._last_key, n)
        chunk = self._compiled_rows(record, state)
        synced = 0  # jobs already copied to self.jobs
        while True:
            status = fl.hooked_round(
                pos, carrying, tmode, pidx, join_at, handovers, state, path, path_of, nest,
                food, relay, opts, nopt, builtin, moves, chunk, jobs, memo, self._cells,
            )  # fmt: skip
            if status < 0:
                raise self._bad_move(-status - 1, moves)
            self.t, self.units, self.delivered = state[:3].tolist()
            xs, ys = pos.T.tolist()
            self.pos = list(zip(xs, ys, strict=True))
            self.carrying = carrying.tolist()
            self.tmode = tmode.tolist()
            self.pidx = pidx.tolist()
            self.handovers = handovers.tolist()
            if relay:
                self.join_at = dict(enumerate(join_at.tolist()))
            if state[fl.N_JOBS] > synced:
                for t, a, kind in jobs[synced : state[fl.N_JOBS]].tolist():
                    cell = self.nest if kind == 1 else self.food
                    self.jobs[a].append((t, *cell, "drop" if kind == 1 else "pickup"))
                synced = int(state[fl.N_JOBS])
            chunk = self._full_chunk(record, chunk, state)
            if status == fl.STOPPED:
                self.stopped = True
            if status == fl.STALLED:
                self.stalled = self.t
            if status != fl.GOING:
                return
            answer = yield Compute(self, self.t, builtin.copy(), pos.copy())
            moves[:] = answer
            state[fl.MOVED] = 1

    def trajectory(self) -> np.ndarray:
        """(rounds, n, 2) int32: a hooked run's robot cells after each Look so far, in round
        order (``segments``: the compiled phases' rows and the Python rows before them; the
        open chunk; ``history``: the Python rows since)."""
        parts = list(self.segments)
        if self._live is not None:
            chunk, state = self._live
            parts.append(chunk[: int(state[5])])
        if self.history:
            parts.append(np.asarray(self.history, dtype=np.int32).reshape(-1, self.n, 2))
        if not parts:
            return np.empty((0, self.n, 2), dtype=np.int32)
        return np.concatenate(parts, axis=0)

    def _tail(self, record: bool, limit: int, on_frame: FrameSink | None = None) -> None:
        """The pure-transport rounds in the compiled loop; with ``on_frame``, one round per
        call (the loop's state lives in the arrays, so the rounds are the same)."""
        from swarmex.missions.foraging.fastloop import transport_memo, transport_tail

        n = self.n
        pos = np.asarray(self.pos, dtype=np.int64)
        carrying = np.asarray(self.carrying, dtype=np.bool_)
        tmode = np.asarray(self.tmode, dtype=np.int64)
        pidx = np.asarray(self.pidx, dtype=np.int64)
        join_at = np.asarray([self.join_at.get(a, 0) for a in range(n)], dtype=np.int64)
        path, path_of = self._path_arrays
        state = np.asarray([self.t, self.units, self.delivered, self.k, 0, 0, 0], np.int64)
        jobs = np.zeros((2 * self.k + 2, 3), dtype=np.int64)
        handovers = np.asarray(self.handovers, dtype=np.int64)
        nest = np.asarray(self.nest, dtype=np.int64)
        food = np.asarray(self.food, dtype=np.int64)
        relay = self.transport != END_TO_END
        chunk = np.empty((1 if on_frame else 4096, n, 2), dtype=np.int64)
        memo = transport_memo(self._last_key, n)
        informed = np.asarray(self.informed, dtype=bool)
        while True:
            t = int(state[0])
            # not past the limit: the last row is the Look of round ``limit``, where the Python
            # loop stops a locked run (the kernel has made that round's Move as well: undone
            # below; a locked team delivers nothing, so no job or count comes from it)
            block = chunk[: max(1, min(len(chunk), limit - t + 1))]
            rows = transport_tail(
                pos, carrying, tmode, pidx, join_at, state, path, path_of, nest, food, relay,
                block, jobs, handovers, memo, self._cells,
            )  # fmt: skip
            if record:
                self.tail_chunks.append(block[:rows].astype(np.int32))
            if on_frame is not None:
                # the round's Look is done (carrying, counts); its Move too unless it was the last
                frame = Frame(
                    t, chunk[0].copy(), carrying.copy(), informed.copy(), int(state[2]),
                    int(state[1]),
                )  # fmt: skip
                try:
                    on_frame(frame)
                except StopRun:
                    self.stopped = True
                    state[0] = t
                    pos[:] = chunk[0]
                    break
            if state[6]:
                break
            if state[0] > limit:
                self.stalled = limit
                state[0] = limit
                pos[:] = block[rows - 1]
                break
        self.t, self.units, self.delivered = int(state[0]), int(state[1]), int(state[2])
        self.pos = [(int(x), int(y)) for x, y in pos]
        self.carrying = [bool(c) for c in carrying]
        self.tmode = [int(m) for m in tmode]
        self.pidx = [int(i) for i in pidx]
        self.handovers = [int(h) for h in handovers]
        for t, a, kind in jobs[: state[4]].tolist():
            cell = self.nest if kind == 1 else self.food
            self.jobs[a].append((t, *cell, "drop" if kind == 1 else "pickup"))


def run_mission(
    timed: Timed,
    food: Cell,
    units: int,
    transport: str,
    record: bool = True,
    fast: bool = True,
    on_frame: FrameSink | None = None,
    decide: Decide | None = None,
    comm: str = SEED,
) -> Outcome:
    """Play one foraging run of the pattern in ``timed`` with food at ``food`` under the
    communication rule ``comm`` (:mod:`.comm`); ``on_frame`` gets every round's
    :class:`Frame`, ``decide`` every round's Compute (module docstring)."""
    if transport not in (RELAY_FOOD, RELAY_PATH, END_TO_END):
        raise ValueError(transport)
    if decide is not None:
        return drive(
            decided_rounds(timed, food, units, transport, record, on_frame, comm), decide
        )
    plan = timed.plan
    pos = timed.pos
    hit = (pos[:, :, 0] == food[0]) & (pos[:, :, 1] == food[1])
    rows = np.flatnonzero(hit.any(axis=1))
    if not len(rows):  # pragma: no cover - every pattern covers the grid
        raise RuntimeError(f"{plan.algorithm} never visits {food}")
    t0 = int(rows[0])
    if on_frame is not None:
        stopped = _timetable_frames(timed, t0, units, on_frame)
        if stopped is not None:
            return _stopped_before_discovery(timed, stopped, units, record)
    start = [(int(x), int(y)) for x, y in pos[t0]]
    m = Mission(plan.g, plan.nest, food, units, transport, start, t=t0, timed=timed, comm=comm)
    m.run(record=record, fast=fast, on_frame=on_frame)
    if record:
        parts = [pos[:t0]]
        if m.history:
            parts.append(np.asarray(m.history, dtype=np.int32).reshape(-1, plan.n, 2))
        positions = np.concatenate(parts + m.tail_chunks, axis=0)
    else:
        positions = np.empty((0, plan.n, 2), dtype=np.int32)
    finders = [a for a in range(plan.n) if m.informed_at[a] == t0 and start[a] == food]
    return _outcome(m, positions, t0, finders, units)


def _outcome(
    m: Mission, positions: np.ndarray, discovery: int | None, finders: list[int], units: int
) -> Outcome:
    """The Outcome of a finished Mission ``m`` (positions, discovery and finders given)."""
    return Outcome(
        positions=positions,
        jobs=m.jobs,
        handovers=m.handovers,
        discovery=discovery,
        finders=finders,
        informed_at=m.informed_at,
        comm_done=m.comm_done,
        makespan=m.t,
        delivered=m.delivered,
        complete=m.delivered >= units,
        extra={"stopped": True} if m.stopped else {"stalled": m.stalled} if m.stalled else {},
    )


def decided_rounds(
    timed: Timed,
    food: Cell,
    units: int,
    transport: str,
    record: bool = True,
    on_frame: FrameSink | None = None,
    comm: str = SEED,
    fast: bool = True,
    stop_at: int | None = None,
) -> Generator[Compute, np.ndarray, Outcome]:
    """A hooked run (module docstring): this loop from round 0, every Compute yielded; the
    generator's value is the Outcome. ``stop_at`` stops it at that round as an ``on_frame``
    raising StopRun there would; ``fast`` plays the Transportation phase's rounds compiled
    (:meth:`Mission._hooked_tail`, when there is no ``on_frame``)."""
    if transport not in (RELAY_FOOD, RELAY_PATH, END_TO_END):
        raise ValueError(transport)
    plan = timed.plan
    start = [plan.nest] * plan.n
    m = Mission(
        plan.g, plan.nest, food, units, transport, start, timed=timed, hooked=True, comm=comm
    )
    yield from m.rounds(record=True, fast=fast, on_frame=on_frame, stop_at=stop_at)
    history = m.trajectory()
    told = [t for t in m.informed_at if t is not None]
    discovery = min(told) if told else None
    finders = [
        a
        for a in range(plan.n)
        if discovery is not None
        and m.informed_at[a] == discovery
        and tuple(history[discovery, a]) == food
    ]
    positions = history if record else np.empty((0, plan.n, 2), dtype=np.int32)
    return _outcome(m, positions, discovery, finders, units)


def _timetable_frames(timed: Timed, t0: int, units: int, on_frame: FrameSink) -> int | None:
    """Frames of the rounds before the discovery (the timetable); the round at which
    ``on_frame`` raised StopRun, or None."""
    n = timed.plan.n
    nobody = np.zeros(n, dtype=bool)
    for t in range(t0):
        try:
            on_frame(
                Frame(t, timed.pos[t].astype(np.int64), nobody.copy(), nobody.copy(), 0, units)
            )
        except StopRun:
            return t
    return None


def _stopped_before_discovery(timed: Timed, t: int, units: int, record: bool) -> Outcome:
    n = timed.plan.n
    if record:
        positions = np.asarray(timed.pos[: t + 1], dtype=np.int32)
    else:
        positions = np.empty((0, n, 2), dtype=np.int32)
    return Outcome(
        positions=positions,
        jobs=[[] for _ in range(n)],
        handovers=[0] * n,
        discovery=None,
        finders=[],
        informed_at=[None] * n,
        comm_done=[None] * n,
        makespan=t,
        delivered=0,
        complete=False,
        extra={"stopped": True},
    )
