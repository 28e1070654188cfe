"""``madgta-r``: rollout (one-step policy improvement) over MADGTA.

Idea
----
Bertsekas' rollout: at a decision, take MADGTA's best few candidates (its utility order,
``k`` of them), simulate the rest of the mission for each on the agent's own belief with
every agent, the deciding one included after its first step, following MADGTA, and take the
candidate whose simulated mission ends best. A rollout policy is never worse than its base
heuristic *when the simulation is exact*; here it is not (rivals break MADGTA's ties at
random, unknown cells are taken as free, and the rivals roll out too), so the gain has to
be measured:

* 32 gap instances, identical agents: sum gap to the optimum 2.48 -> 1.38 %, makespan gap
  3.26 -> 1.27 % (issue 17's targets: 1.5 % and 2 %, both met); mixed agents 15.95 ->
  14.58 % and 4.76 -> 2.89 %.
* Five MovingAI maps, 16 identical agents: makespan -1.20 % ± 0.48 % (issue 17's target:
  -3 %), lower on every map (the interval excludes zero on four of the five, not on
  room-32-32-4), -4.1 % on empty-16-16.

The simulation
--------------
The compiled simulation (:func:`~swarmex.missions.traversal.rollout_sim._simulate`: its
state from the belief, MADGTA in it, distances without a field per move, the objective of
a simulated mission) is described in :mod:`~swarmex.missions.traversal.rollout_sim`; this
module is the policy around it.

Choices, and why
----------------
Measured on the 32 gap instances (identical agents, 5 seeds) and on five MovingAI maps with
16 identical agents (8 seeds, both nest modes); docs/traversal-variants.md §4 has the tables.

* **Only the end game** (``max_vacant=200``): the rollout runs when at most ``max_vacant``
  vacant vertices are left in the belief; before that the agent is MADGTA, bit for bit (the
  same draws from the generator). The waste MADGTA leaves piles up in the end game (40-50 %
  of the moves without a job fall in the last tenth of the jobs), and rolling out earlier
  was no better: 400 gives -1.32 % makespan on the real maps against -1.16 %, within
  noise, at 2.4x the CPU. Rolling out from the start (``None``; random-32-32-20 and
  room-32-32-4, 4 runs each) gave +1.2 % and -0.4 % at 9-12 s of CPU per run; with a
  horizon of 200 or 600 simulated decisions, +0.4 % and -0.9 % / +0.3 % and -2.4 % at
  4-11 s: a long simulation is too far from what the rivals really do. On the gap
  instances (at most 16 vertices) it always runs.
* **Branch 3 candidates are targets**, not next hops: the simulated agent keeps going to
  its candidate target (re-deciding once it gets there or the target is taken), so the
  rollout compares *where* to go; two targets behind the same hop would otherwise tie.
* **k = 4.** Branch 2 rarely has more than 4 vacant neighbours; k = 6 or 8 changed nothing
  measurable.
* **A makespan within one edge of the best, then the least sum** (``objective="lex"``,
  the default since 27 Nov 2026; before, ``"makespan"``: the least makespan, ties by the
  sum). Candidates' simulated makespans often differ by one edge only (a last hop of one
  agent), which the real mission does not reproduce; the sum then decides better. Gap
  instances, identical agents: sum / makespan gap 1.38 / 1.27 % against 1.86 / 1.53 %;
  mixed 14.58 / 2.89 % against 14.63 / 2.76 % (noise); real maps -1.20 % ± 0.48 % against
  -1.16 % ± 0.46 % (sum -1.15 % against -1.03 %). The tolerance: 0, 1e-6 or 0.1 s give
  ``"makespan"``'s runs exactly; 0.5 s (one edge of these identical agents) to 5 s all give
  1.38 / 1.27 % with identical agents, but with mixed agents a job and an edge (the first
  try) or 2 s raise the makespan gap to 4.14 %, and one edge of the deciding agent gives
  14.99 / 3.46 %; one edge of the fastest agent is the setting that is at most noise away
  from ``"makespan"`` on the mixed rows. ``objective="mix"`` (makespan + sum / agents)
  gave 1.80 / 1.73 % (identical), not significant.
* **MADGTA is kept when nothing is better**: among candidates whose simulated objective is
  equal, MADGTA's own order decides, then the generator as MADGTA draws.
* **Unknown cells are free.** Guessing the unsensed walls (``samples``: each not yet sensed
  cell a wall with the density of walls among the sensed ones, averaged over seeded
  guesses) did not help: identical agents, sum / makespan gap 2.04 / 2.07 % with 4 guesses,
  1.95 / 2.07 % with 16, against 1.86 / 1.53 %. Nor did a deterministic guess
  (``unknown="walled"``: every unsensed cell next to a known wall is a wall, as walls come
  in runs): 2.10 / 1.86 % with ``"makespan"``, 1.96 / 2.05 % with ``"lex"``. With
  ``"makespan"`` and 4 tie orders it gives 1.43 / 0.87 %, within both targets too, but
  the mixed makespan gap rises to 3.67 %, at 4x the cost. Information does matter to the rollout
  itself: with the whole map known from the start its gaps are 1.27 / 0.65 % and its real-map
  gain -1.99 % against -1.16 % (MADGTA's own gaps do not move: 2.48 / 3.26 % either way).
* **Ties go to the lowest id**, not to several random orders (``ties``): 4 seeded orders gave
  1.68 / 1.10 % on the gap instances, 16 gave 1.84 / 1.42 %: noise, at 4-16x the cost
  (with ``"makespan"``). With ``"lex"``, 4 orders give 1.63-1.77 / 1.37-1.56 %: worse.
* **Rivals simulated as MADGTA**, not as rollout agents (``nest``: each rival rolls out
  its first simulated decision with :func:`_simulate`, one level of nesting, against the
  "rivals follow MADGTA" mismatch). Gap instances, identical agents: 1.99 / 2.00 % with
  ``"lex"``, 2.05 / 1.81 % with ``"makespan"``, worse than without; mixed agents better,
  13.77 / 2.29 % against 14.58 / 2.89 % (``"lex"``), within the intervals. Real maps not
  measured (it costs about agents × ``k`` times more per rollout decision); kept as an
  option.
* **Not tried (yet):** a detour penalty for unknown cells (it needs weighted distances
  instead of hop rows).
* **Distant targets as well as neighbours** (``far``): -3.9 % on empty-16-16 as without
  them, -1.18 % pooled, within noise of the default at 1.2-1.5x the CPU; not kept.
* **MADGTA outside the rollout**, not madgta+ (``outside="madgta+"``): -1.49 % ± 0.52 %
  pooled against -1.16 % ± 0.46 %, within noise, but +0.02 % on the warehouse, where the
  default's interval excludes zero (-0.23 % ± 0.16 %).
* **Only reachable vacant vertices count**, towards ``max_vacant`` and in the simulation:
  unknown cells count as free, so a walled-in cell would stay "vacant" for ever. On a map
  whose outer wall nobody has sensed all along (ost003d with a shared nest), the unknown
  cells beyond it stay reachable in the belief until the very end, the count never drops
  to ``max_vacant``, and the agent stays MADGTA.
* **Graphs with one edge length only** (hop counts); elsewhere the policy is MADGTA.

Cost
----
Per rollout decision: one hop row per vacant vertex not yet cached (a breadth-first search,
O(n)), then ``k`` simulations of O(events × (vacant + agents) × agents). CPU per run with 16
agents: 0.19 s on empty-16-16, 0.7 s on random-32-32-20, 1.1 s on room-32-32-4, 2.0 s on
random-64-64-20, 3.4 s on warehouse-10-20-10-2-1 (MADGTA: 0.03-0.7 s, madgta+ 0.07-2.4 s);
1-2 ms on the gap instances. No message is added: everything comes from the belief.
"""

from __future__ import annotations

import itertools

import numpy as np

from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.missions.traversal.policies import POLICIES, Decision, Madgta, _pick
from swarmex.missions.traversal.rollout_sim import (
    ABSENT,
    FAR,
    FINISH,
    FREE,
    JOB,
    MOVING,
    NEAR,
    WORKING,
    _far_scan,
    _fill_rows,
    _options,
    _Rows,
    _simulate,
    _simulate_nested,
)
from swarmex.missions.traversal.variants import MadgtaPlus
from swarmex.worlds.nodegraph import NodeGraph

#: what a simulated world is: (known obstacles, status, vacant vertices, table, row_of)
World = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


#: the most tie orders or wall guesses a decision may roll out (each is a whole rollout)
MAX_ROLLOUTS = 1_000


class MadgtaR(Madgta):
    """MADGTA with rollout (see the module docstring).

    ``k``: MADGTA's best candidates simulated per decision. ``max_vacant``: roll out only
    when at most this many vacant vertices are left (None: always). ``horizon``: simulated
    decisions before the rest is estimated (the vacant jobs shared evenly by the agents
    still working). ``objective``: ``"lex"`` (the least sum among the candidates whose
    makespan is within ``tol`` of the best; ``tol`` None: one edge of the fastest known
    agent), ``"makespan"`` (ties by the sum) or ``"mix"`` (makespan + ``weight`` × sum /
    agents). ``unknown``: ``"free"`` (unknown cells are free) or ``"walled"`` (unsensed
    cells next to a known wall are walls in the simulation). ``far``: with vacant
    neighbours, also simulate this many of branch 3's distant targets. ``ties``: average
    over this many seeded random tie orders instead of the lowest id. ``samples``: average
    over this many seeded guesses of the unsensed walls instead of taking unknown cells as
    free. ``seed``: of those draws. ``outside``: the policy before the end game. ``nest``:
    rivals roll out their first simulated decision too.
    """

    name = "madgta-r"
    simulates = True

    def __init__(
        self, k: int = 4, max_vacant: int | None = 200, horizon: int = 1_000_000,
        objective: str = "lex", weight: float = 1.0, far: int = 0, ties: int = 0,
        samples: int = 0, seed: int = 0, outside: str = "madgta", tol: float | None = None,
        unknown: str = "free", nest: bool = False,
    ) -> None:
        if k < 1:
            raise ValueError(f"k must be >= 1, got {k}")
        if objective not in ("makespan", "mix", "lex"):
            raise ValueError(
                f"objective must be 'makespan', 'mix' or 'lex', got {objective!r}")
        if unknown not in ("free", "walled"):
            raise ValueError(f"unknown must be 'free' or 'walled', got {unknown!r}")
        if min(far, ties, samples) < 0 or horizon < 1:
            raise ValueError("far, ties and samples must be >= 0 and horizon >= 1")
        # each tie order or wall guess is one more whole rollout per decision (the docs use
        # at most 16); samples=100000000 took 5 GB in 20 s and would never have finished
        for name, value in (("ties", ties), ("samples", samples)):
            if value > MAX_ROLLOUTS:
                raise ValueError(f"{name} must be in 0..{MAX_ROLLOUTS}, got {value}")
        self.k = k
        self.max_vacant = max_vacant
        self.horizon = horizon
        self.objective = objective
        self.weight = weight
        self.far = far
        self.ties = ties
        self.samples = samples
        self.seed = seed
        if outside not in ("madgta", "madgta+"):
            raise ValueError(f"outside must be 'madgta' or 'madgta+', got {outside!r}")
        self.outside = outside
        self.tol = tol
        self.unknown = unknown
        self.nest = nest
        #: the policy of every decision not rolled out
        self._plain: Madgta = MadgtaPlus() if outside == "madgta+" else Madgta()
        #: the policy before the end game (MADGTA's own, or a subclass's sweep rule)
        self.sweep: Madgta = self._plain
        self._rows: dict[int, _Rows] = {}
        self.rollouts = 0  # decisions rolled out (for the benches)
        self.switched = 0  # of which MADGTA's first choice was not kept

    @property
    def madgta_branch2(self) -> bool:
        """Whether branch 2 still picks among the vacant neighbours (traversal_v0 reads it):
        not when distant targets compete with them (``far``)."""
        return self.far == 0

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        known = belief.known
        if not known.uniform or not belief.in_km(belief.here):
            return self._plain.decide(belief, rng)  # branch 1, or edges of several lengths
        vacant = self._vacant(belief)
        if self.max_vacant is not None and vacant.size > self.max_vacant:
            return self.sweep.decide(belief, rng)  # not yet the end game
        rows = self._rows.get(id(known))
        if rows is None or rows.known is not known:
            rows = self._rows[id(known)] = _Rows(known)
        table, row_of = rows.get(vacant)
        state = self._state(belief)
        cands, kinds = self._candidates(belief, vacant, table, row_of, state)
        if len(cands) < 2:
            return self._plain.decide(belief, rng)
        self.rollouts += 1
        scores = self._scores(belief, cands, kinds, (known.blocked, belief.status, vacant,
                                                     table, row_of), state)
        if self.objective == "lex":  # a makespan near the best, then the least sum
            tol = self._tol(belief)
            low = min(mk for mk, _ in scores) + tol + 1e-9
            scores = [(tot, 0.0) if mk <= low else (np.inf, 0.0) for mk, tot in scores]
        best = min(scores)
        # equal scores: MADGTA's own order (candidates are best first, its own kind first)
        j = next(i for i, s in enumerate(scores) if _same(s, best))
        self.switched += j > 0
        v = cands[j]
        if kinds[j] == NEAR:
            return Decision("move", v, v, 2)
        steps = known.first_steps(known.slot(belief.here), v)
        return Decision("move", _pick(steps, rng), v, 3)

    @staticmethod
    def _vacant(belief: TraversalBelief) -> np.ndarray:
        """The vacant vertices the agent can reach on its known graph (done by nobody, not
        a known wall). Unknown cells count as free, so cells walled in on every side would
        count as vacant for ever (ost003d has thousands); only reachable ones are counted
        and simulated. A vertex only a rival reaches is left out of the simulation."""
        known = belief.known
        free = (belief.status == 0) & ~known.blocked
        if not known.open_lattice:
            row = known.slot(belief.here)  # first: it may grow the table
            free &= known.hops[row] >= 0
        return np.nonzero(free)[0]

    def _candidates(
        self, belief: TraversalBelief, vacant: np.ndarray, table: np.ndarray,
        row_of: np.ndarray, state: tuple[np.ndarray, ...],
    ) -> tuple[list[int], list[int]]:
        """MADGTA's best ``k`` options (vacant neighbours, else distant targets), best
        first, plus ``far`` distant targets when it has vacant neighbours; with their kinds."""
        loc, _, _, mode, _, _ = state
        g, known = belief.graph, belief.known
        me = belief.me
        ids = self._ids(g.n_nodes)
        tpu, jt = belief.time_per_unit, belief.job_time
        out = np.empty(self.k, dtype=np.int64)
        kind, c = _options(me, self.k, g.indptr, g.indices, known.blocked, belief.status,
                           belief.reserved, vacant, table, row_of, loc, mode, tpu, jt,
                           known.step, out, ids)
        if kind in (FINISH, JOB):
            return [], []
        cands, kinds = out[:c].tolist(), [kind] * c
        if kind == NEAR and self.far:
            out = np.empty(self.far, dtype=np.int64)
            e = _far_scan(me, self.far, 2, belief.status, belief.reserved, vacant, table,
                          row_of, loc, mode, tpu, jt, known.step, out, np.empty(self.far),
                          np.empty(self.far), ids)
            cands += out[:e].tolist()
            kinds += [FAR] * e
        return cands, kinds

    def _scores(
        self, belief: TraversalBelief, cands: list[int], kinds: list[int], world: World,
        state: tuple[np.ndarray, ...],
    ) -> list[tuple[float, float]]:
        """Each candidate's simulated (objective, tie-break), averaged over the worlds
        (unsensed walls: ``samples``) and tie orders (``ties``)."""
        loc, dest, tfree, mode, intent, resv = state
        g = belief.graph
        me = belief.me
        worlds = [world]
        if self.unknown == "walled":
            worlds = self._walled_world(belief, np.asarray(cands), world[2]) or worlds
        if self.samples:
            worlds = self._sampled_worlds(belief, np.asarray(cands), world[2]) or worlds
        orders = [self._ids(g.n_nodes)]
        if self.ties:
            gen = np.random.default_rng([self.seed, me, int((belief.status > 0).sum())])
            orders = [gen.permutation(g.n_nodes).astype(np.int64) for _ in range(self.ties)]
        totals = np.zeros((len(cands), 2))
        for (blocked, status, vac, tab, rows), prio in itertools.product(worlds, orders):
            for j, (v, kind) in enumerate(zip(cands, kinds, strict=True)):
                args = (
                    me, v, kind, belief.now, self.horizon, g.indptr, g.indices, blocked,
                    status.copy(), belief.reserved.copy(), vac, tab, rows, loc.copy(),
                    dest.copy(), tfree.copy(), mode.copy(), intent.copy(), resv.copy(),
                    belief.time_per_unit, belief.job_time, belief.known.step, prio,
                )
                if self.nest:
                    totals[j] += _simulate_nested(*args, self.k, self._tol(belief))
                else:
                    totals[j] += _simulate(*args)
        totals /= len(worlds) * len(orders)
        agents = int((mode != ABSENT).sum())
        if self.objective in ("makespan", "lex"):
            return [(float(mk), float(tot)) for mk, tot in totals]
        return [(float(mk + self.weight * tot / max(agents, 1)), 0.0) for mk, tot in totals]

    def _tol(self, belief: TraversalBelief) -> float:
        """``objective='lex'``'s tolerance: ``tol``, or one edge of the fastest agent known."""
        if self.tol is not None:
            return self.tol
        seen = belief.loc >= 0
        seen[0] = False
        return float(belief.known.step * belief.time_per_unit[seen].min())

    def _walled_world(
        self, belief: TraversalBelief, cands: np.ndarray, vacant: np.ndarray
    ) -> list[World]:
        """One world where every unsensed cell next to a known wall is a wall too (walls
        come in runs), candidates excepted; empty if no such cell."""
        walls = self._likely_walls(belief)
        walls[cands] = False
        if not walls.any():
            return []
        world = self._world(belief, walls, vacant)
        _, _, _, table, rows = world
        if (table[rows[cands], belief.here] < 0).any():
            return []  # a candidate cut off by the guessed walls: guess nothing
        return [world]

    @classmethod
    def _likely_walls(cls, belief: TraversalBelief) -> np.ndarray:
        """``unknown="walled"``'s guess: the cells nobody has sensed that are not known done
        and lie next to a known wall (walls come in runs)."""
        g = belief.graph
        known = belief.known
        unknown = ~cls._sensed(belief) & (belief.status == 0) & ~known.blocked
        near = np.zeros(belief.status.size, dtype=bool)
        near[_neighbours(g, np.nonzero(known.blocked)[0])] = True
        return unknown & near

    @staticmethod
    def _visited(belief: TraversalBelief) -> np.ndarray:
        """Vertices some agent has stood on: done vertices and the agents' positions."""
        visited = belief.status > 0
        visited[belief.loc[belief.loc >= 0]] = True
        return visited

    @classmethod
    def _sensed(cls, belief: TraversalBelief, visited: np.ndarray | None = None) -> np.ndarray:
        """Cells some agent has sensed: those agents stood on (``visited``, by default
        :meth:`_visited`) and their neighbours (sensing is adjacency only)."""
        if visited is None:
            visited = cls._visited(belief)
        sensed = visited.copy()
        sensed[_neighbours(belief.graph, np.nonzero(visited)[0])] = True
        return sensed

    @staticmethod
    def _world(
        belief: TraversalBelief,
        walls: np.ndarray,
        vacant: np.ndarray,
        queue: np.ndarray | None = None,
    ) -> World:
        """The simulated world with ``walls`` added to the known ones. ``queue`` is
        scratch space of ``belief.status.size`` int32 for the distance rows (given by a
        caller that builds many worlds, so they share one)."""
        g = belief.graph
        status = belief.status
        blocked = belief.known.blocked | walls
        st = status.copy()
        st[walls] = -1
        vac = vacant[~walls[vacant]]
        table = np.empty((vac.size, status.size), dtype=np.int32)
        rows = np.full(status.size, -1, dtype=np.int64)
        rows[vac] = np.arange(vac.size)
        if queue is None:
            queue = np.empty(status.size, dtype=np.int32)
        _fill_rows(g.indptr, g.indices, blocked, vac, rows[vac], table, queue)
        return (blocked, st, vac, table, rows)

    def _sampled_worlds(
        self, belief: TraversalBelief, cands: np.ndarray, vacant: np.ndarray
    ) -> list[World]:
        """``samples`` guesses of the walls nobody has sensed yet (empty: none unknown).

        Sensed cells are the vertices agents stood on (done vertices, agents' positions)
        and their neighbours; each other not-done cell is a wall with the density of walls
        among the sensed cells. Drawn from a generator seeded by the belief (the agent, the
        number of done vertices), so the same belief gives the same guesses. Candidates
        are never walls (the agent compares going there).
        """
        known = belief.known
        status = belief.status
        visited = self._visited(belief)
        sensed = self._sensed(belief, visited)
        unknown = ~sensed & (status == 0) & ~known.blocked
        unknown[cands] = False
        if not unknown.any():
            return []
        density = float(known.blocked.sum()) / max(int(sensed.sum()), 1)
        gen = np.random.default_rng([self.seed, belief.me, int(visited.sum())])
        worlds: list[World] = []
        queue = np.empty(status.size, dtype=np.int32)
        for _ in range(self.samples):
            walls = unknown & (gen.random(status.size) < density)
            worlds.append(self._world(belief, walls, vacant, queue))
        return worlds

    def _ids(self, n: int) -> np.ndarray:
        """Tie ranks = vertex ids (cached)."""
        ids: np.ndarray | None = getattr(self, "_id_order", None)
        if ids is None or ids.size != n:
            ids = self._id_order = np.arange(n, dtype=np.int64)
        return ids

    @staticmethod
    def _state(belief: TraversalBelief) -> tuple[np.ndarray, ...]:
        """The simulation's agents from the belief (see the module docstring):
        (loc, dest, tfree, mode, intent, reservation) per agent id."""
        m1 = belief.loc.size
        loc = belief.loc.copy()
        dest = loc.copy()
        now = belief.now
        tfree = np.full(m1, now)
        mode = np.full(m1, ABSENT, dtype=np.int64)
        intent = np.full(m1, -1, dtype=np.int64)
        resv = belief.reservation.copy()
        st = belief.status
        for a in range(1, m1):
            if loc[a] < 0:
                continue
            nxt = int(belief.next_loc[a])
            fa = float(belief.free_at[a])
            if a == belief.me:
                mode[a] = FREE
            elif nxt >= 0 and nxt != loc[a]:  # C05: on its way to nxt
                mode[a] = MOVING
                dest[a] = nxt
                tfree[a] = max(fa, now)
                if belief.reserved[nxt] == a:
                    intent[a] = nxt
            elif nxt >= 0 and st[nxt] == a and fa > now:  # C07: working at nxt
                mode[a] = WORKING
                tfree[a] = fa
            else:
                mode[a] = FREE
        return loc, dest, tfree, mode, intent, resv


def _neighbours(g: NodeGraph, vertices: np.ndarray) -> np.ndarray:
    """The neighbours of ``vertices`` in ``g``'s CSR lists, concatenated (repeats kept): one
    vectorised gather, where a Python loop per vertex would cost a call each."""
    starts, ends = g.indptr[vertices], g.indptr[vertices + 1]
    lens = ends - starts
    offs = np.repeat(starts - np.cumsum(lens) + lens, lens) + np.arange(int(lens.sum()))
    return np.asarray(g.indices[offs])


def _same(a: tuple[float, float], b: tuple[float, float]) -> bool:
    return all(abs(x - y) <= 1e-9 * (1.0 + abs(y)) for x, y in zip(a, b, strict=True))


POLICIES[MadgtaR.name] = MadgtaR
