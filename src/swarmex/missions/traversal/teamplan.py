"""``madgta-p``: madgta-r's rollout with one more candidate, the first vertex of an
end-game team plan (replicated min-max routing).

Idea
----
In the end game (at most ``max_vacant`` vacant vertices in the belief) the agent plans the
whole rest of the mission for the whole team, from its own belief, and offers the first
vertex of its own route to madgta-r's rollout (:mod:`swarmex.missions.traversal.rollout`)
as one more candidate beside MADGTA's best ``k``:

1. **A start plan from MADGTA.** madgta-r's compiled MADGTA simulation runs from the
   belief to the end; each simulated agent's jobs, in order, are its route.
2. **Min-max local search** (:func:`_improve`). Routes are open paths from where each agent
   is next free (its announced node, or its vertex) at the time it is next free; a route
   ends at that time plus, per vertex, its hops from the previous one (madgta-r's hop rows
   of the vacant vertices, unknown cells as free) and the job. The search reverses a
   stretch of a route (2-opt), moves a vertex inside its route (or-opt) or to another
   route, swaps two vertices of two routes and exchanges two routes' tails (2-opt*); a
   change is kept when it lowers the later end of the routes it touches, or keeps it and
   lowers their sum: the team's makespan first, then its total time. Deterministic (fixed
   order, ties to the lowest id): the same belief gives the same plan, so under the
   perfect broadcast the agents' plans differ only in when they are made.
3. **The rollout decides.** The plan's first vertex (a vacant neighbour, or a distant
   target reached hop by hop) is simulated like MADGTA's candidates, and madgta-r's
   objective (a makespan within one edge of the best, then the least sum) picks; MADGTA's
   own order wins ties.

Results (docs/traversal-variants.md §5; five MovingAI maps, 16 identical agents, 8 seeds,
both nest modes): makespan -1.50 % ± 0.49 % against MADGTA (madgta-r: -1.20 % ± 0.48 %;
paired against madgta-r -0.30 % ± 0.20 %), never significantly above MADGTA in any map and
nest row; issue 17's -3 % is not reached. Gap instances: identical agents exactly
madgta-r's runs (sum / makespan gap 1.38 / 1.27 %); mixed sum gap 14.25 % (madgta-r
14.58 %). An oracle that plans on the true map from
MADGTA's state at 200 vacant vertices gains -2.95 % on average over the maps, and its lower
bound shows that no end-game plan gains more than 2.3 % (warehouse) and 3.0 % (random-64)
there (bench/endgame_headroom.py).

Choices, and why
----------------
* **The plan as a candidate, not as the decision** (``follow=False``). Following the
  plan's first vertex (``follow=True``) gave -0.91 % ± 0.35 % (with ``commit=True``,
  heading for a distant first vertex until it is reached or taken: -0.91 % ± 0.38 %):
  agents replan at different moments from slightly different states, and the plans, which
  assume unknown cells free, do not agree; the rollout filters the plan's bad first steps.
* **MADGTA's routes as the start plan.** A cold start (insertion of the farthest vertex at
  its cheapest place, min-max) was 2-12 % worse than MADGTA's own rest in the oracle, and
  the local search did not recover it.
* **No ruin and recreate by default** (``ils=0``). ``ils=N`` improves the local search's
  plan by N rounds of iterated local search (:func:`_iterated_search`: a random planned
  vertex and its ``ruin`` - 1 nearest planned vertices taken out, put back one by one where
  each ends its route soonest, the local search again, the plan kept if it lowers
  (makespan, sum)); its generator is seeded by the belief (vacant count, time), so the same
  belief still gives the same plan. On the true map it adds 1.2-1.5 points to the oracle's
  gain (bench/endgame_headroom.py), but in the missions it bought too little for its cost
  (docs/traversal-variants.md §5, "Ruin and recreate in the missions"; 16 agents, seeds 0-3):
  as a rollout candidate (madgta-k with ``ils=10``) -0.24 % ± 0.30 % against madgta-k;
  followed (``ils=30, follow=True``) -0.56 % on random-32-32-20 and -0.98 % on
  room-32-32-4, but +0.61 % on empty-16-16 and nothing on the two large maps (ils=10), at 10-30x
  madgta-k's CPU on the small maps. With ``keep=True`` (the previous plan, brought up to
  date, as a second start, so the rounds add up between decisions) the followed plan gains
  -1.49 % on random-32-32-20 and -0.86 % on room-32-32-4, still loses on empty-16-16
  (+0.90 %), then at about 20x madgta-k's CPU; with the faster search below, ``madgta-f``
  (:mod:`.followed`) follows such a plan once a wall is known.
* **A search that costs less, with the same moves.** The tail exchange prices a candidate
  from the two routes' hop prefixes (:func:`_hop_prefix`, O(1) instead of O(route)), and
  after a ruin and recreate the local search prices only moves that touch a route changed
  since the plan was last locally optimal (:func:`_improve_from`): the other moves were
  priced on the same routes a round before and refused. Both take exactly the moves of the
  full search (tested against it), and cut ``ils=30`` runs' CPU 3-4 times.
* **Only the end game** (``max_vacant=200``, as madgta-r): 400 gives -1.53 % ± 0.48 % on
  the real maps, noise, at 3-5x the CPU. ``outside="madgta+"`` gives -1.53 % ± 0.50 %, but
  it loses the warehouse (-0.02 % ± 0.42 %), as it did for madgta-r.

Cost
----
Per end-game decision: madgta-r's (``k`` simulations, now ``k`` + 1) plus one simulation
for the start plan and at most ``passes`` rounds of local search, each
O(vacant x (vacant + agents)) for relocation and O(agents^2 x route length^3) for tail
exchanges. CPU per run with 16 agents: 0.9 s on empty-16-16, 2.2 s on random-32-32-20,
3.0 s on room-32-32-4, 5.0 s on random-64-64-20, 6.9 s on warehouse-10-20-10-2-1, about
twice madgta-r's; 2 ms on the gap instances. No message is added.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.missions.traversal.belief import TeamPlan, TraversalBelief, route_cells
from swarmex.missions.traversal.policies import POLICIES, Decision, _pick
from swarmex.missions.traversal.rollout import MadgtaR
from swarmex.missions.traversal.rollout_sim import (
    ABSENT,
    DECIDE,
    FAR,
    MOVING,
    NEAR,
    WORKING,
    _madgta_step,
    _next_agent,
    _Rows,
    _turn,
)

#: a hop count standing for "unreachable" in the plan's costs
_FAR = 1_000_000
#: what an agent with no route of its own in a followed plan does (``idle``): MADGTA's
#: decision, or stop
IDLE = ("madgta", "stop")


@kernel(cache=True, nogil=True)
def _madgta_routes(
    now: float, indptr: NDArray[np.int64], indices: NDArray[np.int32],
    blocked: NDArray[np.bool_], st: NDArray[np.int32], rs: NDArray[np.int32],
    vacant: NDArray[np.int64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    loc: NDArray[np.int64], dest: NDArray[np.int64], tfree: NDArray[np.float64],
    mode: NDArray[np.int64], intent: NDArray[np.int64], resv: NDArray[np.int64],
    tpu: NDArray[np.float64], jt: NDArray[np.float64], step: float,
    prio: NDArray[np.int64], routes: NDArray[np.int64], lens: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """MADGTA everywhere from the state (overwritten) to the end; ``routes[a, :lens[a]]``
    are the vertices agent ``a`` starts its jobs on, in order."""
    m1 = loc.shape[0]
    work = np.zeros(m1)
    last = tfree.copy()
    target = np.full(m1, -1, dtype=np.int64)
    out = np.empty(1, dtype=np.int64)
    while True:
        a, t = _next_agent(mode, tfree)
        if a < 0:
            break
        if _turn(
            a, t, False, target,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
        ) == DECIDE:
            _madgta_step(
                a, t, out,
                indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest,
                tfree, mode, intent, resv, tpu, jt, step, prio, work, last,
            )
        if mode[a] == WORKING and tfree[a] > t:  # a job begun at t
            routes[a, lens[a]] = loc[a]
            lens[a] += 1


@kernel(cache=True, nogil=True)
def _d(
    u: int, v: int, table: NDArray[np.int32], row_of: NDArray[np.int64],
) -> float:  # pragma: no cover - compiled
    """Hops between any vertex ``u`` and a vacant vertex ``v`` (``_FAR``: unreachable)."""
    h = table[row_of[v], u]
    return float(h) if h >= 0 else float(_FAR)


@kernel(cache=True, nogil=True)
def _route_end(
    a: int, base: NDArray[np.float64], pos: NDArray[np.int64], routes: NDArray[np.int64],
    lens: NDArray[np.int64], edge: NDArray[np.float64], jt: NDArray[np.float64],
    table: NDArray[np.int32], row_of: NDArray[np.int64],
) -> float:  # pragma: no cover - compiled
    """When agent ``a`` ends its route."""
    c = base[a]
    prev = pos[a]
    for i in range(lens[a]):
        v = routes[a, i]
        c += edge[a] * _d(prev, v, table, row_of) + jt[a]
        prev = v
    return c


@kernel(cache=True, nogil=True)
def _lex_lower(new_m: float, new_s: float, old_m: float, old_s: float) -> bool:
    """Whether (makespan, sum) ``(new_m, new_s)`` is lower than ``(old_m, old_s)``: a lower
    makespan, or the same one and a lower sum (1e-9 s apart)."""
    if new_m < old_m - 1e-9:
        return True
    return new_m <= old_m + 1e-9 and new_s < old_s - 1e-9


@kernel(cache=True, nogil=True)
def _gain(old_a: float, old_b: float, new_a: float, new_b: float) -> bool:
    """A change of two routes is kept when it lowers their later end, or keeps it and
    lowers their sum (so the team's sorted ends fall: makespan first, then total)."""
    return _lex_lower(max(new_a, new_b), new_a + new_b, max(old_a, old_b), old_a + old_b)


@kernel(cache=True, nogil=True)
def _accept(old_a: float, old_b: float, new_a: float, new_b: float, cap: float) -> bool:
    """:func:`_gain`, or with ``cap`` >= 0: both routes end by ``cap`` and their sum
    falls (a strict descent of the sum under a fixed makespan limit)."""
    if cap < 0.0:
        return _gain(old_a, old_b, new_a, new_b)
    return max(new_a, new_b) <= cap + 1e-9 and new_a + new_b < old_a + old_b - 1e-9


@kernel(cache=True, nogil=True)
def _shift(routes: NDArray[np.int64], a: int, i: int, q: int, n: int) -> None:
    """Move ``routes[a, i]`` to position ``q`` of the ``n`` of route ``a``."""
    v = routes[a, i]
    if i < q:
        for t in range(i, q):
            routes[a, t] = routes[a, t + 1]
    else:
        for t in range(i, q, -1):
            routes[a, t] = routes[a, t - 1]
    routes[a, q] = v


@kernel(cache=True, nogil=True)
def _insert_at(
    routes: NDArray[np.int64], lens: NDArray[np.int64], a: int, q: int, v: int,
) -> None:  # pragma: no cover - compiled
    """Put vertex ``v`` at position ``q`` of route ``a`` (the rest moves one place on)."""
    for t in range(lens[a], q, -1):
        routes[a, t] = routes[a, t - 1]
    routes[a, q] = v
    lens[a] += 1


@kernel(cache=True, nogil=True)
def _improve(
    base: NDArray[np.float64], pos: NDArray[np.int64], active: NDArray[np.bool_],
    routes: NDArray[np.int64], lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    passes: int,
) -> int:  # pragma: no cover - compiled
    """Min-max local search on the routes in place (2-opt and or-opt inside a route,
    relocation to another route, swaps and tail exchanges between routes), at most
    ``passes`` rounds; returns the rounds that changed something."""
    return _improve_from(base, pos, active, routes, lens, edge, jt, table, row_of, passes,
                         np.ones(base.shape[0], dtype=np.bool_), -1.0)


@kernel(cache=True, nogil=True)
def _improve_from(
    base: NDArray[np.float64], pos: NDArray[np.int64], active: NDArray[np.bool_],
    routes: NDArray[np.int64], lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    passes: int, dirty: NDArray[np.bool_], cap: float,
) -> int:  # pragma: no cover - compiled
    """:func:`_improve` when only the routes marked ``dirty`` may have changed since the
    plan was last locally optimal. A move is priced only if one of its routes changed in
    this round or the one before (``seen``): every other one was priced on the same
    routes a round ago and refused, and a move's worth depends on its own routes alone,
    so the search takes the same moves as a full one, at a fraction of the cost.
    ``cap`` < 0 keeps a move by :func:`_gain` (min-max); ``cap`` >= 0 keeps it when it
    lowers the sum and both routes then end by ``cap`` (:func:`_accept`: the ``slack``
    pass, where swapping two agents' whole routes is a move too). Either way a move's
    worth depends on its own two routes only."""
    m1 = base.shape[0]
    seen = np.full(m1, -2, dtype=np.int64)  # the last round a route changed in
    for a in range(m1):
        if dirty[a]:
            seen[a] = 0
    ends = np.zeros(m1)
    for a in range(1, m1):
        if active[a]:
            ends[a] = _route_end(a, base, pos, routes, lens, edge, jt, table, row_of)
    hp_a = np.empty(routes.shape[1] + 1)
    hp_b = np.empty(routes.shape[1] + 1)
    changed = 0
    for r in range(1, passes + 1):
        better = False
        # 2-opt inside each route: reverse routes[a, i..j]
        for a in range(1, m1):
            if not active[a] or seen[a] < r - 1:
                continue
            n = lens[a]
            for i in range(n):
                p = pos[a] if i == 0 else routes[a, i - 1]
                for j in range(i + 1, n):
                    vi = routes[a, i]
                    vj = routes[a, j]
                    delta = _d(p, vj, table, row_of) - _d(p, vi, table, row_of)
                    if j + 1 < n:
                        nx = routes[a, j + 1]
                        delta += _d(vi, nx, table, row_of) - _d(vj, nx, table, row_of)
                    if delta < -1e-9:
                        lo, hi = i, j
                        while lo < hi:
                            tmp = routes[a, lo]
                            routes[a, lo] = routes[a, hi]
                            routes[a, hi] = tmp
                            lo += 1
                            hi -= 1
                        ends[a] += edge[a] * delta
                        seen[a] = r
                        better = True
        # move one vertex elsewhere in its own route (or-opt of one)
        for a in range(1, m1):
            if not active[a] or seen[a] < r - 1:
                continue
            n = lens[a]
            for i in range(n):
                for q in range(n):
                    if q == i:
                        continue
                    _shift(routes, a, i, q, n)
                    e = _route_end(a, base, pos, routes, lens, edge, jt, table, row_of)
                    if e < ends[a] - 1e-9:
                        ends[a] = e
                        seen[a] = r
                        better = True
                    else:
                        _shift(routes, a, q, i, n)
        # relocate one vertex to another route (best place)
        for a in range(1, m1):
            if not active[a]:
                continue
            i = 0
            while i < lens[a]:
                v = routes[a, i]
                p = pos[a] if i == 0 else routes[a, i - 1]
                cut = -_d(p, v, table, row_of)
                if i + 1 < lens[a]:
                    nx = routes[a, i + 1]
                    cut += _d(p, nx, table, row_of) - _d(v, nx, table, row_of)
                new_a = ends[a] + edge[a] * cut - jt[a]
                best_b = -1
                best_q = -1
                best_m = np.inf
                best_s = np.inf
                best_nb = 0.0
                for b in range(1, m1):
                    if not active[b] or b == a or (seen[a] < r - 1 and seen[b] < r - 1):
                        continue
                    q_prev = pos[b]
                    for q in range(lens[b] + 1):
                        add = _d(q_prev, v, table, row_of)
                        if q < lens[b]:
                            nx = routes[b, q]
                            add += _d(v, nx, table, row_of) - _d(q_prev, nx, table, row_of)
                        nb = ends[b] + edge[b] * add + jt[b]
                        if _accept(ends[a], ends[b], new_a, nb, cap):
                            nm = max(new_a, nb) if cap < 0.0 else 0.0
                            ns = new_a + nb
                            if nm < best_m - 1e-9 or (nm <= best_m + 1e-9 and ns < best_s - 1e-9):
                                best_m = nm
                                best_s = ns
                                best_b = b
                                best_q = q
                                best_nb = nb
                        if q < lens[b]:
                            q_prev = routes[b, q]
                if best_b >= 0:
                    for t in range(i, lens[a] - 1):
                        routes[a, t] = routes[a, t + 1]
                    lens[a] -= 1
                    b = best_b
                    _insert_at(routes, lens, b, best_q, v)
                    ends[a] = new_a
                    ends[b] = best_nb
                    seen[a] = r
                    seen[b] = r
                    better = True
                else:
                    i += 1
        # swap two vertices of two routes
        for a in range(1, m1):
            if not active[a]:
                continue
            for b in range(a + 1, m1):
                if not active[b] or (seen[a] < r - 1 and seen[b] < r - 1):
                    continue
                for i in range(lens[a]):
                    va = routes[a, i]
                    pa = pos[a] if i == 0 else routes[a, i - 1]
                    na = routes[a, i + 1] if i + 1 < lens[a] else -1
                    for j in range(lens[b]):
                        vb = routes[b, j]
                        pb = pos[b] if j == 0 else routes[b, j - 1]
                        nb_ = routes[b, j + 1] if j + 1 < lens[b] else -1
                        da = _d(pa, vb, table, row_of) - _d(pa, va, table, row_of)
                        if na >= 0:
                            da += _d(vb, na, table, row_of) - _d(va, na, table, row_of)
                        db = _d(pb, va, table, row_of) - _d(pb, vb, table, row_of)
                        if nb_ >= 0:
                            db += _d(va, nb_, table, row_of) - _d(vb, nb_, table, row_of)
                        new_a = ends[a] + edge[a] * da
                        new_b = ends[b] + edge[b] * db
                        if _accept(ends[a], ends[b], new_a, new_b, cap):
                            routes[a, i] = vb
                            routes[b, j] = va
                            ends[a] = new_a
                            ends[b] = new_b
                            va = vb
                            seen[a] = r
                            seen[b] = r
                            better = True
        # exchange the tails of two routes (2-opt*): a[:i] + b[j:] and b[:j] + a[i:],
        # each candidate priced in O(1) from the routes' hop prefixes
        for a in range(1, m1):
            if not active[a]:
                continue
            for b in range(a + 1, m1):
                if not active[b] or (seen[a] < r - 1 and seen[b] < r - 1):
                    continue
                found = True
                while found:
                    found = False
                    top = max(ends[a], ends[b]) if cap < 0.0 else cap
                    _hop_prefix(a, pos, routes, lens, table, row_of, hp_a)
                    _hop_prefix(b, pos, routes, lens, table, row_of, hp_b)
                    # a candidate that ends either route later than both end now cannot
                    # gain; a[:i] alone already ends at base + hops + jobs of its i vertices,
                    # which grows with i (so does b[:j] with j): the scans stop there
                    for i in range(lens[a] + 1):
                        if base[a] + edge[a] * hp_a[i] + jt[a] * i > top + 1e-9:
                            break
                        for j in range(lens[b] + 1):
                            if base[b] + edge[b] * hp_b[j] + jt[b] * j > top + 1e-9:
                                break
                            if i == lens[a] and j == lens[b]:
                                continue
                            if i == 0 and j == 0 and cap < 0.0:
                                continue  # swapping whole routes: a sum-pass move only
                            new_a = _spliced_end(a, base, pos, routes, i, b, j, lens, edge, jt,
                                                 table, row_of, hp_a, hp_b)
                            if new_a > top + 1e-9:
                                continue
                            new_b = _spliced_end(b, base, pos, routes, j, a, i, lens, edge, jt,
                                                 table, row_of, hp_b, hp_a)
                            if _accept(ends[a], ends[b], new_a, new_b, cap):
                                _swap_tails(routes, lens, a, i, b, j)
                                ends[a] = new_a
                                ends[b] = new_b
                                seen[a] = r
                                seen[b] = r
                                better = True
                                found = True
                                break
                        if found:
                            break
        if not better:
            break
        changed += 1
    return changed


@kernel(cache=True, nogil=True)
def _hop_prefix(
    a: int, pos: NDArray[np.int64], routes: NDArray[np.int64], lens: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], hp: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """``hp[i]``: hops from agent ``a``'s place through ``routes[a, :i]`` (``hp[0] = 0``)."""
    hp[0] = 0.0
    prev = pos[a]
    for i in range(lens[a]):
        v = routes[a, i]
        hp[i + 1] = hp[i] + _d(prev, v, table, row_of)
        prev = v


@kernel(cache=True, nogil=True)
def _spliced_end(
    a: int, base: NDArray[np.float64], pos: NDArray[np.int64], routes: NDArray[np.int64],
    i: int, b: int, j: int, lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    hp_a: NDArray[np.float64], hp_b: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """When agent ``a`` ends the route ``routes[a, :i]`` + ``routes[b, j:]``, from the two
    routes' hop prefixes (:func:`_hop_prefix`): a route's end is its start plus its hops
    times the agent's edge time plus its jobs, so the spliced route costs O(1), not O(n)."""
    hops = hp_a[i]
    if j < lens[b]:
        prev = pos[a] if i == 0 else routes[a, i - 1]
        hops += _d(prev, routes[b, j], table, row_of) + hp_b[lens[b]] - hp_b[j + 1]
    return base[a] + edge[a] * hops + jt[a] * (i + lens[b] - j)


@kernel(cache=True, nogil=True)
def _swap_tails(
    routes: NDArray[np.int64], lens: NDArray[np.int64], a: int, i: int, b: int, j: int,
) -> None:  # pragma: no cover - compiled
    """``routes[a]`` becomes a[:i] + b[j:] and ``routes[b]`` b[:j] + a[i:]."""
    ta = routes[a, i:lens[a]].copy()
    tb = routes[b, j:lens[b]].copy()
    na = i + tb.size
    nb = j + ta.size
    routes[a, i:na] = tb
    routes[b, j:nb] = ta
    routes[a, na:] = -1
    routes[b, nb:] = -1
    lens[a] = na
    lens[b] = nb


@kernel(cache=True, nogil=True)
def _next_random(rs: NDArray[np.uint64], n: int) -> int:  # pragma: no cover - compiled
    """A draw in [0, n) from the xorshift64 state ``rs[0]`` (advanced, never 0): the plan's
    own generator, so that it depends on the belief only, not on the agent's stream.
    Shifts and xors only, so that run interpreted it gives the same draws and no overflow
    warnings."""
    x = rs[0]
    x ^= x << np.uint64(13)
    x ^= x >> np.uint64(7)
    x ^= x << np.uint64(17)
    rs[0] = x
    return int(x >> np.uint64(11)) % n


@kernel(cache=True, nogil=True)
def _insert_soonest(
    v: int, pos: NDArray[np.int64], active: NDArray[np.bool_], routes: NDArray[np.int64],
    lens: NDArray[np.int64], edge: NDArray[np.float64], jt: NDArray[np.float64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], ends: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Put ``v`` where it ends its route soonest (ties: the lowest agent and place);
    ``ends`` (each active route's end) is kept up to date."""
    best = np.inf
    best_a = -1
    best_i = 0
    for a in range(1, pos.shape[0]):
        if not active[a]:
            continue
        prev = pos[a]
        for i in range(lens[a] + 1):
            add = edge[a] * _d(prev, v, table, row_of) + jt[a]
            if i < lens[a]:
                nx = routes[a, i]
                add += edge[a] * (_d(v, nx, table, row_of) - _d(prev, nx, table, row_of))
                prev = nx
            if ends[a] + add < best - 1e-9:
                best = ends[a] + add
                best_a = a
                best_i = i
    _insert_at(routes, lens, best_a, best_i, v)
    ends[best_a] = best


@kernel(cache=True, nogil=True)
def _ruin_recreate(
    base: NDArray[np.float64], pos: NDArray[np.int64], active: NDArray[np.bool_],
    routes: NDArray[np.int64], lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    ends: NDArray[np.float64], size: int, rs: NDArray[np.uint64],
) -> None:  # pragma: no cover - compiled
    """Take out a random planned vertex and its ``size`` - 1 nearest planned vertices (a
    spatial cluster), then put each back, in random order, where it ends its route soonest
    (ties: the lowest agent and place). ``ends`` is kept up to date."""
    m1 = base.shape[0]
    total = 0
    for a in range(1, m1):
        total += lens[a]
    if total == 0:
        return
    planned = np.empty(total, dtype=np.int64)
    t = 0
    for a in range(1, m1):
        for i in range(lens[a]):
            planned[t] = routes[a, i]
            t += 1
    centre = planned[_next_random(rs, total)]
    hops = np.empty(total)
    for t in range(total):
        hops[t] = _d(centre, planned[t], table, row_of)
    order = np.argsort(hops, kind="mergesort")
    size = min(size, total)
    out = np.zeros(row_of.shape[0], dtype=np.bool_)
    removed = np.empty(size, dtype=np.int64)
    for t in range(size):
        removed[t] = planned[order[t]]
        out[removed[t]] = True
    for a in range(1, m1):
        n = 0
        for i in range(lens[a]):
            v = routes[a, i]
            if not out[v]:
                routes[a, n] = v
                n += 1
        routes[a, n:lens[a]] = -1
        lens[a] = n
        if active[a]:
            ends[a] = _route_end(a, base, pos, routes, lens, edge, jt, table, row_of)
    for t in range(size - 1, 0, -1):  # Fisher-Yates: the order they go back in
        u = _next_random(rs, t + 1)
        tmp = removed[t]
        removed[t] = removed[u]
        removed[u] = tmp
    for t in range(size):
        _insert_soonest(removed[t], pos, active, routes, lens, edge, jt, table, row_of, ends)


@kernel(cache=True, nogil=True)
def _plan_ends(
    base: NDArray[np.float64], pos: NDArray[np.int64], active: NDArray[np.bool_],
    routes: NDArray[np.int64], lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    ends: NDArray[np.float64],
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Every active agent's route end into ``ends``; returns the plan's (makespan, sum)."""
    mk = 0.0
    sm = 0.0
    for a in range(1, base.shape[0]):
        if active[a]:
            ends[a] = _route_end(a, base, pos, routes, lens, edge, jt, table, row_of)
            mk = max(mk, ends[a])
            sm += ends[a]
    return mk, sm


@kernel(cache=True, nogil=True)
def _iterated_search(
    base: NDArray[np.float64], pos: NDArray[np.int64], active: NDArray[np.bool_],
    routes: NDArray[np.int64], lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    rounds: int, size: int, passes: int, seed: int,
) -> int:  # pragma: no cover - compiled
    """Iterated local search on a plan, in place: ``rounds`` times ruin and recreate a
    cluster of ``size`` vertices (:func:`_ruin_recreate`), run the local search again (at
    most ``passes`` rounds) and keep the plan if it lowers (makespan, sum), else go back to
    the best one. Returns how many rounds improved the plan.

    The local search first makes sure the plan is locally optimal (one round when it is
    already); after that, while the kept plan is locally optimal, a round's search starts
    from the routes the ruin and recreate changed (:func:`_improve_from`), which gives the
    same plan as a full search."""
    m1 = base.shape[0]
    optimal = _improve(base, pos, active, routes, lens, edge, jt, table, row_of, passes) < passes
    ends = np.zeros(m1)
    best_m, best_s = _plan_ends(base, pos, active, routes, lens, edge, jt, table, row_of, ends)
    kept = routes.copy()
    kept_lens = lens.copy()
    rs = np.full(1, np.uint64(seed) ^ np.uint64(0x9E3779B97F4A7C15))  # never 0: seed >= 0
    dirty = np.ones(m1, dtype=np.bool_)
    won = 0
    for _ in range(rounds):
        _ruin_recreate(base, pos, active, routes, lens, edge, jt, table, row_of, ends, size,
                       rs)
        for a in range(m1):
            n = lens[a]
            dirty[a] = (not optimal or n != kept_lens[a]
                        or np.any(routes[a, :n] != kept[a, :n]))
        settled = _improve_from(base, pos, active, routes, lens, edge, jt, table, row_of,
                                passes, dirty, -1.0) < passes
        mk, sm = _plan_ends(base, pos, active, routes, lens, edge, jt, table, row_of, ends)
        if _lex_lower(mk, sm, best_m, best_s):
            best_m = mk
            best_s = sm
            kept[:] = routes
            kept_lens[:] = lens
            optimal = settled
            won += 1
        else:
            routes[:] = kept
            lens[:] = kept_lens
            _plan_ends(base, pos, active, routes, lens, edge, jt, table, row_of, ends)
    return won


@kernel(cache=True, nogil=True)
def _warm_start(
    base: NDArray[np.float64], pos: NDArray[np.int64], active: NDArray[np.bool_],
    routes: NDArray[np.int64], lens: NDArray[np.int64], edge: NDArray[np.float64],
    jt: NDArray[np.float64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    warm: NDArray[np.int64], warm_lens: NDArray[np.int64], passes: int,
) -> bool:  # pragma: no cover - compiled
    """Replace the plan (``routes``) by the agent's previous plan brought up to date, if
    that is better after the local search: each route keeps its previous vertices still to
    be planned, in order; the others go where they end their route soonest. Returns
    whether it replaced the plan."""
    m1 = base.shape[0]
    n = row_of.shape[0]
    todo = np.zeros(n, dtype=np.bool_)
    for a in range(1, m1):
        for i in range(lens[a]):
            todo[routes[a, i]] = True
    cand = np.full_like(routes, -1)
    clens = np.zeros_like(lens)
    for a in range(1, min(m1, warm.shape[0])):
        if not active[a]:
            continue
        for i in range(warm_lens[a]):
            v = warm[a, i]
            if v >= 0 and v < n and todo[v]:
                cand[a, clens[a]] = v
                clens[a] += 1
                todo[v] = False
    ends = np.zeros(m1)
    _plan_ends(base, pos, active, cand, clens, edge, jt, table, row_of, ends)
    for a in range(1, m1):
        for i in range(lens[a]):
            v = routes[a, i]
            if not todo[v]:
                continue
            todo[v] = False
            _insert_soonest(v, pos, active, cand, clens, edge, jt, table, row_of, ends)
    _improve(base, pos, active, cand, clens, edge, jt, table, row_of, passes)
    m_old, s_old = _plan_ends(base, pos, active, routes, lens, edge, jt, table, row_of, ends)
    m_new, s_new = _plan_ends(base, pos, active, cand, clens, edge, jt, table, row_of, ends)
    if _lex_lower(m_new, s_new, m_old, s_old):
        routes[:] = cand
        lens[:] = clens
        return True
    return False


@kernel(cache=True, nogil=True)
def _team_plan(
    me: int, now: float, indptr: NDArray[np.int64], indices: NDArray[np.int32],
    blocked: NDArray[np.bool_], st: NDArray[np.int32], rs: NDArray[np.int32],
    vacant: NDArray[np.int64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    loc: NDArray[np.int64], dest: NDArray[np.int64], tfree: NDArray[np.float64],
    mode: NDArray[np.int64], intent: NDArray[np.int64], resv: NDArray[np.int64],
    tpu: NDArray[np.float64], jt: NDArray[np.float64], step: float,
    prio: NDArray[np.int64], passes: int, routes: NDArray[np.int64], lens: NDArray[np.int64],
    ils: int, ruin: int, warm: NDArray[np.int64], warm_lens: NDArray[np.int64],
    slack: float, trade: float, own: NDArray[np.int64], own_lens: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """The team plan from the state (the caller's copies; overwritten): MADGTA's routes,
    then :func:`_improve`, then ``ils`` rounds of :func:`_iterated_search` (seeded by the
    number of vacant vertices and the time, so the same belief gives the same plan).
    With a previous plan (``warm_lens`` not all 0) that plan, brought up to date, replaces
    MADGTA's if it is better (:func:`_warm_start`), before the ruin and recreate.
    ``routes`` is the plan to share and to start from next time; ``own`` the plan to follow:
    the same, or with ``slack`` > 0 the sum pass's plan (:func:`_improve_from` from it, no
    route ending more than ``slack`` edges of the fastest agent after its makespan) if its
    sum plus ``trade`` x active agents x its makespan is lower.
    Returns the first vertex of ``me``'s route in ``own`` (-1: none)."""
    m1 = loc.shape[0]
    base = tfree.copy()
    pos = loc.copy()
    active = np.zeros(m1, dtype=np.bool_)
    fixed = np.full(m1, -1, dtype=np.int64)
    for a in range(1, m1):
        if mode[a] == ABSENT:
            continue
        active[a] = True
        if a == me:
            base[a] = now
        elif mode[a] == MOVING:
            pos[a] = dest[a]
            if intent[a] >= 0:
                fixed[a] = intent[a]  # its job on arrival: not for the plan to move
        if base[a] < now:
            base[a] = now
    _madgta_routes(now, indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest,
                   tfree, mode, intent, resv, tpu, jt, step, prio, routes, lens)
    edge = np.empty(m1)
    for a in range(m1):
        edge[a] = step * tpu[a]
        if active[a] and fixed[a] >= 0 and lens[a] > 0 and routes[a, 0] == fixed[a]:
            for t in range(lens[a] - 1):
                routes[a, t] = routes[a, t + 1]
            lens[a] -= 1
            base[a] += jt[a]
    _improve(base, pos, active, routes, lens, edge, jt, table, row_of, passes)
    if warm_lens.sum() > 0:
        _warm_start(base, pos, active, routes, lens, edge, jt, table, row_of, warm, warm_lens,
                    passes)
    if ils > 0:
        seed = vacant.shape[0] * 1_000_003 + int(now * 1000.0)
        _iterated_search(base, pos, active, routes, lens, edge, jt, table, row_of, ils, ruin,
                         passes, seed)
    own[:] = routes
    own_lens[:] = lens
    if slack > 0.0:  # the followed plan: a lower sum within slack edges of the makespan
        ends = np.zeros(m1)
        mk, sm = _plan_ends(base, pos, active, routes, lens, edge, jt, table, row_of, ends)
        _improve_from(base, pos, active, own, own_lens, edge, jt, table, row_of, passes,
                      np.ones(m1, dtype=np.bool_), mk + slack * edge[active].min())
        mk_own, sm_own = _plan_ends(base, pos, active, own, own_lens, edge, jt, table, row_of,
                                    ends)
        weight = trade * active.sum()
        if sm_own + weight * mk_own >= sm + weight * mk - 1e-9:
            own[:] = routes  # not worth its longer makespan
            own_lens[:] = lens
    return own[me, 0] if own_lens[me] > 0 else -1


@dataclass(frozen=True)
class _Planned:
    """An end-game plan made for one decision: the agent's first vertex in it (-1: no
    route of its own), every agent's route (``routes``, to share and keep; ``own``, to
    follow: the sum pass's), and what the decision reuses."""

    first: int
    routes: np.ndarray
    lens: np.ndarray
    following: bool
    searched: bool
    vacant: np.ndarray
    table: np.ndarray
    row_of: np.ndarray
    state: tuple[np.ndarray, ...]
    own: np.ndarray
    own_lens: np.ndarray


#: the largest ``passes`` or ``ils`` a plan may be asked for
MAX_BUDGET = 10_000


class MadgtaP(MadgtaR):
    """madgta-r with the team plan's first vertex as one more candidate (see the module
    docstring).

    ``passes``: rounds of local search per plan (0: MADGTA's simulated routes as they are).
    ``ils``: rounds of ruin and recreate after it (0: none; measured, not kept), each
    taking out a cluster of ``ruin`` planned vertices. ``keep``: start also from the
    agent's previous plan, brought up to date, when it is better than MADGTA's (so the
    rounds add up from decision to decision).
    ``share`` (with ``keep``): the plan to start from is the newest the agent made or heard
    (:attr:`TraversalBelief.plan`), and the searched plan goes out with the decision as a
    ``plan`` message (madgta-s, :mod:`.followed`).
    ``follow``: go to the plan's first vertex instead of rolling it out (not kept, for the
    benches); ``"walls"``: only once a wall is known (on an open lattice the decision is
    the rollout's, without ``ils`` or ``keep``, because there a followed plan lost);
    ``commit`` (with ``follow``): keep heading for a distant first vertex until it is
    reached or taken. ``idle`` (with ``follow``): what an agent with no route of its own in
    the plan does, ``"madgta"`` (MADGTA's decision) or ``"stop"`` (it finishes and says
    ``leave``, if every agent holding a route is on time in its belief:
    :func:`_holders_on_time`). ``detour`` (with ``follow``): on the way to a distant first
    vertex, prefer a first step that is not a teammate's planned vertex (madgta-s has both:
    :mod:`.followed`). ``slack`` (edges of the fastest agent, 0: off) and ``trade``: the
    plan followed is the searched plan after a pass that lowers its sum while no route ends
    more than ``slack`` edges after its makespan, if that pass's sum plus ``trade`` x the
    active agents x its makespan is lower; the searched plan is the one kept and shared
    (madgta-s: ``slack=1.5``). Every other keyword is madgta-r's (``max_vacant``, ``k``, ...);
    madgta-r's ``unknown="walled"`` also leaves the likely walls (unsensed cells next to a
    known wall) out of a followed plan's jobs, while its paths may still cross them
    (screened, not kept: docs/traversal-variants.md §7).
    """

    name = "madgta-p"

    def __init__(self, passes: int = 50, follow: bool | str = False, commit: bool = False,
                 ils: int = 0, ruin: int = 12, keep: bool = False, share: bool = False,
                 idle: str = "madgta", detour: bool = False, slack: float = 0.0,
                 trade: float = 0.5, **rollout: object) -> None:
        super().__init__(**rollout)  # type: ignore[arg-type]
        if follow not in (False, True, "walls"):
            raise ValueError(f"follow must be True, False or 'walls', got {follow!r}")
        if idle not in IDLE:
            raise ValueError(f"idle must be one of {', '.join(IDLE)}, got {idle!r}")
        if (idle != "madgta" or detour) and not follow:
            raise ValueError("idle and detour act on a followed plan: they need follow")
        self.idle = idle
        #: the agent core broadcasts ``leave`` when an agent finishes: with ``idle="stop"``
        #: it may finish while vacant vertices remain, and the others must not plan for it
        self.announce_leave = idle == "stop"
        self.detour = detour
        if slack < 0 or trade < 0:
            raise ValueError(f"slack and trade must be >= 0, got {slack} and {trade}")
        self.slack = float(slack)
        self.trade = float(trade)
        # budgets are capped: they run in compiled loops that Ctrl-C cannot stop, and
        # ils=1000000000 (a typo's worth) ran for ever; the benches use at most a few hundred
        if not 0 <= passes <= MAX_BUDGET:
            raise ValueError(f"passes must be in 0..{MAX_BUDGET}, got {passes}")
        if not 0 <= ils <= MAX_BUDGET:
            raise ValueError(f"ils must be in 0..{MAX_BUDGET}, got {ils}")
        if ruin < 1:
            raise ValueError(f"ruin must be >= 1, got {ruin}")
        self.ils = ils
        self.ruin = ruin
        if share and not keep:
            raise ValueError("share needs keep=True (the shared plan is the kept one)")
        self.keep = keep
        self.share = share
        self._kept: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        if commit and not follow:
            raise ValueError("commit needs follow=True")
        if commit and idle == "stop":  # retires() plans as decide() does, without a target
            raise ValueError("idle='stop' cannot be combined with commit")
        self.passes = passes
        self.follow = follow
        self.commit = commit
        self._target: dict[int, int] = {}
        self.plans = 0  # decisions planned (for the benches)

    @property
    def madgta_branch2(self) -> bool:
        """Whether branch 2 still picks among the vacant neighbours (traversal_v0 reads
        it): not here, the plan may send an agent past a vacant neighbour."""
        return False

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        known = belief.known
        if not known.uniform or not belief.in_km(belief.here):
            return self._plain.decide(belief, rng)
        vacant = self._vacant(belief)
        if self.max_vacant is not None and vacant.size > self.max_vacant:
            return self.sweep.decide(belief, rng)  # not yet the end game
        me = belief.me
        here = belief.here
        if self.commit:
            f = self._target.pop(me, -1)
            if (f >= 0 and f != here and belief.status[f] == 0 and not known.blocked[f]
                    and belief.reserved[f] in (0, me)
                    and (known.open_lattice or known.hops[known.slot(here)][f] >= 0)):
                return self._towards(belief, f, rng)
        if vacant.size == 0:
            return self._plain.decide(belief, rng)
        p = self._plan(belief, vacant)
        made = None
        if self.keep and p.searched:
            if self.share:  # broadcast with the decision; the agent core keeps it too
                made = TeamPlan(belief.now, p.routes, p.lens)
            else:
                self._kept[me] = (p.routes, p.lens)
        d = self._choose(belief, rng, p)
        # an agent that stops sends no plan (nor does an environment's agent with nothing
        # left to choose, whose finish never reaches the policy)
        return d if made is None or d.kind == "finish" else replace(d, plan=made)

    def retires(self, belief: TraversalBelief) -> bool:
        """Whether the agent stops now although vacant vertices remain (``idle="stop"``):
        the traversal environment asks this before it asks for an action. The same plan as
        :meth:`decide` makes, and nothing kept from it (no generator draw)."""
        known = belief.known
        if self.idle != "stop" or not known.uniform or not belief.in_km(belief.here):
            return False
        vacant = self._vacant(belief)
        if vacant.size == 0 or (self.max_vacant is not None and vacant.size > self.max_vacant):
            return False
        p = self._plan(belief, vacant)
        return p.following and p.first < 0 and _holders_on_time(belief, p.own, p.own_lens)

    def _plan(self, belief: TraversalBelief, vacant: np.ndarray) -> _Planned:
        """The end-game team plan from the belief (deterministic: the same belief and kept
        plan give the same plan)."""
        known = belief.known
        rows = self._rows.get(id(known))
        if rows is None or rows.known is not known:
            rows = self._rows[id(known)] = _Rows(known)
        g = belief.graph
        table, row_of = rows.get(vacant)
        state = self._state(belief)
        loc, dest, tfree, mode, intent, resv = state
        following = self.follow is True or (self.follow == "walls" and not known.open_lattice)
        # with follow="walls" the search and the kept plan serve the followed plan only,
        # so that on an open lattice the decision is exactly the rollout's
        searched = self.follow != "walls" or following
        routes = np.full((loc.size, vacant.size + 1), -1, dtype=np.int64)
        lens = np.zeros(loc.size, dtype=np.int64)
        own, own_lens = np.empty_like(routes), np.empty_like(lens)
        status, planned = belief.status.copy(), vacant
        if self.unknown == "walled" and following:
            # no job planned on a likely wall (rollout.py's guess); still free to cross
            likely = self._likely_walls(belief)[vacant]
            if likely.any() and not likely.all():
                status[vacant[likely]] = -1
                planned = vacant[~likely]
        f = _team_plan(
            belief.me, belief.now, g.indptr, g.indices, known.blocked, status,
            belief.reserved.copy(), planned, table, row_of, loc.copy(), dest.copy(),
            tfree.copy(), mode.copy(), intent.copy(), resv.copy(), belief.time_per_unit,
            belief.job_time, known.step, self._ids(g.n_nodes), self.passes, routes, lens,
            self.ils if searched else 0, self.ruin,
            *self._warm(belief, loc.size, searched), self.slack if searched else 0.0,
            self.trade, own, own_lens,
        )
        return _Planned(int(f), routes, lens, following, searched, vacant, table, row_of,
                        state, own, own_lens)

    def _choose(self, belief: TraversalBelief, rng: np.random.Generator,
                p: _Planned) -> Decision:
        """The decision once the plan is made: its first vertex followed, or judged as one
        more candidate of madgta-r's rollout."""
        g = belief.graph
        known = belief.known
        here = belief.here
        f, vacant, table, row_of, state = p.first, p.vacant, p.table, p.row_of, p.state
        if not p.following:  # the plan's vertex as one more candidate of madgta-r's rollout
            cands, kinds = self._candidates(belief, vacant, table, row_of, state)
            if not cands:
                return self._plain.decide(belief, rng)
            if f >= 0 and f not in cands:
                near = f in g.indices[g.indptr[here]:g.indptr[here + 1]]
                cands.append(int(f))
                kinds.append(NEAR if near else FAR)
            if len(cands) < 2:
                return self._plain.decide(belief, rng)
            scores = self._scores(belief, cands, kinds, (known.blocked, belief.status,
                                                         vacant, table, row_of), state)
            low = min(mk for mk, _ in scores) + self._tol(belief) + 1e-9
            keyed = [(tot if mk <= low else np.inf) for mk, tot in scores]
            j = int(np.argmin(keyed))
            self.plans += 1
            if kinds[j] == NEAR:
                return Decision("move", cands[j], cands[j], 2)
            steps = known.first_steps(known.slot(here), cands[j])
            return Decision("move", _pick(steps, rng), cands[j], 3)
        if f < 0:  # no route of its own in the plan
            if self.idle == "stop" and _holders_on_time(belief, p.own, p.own_lens):
                return Decision("finish")
            return self._plain.decide(belief, rng)
        self.plans += 1
        theirs = _theirs(belief, p.own, p.own_lens) if self.detour else None
        return self._towards(belief, int(f), rng, theirs)

    def _warm(self, belief: TraversalBelief, rows: int,
              searched: bool) -> tuple[np.ndarray, np.ndarray]:
        """The plan to start from (``keep``, when the plan is searched): the agent's
        previous one, or with ``share`` the newest made or heard; else none (all lengths
        0)."""
        kept: tuple[np.ndarray, np.ndarray] | None = None
        if self.keep and searched:
            if self.share:
                heard = belief.plan
                kept = None if heard is None else (heard.routes, heard.lens)
            else:
                kept = self._kept.get(belief.me)
        if kept is None or kept[1].size != rows:
            return np.full((rows, 1), -1, dtype=np.int64), np.zeros(rows, dtype=np.int64)
        return kept

    def _towards(self, belief: TraversalBelief, f: int, rng: np.random.Generator,
                 theirs: np.ndarray | None = None) -> Decision:
        """To ``f``: directly if it is a neighbour, else one hop on a shortest path; with
        ``theirs`` (a mask of the vertices planned for the other agents), a first step that
        is not one of them when such a step exists (``detour``)."""
        g = belief.graph
        here = belief.here
        if f in g.indices[g.indptr[here]:g.indptr[here + 1]]:
            return Decision("move", f, f, 2)
        if self.commit:
            self._target[belief.me] = f
        known = belief.known
        steps = known.first_steps(known.slot(here), f)
        if theirs is not None and steps.size > 1:
            # whoever reaches a vacant vertex first does its job (§1.3): stepping on a
            # teammate's planned vertex would take it and break the plan for both
            clear = steps[~theirs[steps]]
            if clear.size:
                steps = clear
        return Decision("move", _pick(steps, rng), f, 3)


def _holders_on_time(belief: TraversalBelief, routes: np.ndarray, lens: np.ndarray) -> bool:
    """Whether every other agent with a route in the plan is, in the belief, still at work:
    not gone, and its announced next event still to come. An agent that stopped without
    being heard (a lost ``leave``) has an event in the past, so nobody leaves a vertex to it
    (``idle="stop"``)."""
    holders = np.nonzero(lens > 0)[0]
    holders = holders[holders != belief.me]
    return bool((belief.loc[holders] >= 0).all()
                and (belief.free_at[holders] > belief.now).all())


def _theirs(belief: TraversalBelief, routes: np.ndarray, lens: np.ndarray) -> np.ndarray:
    """A mask of the still vacant vertices planned for the agents other than ``me``."""
    cells = route_cells(lens, routes.shape[1])
    cells[belief.me] = False
    mask = np.zeros(belief.status.size, dtype=bool)
    mask[routes[cells]] = True
    return mask & (belief.status == 0)


POLICIES[MadgtaP.name] = MadgtaP
