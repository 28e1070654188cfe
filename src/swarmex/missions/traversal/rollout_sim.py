"""``madgta-r``'s simulation: the rest of a mission under MADGTA, compiled, on one belief.

The rollout policy (:mod:`swarmex.missions.traversal.rollout`) and madgta-p's team plan
(:mod:`swarmex.missions.traversal.teamplan`) both run this simulation (:func:`_simulate`)
to compare candidates; it lives apart from the policy because it is a self-contained,
numba-compiled model of the mission, with its own state arrays and event loop, while the
policy only builds its inputs from the belief and reads its outcomes.

* **State from the belief only.** Done vertices, known obstacles and reservations
  (``status``, ``reserved``, ``known.blocked``); each known agent's last vertex ``loc``, the
  node it announced (``next_loc``: C05 next node, or C07 job node) and when it is next free
  (``free_at``, the eta C05/C07 carry). A rival whose announced node differs from its last
  vertex is moving there; one whose announced node holds its own job is working until
  ``free_at``; any other is free now. Unknown cells count as free (as MADGTA's own distances
  do), so the simulation does jobs on walls nobody has seen yet.
* **MADGTA in the simulation.** Branch 1 (my vertex is vacant: its job), branch 2 (max-min
  over the vacant neighbours, ties by the sum over rivals), branch 3 (the same over every
  vacant vertex, then one hop on a shortest path). Ties that MADGTA draws at random go to
  the lowest vertex id, so the simulation is deterministic: the same belief gives the same
  choice. Rivals are every agent whose position is known, finished ones included (as
  ``belief.rivals()``); an arrival does the job when the vertex is vacant and the agent
  announced it, or nobody reserved it (``TraversalBelief.job_on_arrival``). Events run in
  time order, ties by agent id.
* **Distances without a field per move.** Every distance the simulation needs is between an
  agent's vertex and a vertex vacant at the decision (candidates only ever are vacant
  vertices, and a hop towards a target is read from the target's row). So one hop-count row
  per vacant vertex (a breadth-first search on the known graph) serves every candidate and
  every simulated event; rows are cached across decisions while no obstacle is learnt.
* **The objective** of a simulated mission: its makespan (the latest time any agent ends
  its last job or move; ``free_at`` times are absolute) and its sum (the time every agent
  spends from now on, the thesis's ``total_time_all``). ``objective="lex"`` (default): among
  the candidates whose makespan is within ``tol`` of the best (default: one edge of the
  fastest known agent), the least sum; ``"makespan"``: the least makespan, ties by the sum;
  ``"mix"``: makespan + ``weight`` × sum / agents.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.planning.distance import _bfs_hops
from swarmex.planning.fieldcache import KnownGraph

#: agent modes of the simulation
ABSENT, FREE, MOVING, WORKING, FINISHED = -1, 0, 1, 2, 3
#: kinds of the deciding agent's options (returned by :func:`_options`)
FINISH, JOB, NEAR, FAR = 0, 1, 2, 3


@kernel(cache=True, nogil=True)
def _fill_rows(
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    verts: NDArray[np.int64], rows: NDArray[np.int64], table: NDArray[np.int32],
    queue: NDArray[np.int32],
) -> None:  # pragma: no cover - compiled
    """Hop counts from each ``verts[i]`` into ``table[rows[i]]`` (-1: unreachable)."""
    src = np.empty(1, dtype=np.int64)
    for i in range(verts.shape[0]):
        src[0] = verts[i]
        _bfs_hops(indptr, indices, blocked, src, table[rows[i]], queue)


@kernel(cache=True, nogil=True)
def _better(m1: float, s1: float, p1: int, m2: float, s2: float, p2: int) -> bool:
    """Algorithm 2's order: larger min, then larger sum, then (not random here) the lower
    tie rank ``p`` (the vertex id, or a seeded permutation of the ids)."""
    if not np.isfinite(m2) and m2 < 0:
        return True
    tol = 1e-9 * (1.0 + abs(m2)) if np.isfinite(m2) else 0.0
    if m1 > m2 + tol:
        return True
    if m1 < m2 - tol:
        return False
    tol = 1e-9 * (1.0 + abs(s2)) if np.isfinite(s2) else 0.0
    if s1 > s2 + tol:
        return True
    if s1 < s2 - tol:
        return False
    return p1 < p2


@kernel(cache=True, nogil=True)
def _key(
    v: int, a: int, table: NDArray[np.int32], row_of: NDArray[np.int64],
    loc: NDArray[np.int64], mode: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """(min, sum) over rivals of MADGTA's utility of vacant vertex ``v`` for agent ``a``
    (``-inf`` if ``a`` cannot reach it); with no rival, minus ``a``'s own cost."""
    row = table[row_of[v]]
    h = row[loc[a]]
    if h < 0:
        return -np.inf, -np.inf
    mine = h * step * tpu[a] + jt[a]
    lo = np.inf
    s = 0.0
    any_rival = False
    for r in range(1, loc.shape[0]):
        if r == a or mode[r] == ABSENT:
            continue
        any_rival = True
        hr = row[loc[r]]
        theirs = np.inf if hr < 0 else hr * step * tpu[r]
        u = theirs + jt[r] - mine
        if u < lo:
            lo = u
        s += u
    if not any_rival:
        return -mine, -mine
    return lo, s


@kernel(cache=True, nogil=True)
def _options(
    a: int, k: int, indptr: NDArray[np.int64], indices: NDArray[np.int32],
    blocked: NDArray[np.bool_], st: NDArray[np.int32], rs: NDArray[np.int32],
    vacant: NDArray[np.int64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    loc: NDArray[np.int64], mode: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, out: NDArray[np.int64], prio: NDArray[np.int64],
) -> tuple[int, int]:  # pragma: no cover - compiled
    """MADGTA's options for agent ``a``: (kind, count) with the best ``k`` candidates in
    ``out``, best first (branch 2: vacant neighbours; branch 3: vacant vertices)."""
    here = loc[a]
    if st[here] == 0 and (rs[here] == 0 or rs[here] == a):
        out[0] = here
        return JOB, 1
    mins = np.empty(k)
    sums = np.empty(k)
    c = 0
    for e in range(indptr[here], indptr[here + 1]):
        v = indices[e]
        if blocked[v] or st[v] != 0 or (rs[v] != 0 and rs[v] != a):
            continue
        lo, s = _key(v, a, table, row_of, loc, mode, tpu, jt, step)
        c = _insert(out, mins, sums, c, k, v, lo, s, prio)
    if c > 0:
        return NEAR, c
    c = _far_scan(a, k, 1, st, rs, vacant, table, row_of, loc, mode, tpu, jt, step, out,
                  mins, sums, prio)
    if c > 0:
        return FAR, c
    return FINISH, 0


@kernel(cache=True, nogil=True)
def _far_scan(
    a: int, k: int, min_hops: int, st: NDArray[np.int32], rs: NDArray[np.int32],
    vacant: NDArray[np.int64], table: NDArray[np.int32], row_of: NDArray[np.int64],
    loc: NDArray[np.int64], mode: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, out: NDArray[np.int64], mins: NDArray[np.float64],
    sums: NDArray[np.float64], prio: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Branch 3's candidates: the best ``k`` vacant vertices not in ``a``'s KM that ``a``
    reaches in ``min_hops`` hops or more, best first, into ``out``; returns how many."""
    here = loc[a]
    c = 0
    for i in range(vacant.shape[0]):
        v = vacant[i]
        if st[v] != 0 or (rs[v] != 0 and rs[v] != a):
            continue
        h = table[row_of[v], here]
        if h < min_hops:  # also -1: unreachable
            continue
        lo, s = _key(v, a, table, row_of, loc, mode, tpu, jt, step)
        c = _insert(out, mins, sums, c, k, v, lo, s, prio)
    return c


@kernel(cache=True, nogil=True)
def _insert(
    out: NDArray[np.int64], mins: NDArray[np.float64], sums: NDArray[np.float64], c: int,
    k: int, v: int, lo: float, s: float, prio: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Insert ``v`` into the best-first list of length ``c`` (at most ``k``)."""
    j = c
    while j > 0 and _better(lo, s, prio[v], mins[j - 1], sums[j - 1], prio[out[j - 1]]):
        j -= 1
    if j >= k:
        return c
    last = min(c, k - 1)
    for t in range(last, j, -1):
        out[t] = out[t - 1]
        mins[t] = mins[t - 1]
        sums[t] = sums[t - 1]
    out[j] = v
    mins[j] = lo
    sums[j] = s
    return min(c + 1, k)


@kernel(cache=True, nogil=True)
def _hop(
    here: int, f: int, indptr: NDArray[np.int64], indices: NDArray[np.int32],
    blocked: NDArray[np.bool_], table: NDArray[np.int32], row_of: NDArray[np.int64],
    prio: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """The neighbour of ``here`` of lowest tie rank on a shortest path to ``f``."""
    row = table[row_of[f]]
    want = row[here] - 1
    best = -1
    for e in range(indptr[here], indptr[here + 1]):
        v = indices[e]
        if not blocked[v] and row[v] == want and (best < 0 or prio[v] < prio[best]):
            best = v
    return best


@kernel(cache=True, nogil=True)
def _move(
    a: int, v: int, t: float, loc: NDArray[np.int64], dest: NDArray[np.int64],
    tfree: NDArray[np.float64], mode: NDArray[np.int64], intent: NDArray[np.int64],
    resv: NDArray[np.int64], st: NDArray[np.int32], rs: NDArray[np.int32],
    work: NDArray[np.float64], last: NDArray[np.float64], dt: float,
) -> None:  # pragma: no cover - compiled
    """Agent ``a`` sets off to neighbour ``v`` (C05): it reserves ``v`` if it intends to do
    its job there (``TraversalBelief.announce_move``)."""
    old = resv[a]
    if old >= 0:
        if rs[old] == a:
            rs[old] = 0
        resv[a] = -1
    if st[v] == 0 and (rs[v] == 0 or rs[v] == a):
        intent[a] = v
        rs[v] = a
        resv[a] = v
    else:
        intent[a] = -1
    dest[a] = v
    mode[a] = MOVING
    tfree[a] = t + dt
    work[a] += dt
    last[a] = tfree[a]


@kernel(cache=True, nogil=True)
def _start_job(
    a: int, v: int, t: float, tfree: NDArray[np.float64], mode: NDArray[np.int64],
    resv: NDArray[np.int64], st: NDArray[np.int32], rs: NDArray[np.int32],
    work: NDArray[np.float64], last: NDArray[np.float64], jt: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    st[v] = a
    holder = rs[v]
    if holder != 0:
        rs[v] = 0
        resv[holder] = -1
    mode[a] = WORKING
    tfree[a] = t + jt[a]
    work[a] += jt[a]
    last[a] = tfree[a]


@kernel(cache=True, nogil=True)
def _next_agent(
    mode: NDArray[np.int64], tfree: NDArray[np.float64],
) -> tuple[int, float]:  # pragma: no cover - compiled
    """The active agent with the earliest event (ties: lowest id), or -1."""
    a = -1
    t = np.inf
    for r in range(1, mode.shape[0]):
        if (mode[r] == FREE or mode[r] == MOVING or mode[r] == WORKING) and tfree[r] < t:
            t = tfree[r]
            a = r
    return a, t


@kernel(cache=True, nogil=True)
def _next_event(
    a: int, t: float,
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], vacant: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], loc: NDArray[np.int64],
    dest: NDArray[np.int64], tfree: NDArray[np.float64], mode: NDArray[np.int64],
    intent: NDArray[np.int64], resv: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, prio: NDArray[np.int64],
    work: NDArray[np.float64], last: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Agent ``a``'s arrival at its event time ``t``, if it was moving: the job there when it
    may (``TraversalAgent.arrive``; True), else nothing done yet (False: it decides)."""
    if mode[a] == MOVING:  # arrival (TraversalAgent.arrive)
        v = dest[a]
        loc[a] = v
        old = resv[a]
        if old >= 0:
            if rs[old] == a:
                rs[old] = 0
            resv[a] = -1
        if st[v] == 0 and (intent[a] == v or rs[v] == 0):
            intent[a] = -1
            _start_job(a, v, t, tfree, mode, resv, st, rs, work, last, jt)
            return True
        intent[a] = -1
    return False


@kernel(cache=True, nogil=True)
def _follow_target(
    a: int, t: float, target: NDArray[np.int64],
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], vacant: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], loc: NDArray[np.int64],
    dest: NDArray[np.int64], tfree: NDArray[np.float64], mode: NDArray[np.int64],
    intent: NDArray[np.int64], resv: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, prio: NDArray[np.int64],
    work: NDArray[np.float64], last: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """A committed target first: its job when the agent stands on a vacant vertex on the
    way, else one hop towards it (True); False when there is none (or it was taken)."""
    f = target[a]
    if f < 0:
        return False
    if f == loc[a] or st[f] != 0 or (rs[f] != 0 and rs[f] != a):
        target[a] = -1
        return False
    here = loc[a]
    if st[here] == 0 and (rs[here] == 0 or rs[here] == a):
        _start_job(a, here, t, tfree, mode, resv, st, rs, work, last, jt)
        return True
    v = _hop(here, f, indptr, indices, blocked, table, row_of, prio)
    _move(a, v, t, loc, dest, tfree, mode, intent, resv, st, rs, work, last, step * tpu[a])
    return True


@kernel(cache=True, nogil=True)
def _madgta_step(
    a: int, t: float, out: NDArray[np.int64],
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], vacant: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], loc: NDArray[np.int64],
    dest: NDArray[np.int64], tfree: NDArray[np.float64], mode: NDArray[np.int64],
    intent: NDArray[np.int64], resv: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, prio: NDArray[np.int64],
    work: NDArray[np.float64], last: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """MADGTA's decision for agent ``a`` (lowest-id ties): its job, a neighbour, one hop
    towards a distant target, or finished."""
    kind, c = _options(a, 1, indptr, indices, blocked, st, rs, vacant, table, row_of,
                       loc, mode, tpu, jt, step, out, prio)
    if kind == JOB:
        _start_job(a, loc[a], t, tfree, mode, resv, st, rs, work, last, jt)
    elif kind == NEAR:
        _move(a, out[0], t, loc, dest, tfree, mode, intent, resv, st, rs, work, last,
              step * tpu[a])
    elif kind == FAR:
        v = _hop(loc[a], out[0], indptr, indices, blocked, table, row_of, prio)
        _move(a, v, t, loc, dest, tfree, mode, intent, resv, st, rs, work, last,
              step * tpu[a])
    else:
        mode[a] = FINISHED


@kernel(cache=True, nogil=True)
def _outcome(
    cut: bool, mode: NDArray[np.int64], tfree: NDArray[np.float64],
    work: NDArray[np.float64], last: NDArray[np.float64], st: NDArray[np.int32],
    vacant: NDArray[np.int64], tpu: NDArray[np.float64], jt: NDArray[np.float64], step: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """(makespan, sum) of a simulated mission; when it was ``cut`` at the horizon, the rest
    is estimated (see :class:`MadgtaR`)."""
    m1 = mode.shape[0]
    makespan = 0.0
    total = 0.0
    for r in range(1, m1):
        if mode[r] != ABSENT:
            makespan = max(makespan, last[r])
            total += work[r]
    if cut:  # the rest: vacant jobs shared by the working agents
        left = 0
        for i in range(vacant.shape[0]):
            if st[vacant[i]] == 0:
                left += 1
        busy = 0.0
        rate = 0.0
        n_on = 0
        for r in range(1, m1):
            if mode[r] == FREE or mode[r] == MOVING or mode[r] == WORKING:
                busy += tfree[r]
                rate += jt[r] + step * tpu[r]
                n_on += 1
        if n_on > 0:
            per_job = rate / n_on
            makespan = max(makespan, (busy + left * per_job) / n_on)
            total += left * per_job
    return makespan, total


# what one simulated event was (:func:`_turn`)
EVENT, STOP, FOLLOWED, DECIDE = 0, 1, 2, 3


@kernel(cache=True, nogil=True)
def _take(
    a: int, f: int, kind: int, t: float, target: NDArray[np.int64],
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], table: NDArray[np.int32],
    row_of: NDArray[np.int64], loc: NDArray[np.int64], dest: NDArray[np.int64],
    tfree: NDArray[np.float64], mode: NDArray[np.int64], intent: NDArray[np.int64],
    resv: NDArray[np.int64], tpu: NDArray[np.float64], step: float, prio: NDArray[np.int64],
    work: NDArray[np.float64], last: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Agent ``a`` takes the candidate ``f`` a rollout chose: NEAR, move to that neighbour;
    FAR, commit to that target and make its first hop now."""
    if kind == FAR:
        target[a] = f
        f = _hop(loc[a], f, indptr, indices, blocked, table, row_of, prio)
    _move(a, f, t, loc, dest, tfree, mode, intent, resv, st, rs, work, last, step * tpu[a])


@kernel(cache=True, nogil=True)
def _begin(
    me: int, first: int, first_kind: int, now: float,
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], table: NDArray[np.int32],
    row_of: NDArray[np.int64], loc: NDArray[np.int64], dest: NDArray[np.int64],
    tfree: NDArray[np.float64], mode: NDArray[np.int64], intent: NDArray[np.int64],
    resv: NDArray[np.int64], tpu: NDArray[np.float64], step: float, prio: NDArray[np.int64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:  # pragma: no cover
    """A simulation's start: ``me`` takes its candidate ``first`` (NEAR: move to that
    neighbour; FAR: commit to that target, first hop now). Returns (work, last, target)."""
    m1 = loc.shape[0]
    work = np.zeros(m1)
    last = tfree.copy()
    target = np.full(m1, -1, dtype=np.int64)
    _take(me, first, first_kind, now, target, indptr, indices, blocked, st, rs, table, row_of,
          loc, dest, tfree, mode, intent, resv, tpu, step, prio, work, last)
    return work, last, target


@kernel(cache=True, nogil=True)
def _turn(
    a: int, t: float, over: bool, target: NDArray[np.int64],
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], vacant: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], loc: NDArray[np.int64],
    dest: NDArray[np.int64], tfree: NDArray[np.float64], mode: NDArray[np.int64],
    intent: NDArray[np.int64], resv: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, prio: NDArray[np.int64],
    work: NDArray[np.float64], last: NDArray[np.float64],
) -> int:  # pragma: no cover - compiled
    """Agent ``a``'s event at ``t`` up to its free decision: EVENT (an arrival that began a
    job; not a decision), STOP (a decision, but ``over`` the horizon), FOLLOWED (a decision
    taken by the committed target) or DECIDE (the caller decides)."""
    if _next_event(
        a, t,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
    ):
        return EVENT
    if over:
        return STOP
    if _follow_target(
        a, t, target,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
    ):
        return FOLLOWED
    return DECIDE


@kernel(cache=True, nogil=True)
def _simulate(
    me: int, first: int, first_kind: int, now: float, horizon: int,
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], vacant: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], loc: NDArray[np.int64],
    dest: NDArray[np.int64], tfree: NDArray[np.float64], mode: NDArray[np.int64],
    intent: NDArray[np.int64], resv: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, prio: NDArray[np.int64],
) -> tuple[float, float]:  # pragma: no cover - compiled
    """The rest of the mission with MADGTA everywhere, after ``me`` takes its candidate
    ``first`` (NEAR: move to that neighbour; FAR: head for that target until it is reached
    or taken). The state arrays are the caller's copies and are overwritten. Returns
    (makespan, sum): the latest end of any agent's job or move, and the time spent from now
    on summed over agents; after ``horizon`` decisions the rest is estimated (see
    :class:`MadgtaR`)."""
    work, last, target = _begin(me, first, first_kind, now, indptr, indices, blocked, st, rs,
                                table, row_of, loc, dest, tfree, mode, intent, resv, tpu,
                                step, prio)
    out = np.empty(1, dtype=np.int64)
    decisions = 0
    while True:
        a, t = _next_agent(mode, tfree)
        if a < 0:
            break
        turn = _turn(
            a, t, decisions >= horizon, target,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
        )
        if turn == EVENT:
            continue
        decisions += 1
        if turn == STOP:
            break
        if turn == FOLLOWED:
            continue
        _madgta_step(
            a, t, out,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
        )
    return _outcome(decisions > horizon, mode, tfree, work, last, st, vacant, tpu, jt, step)


@kernel(cache=True, nogil=True)
def _simulate_nested(
    me: int, first: int, first_kind: int, now: float, horizon: int,
    indptr: NDArray[np.int64], indices: NDArray[np.int32], blocked: NDArray[np.bool_],
    st: NDArray[np.int32], rs: NDArray[np.int32], vacant: NDArray[np.int64],
    table: NDArray[np.int32], row_of: NDArray[np.int64], loc: NDArray[np.int64],
    dest: NDArray[np.int64], tfree: NDArray[np.float64], mode: NDArray[np.int64],
    intent: NDArray[np.int64], resv: NDArray[np.int64], tpu: NDArray[np.float64],
    jt: NDArray[np.float64], step: float, prio: NDArray[np.int64], k: int, tol: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """:func:`_simulate` where every rival rolls out its first decision in the simulation
    (``k`` candidates, each simulated with :func:`_simulate`, chosen as ``objective='lex'``
    with ``tol``): one level of nesting, so the rivals are simulated as rollout agents for
    the next step instead of as MADGTA. (Its own loop rather than a flag of
    :func:`_simulate`, which it calls: compiled kernels cannot recurse.)"""
    work, last, target = _begin(me, first, first_kind, now, indptr, indices, blocked, st, rs,
                                table, row_of, loc, dest, tfree, mode, intent, resv, tpu,
                                step, prio)
    out = np.empty(1, dtype=np.int64)
    outk = np.empty(k, dtype=np.int64)
    nested = np.zeros(loc.shape[0], dtype=np.bool_)
    decisions = 0
    while True:
        a, t = _next_agent(mode, tfree)
        if a < 0:
            break
        turn = _turn(
            a, t, decisions >= horizon, target,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
        )
        if turn == EVENT:
            continue
        decisions += 1
        if turn == STOP:
            break
        if turn == FOLLOWED:
            continue
        if a != me and not nested[a]:
            nested[a] = True
            kind, c = _options(a, k, indptr, indices, blocked, st, rs, vacant, table,
                               row_of, loc, mode, tpu, jt, step, outk, prio)
            if kind in (NEAR, FAR) and c > 1:
                mks = np.empty(c)
                tots = np.empty(c)
                for j in range(c):
                    mks[j], tots[j] = _simulate(
                        a, outk[j], kind, t, horizon, indptr, indices, blocked, st.copy(),
                        rs.copy(), vacant, table, row_of, loc.copy(), dest.copy(),
                        tfree.copy(), mode.copy(), intent.copy(), resv.copy(), tpu, jt,
                        step, prio)
                lo = mks.min() + tol + 1e-9
                pick = -1
                for j in range(c):
                    if mks[j] <= lo and (pick < 0 or tots[j] < tots[pick] - 1e-9):
                        pick = j
                _take(a, outk[pick], kind, t, target, indptr, indices, blocked, st, rs,
                      table, row_of, loc, dest, tfree, mode, intent, resv, tpu, step, prio,
                      work, last)
                continue
        _madgta_step(
            a, t, out,
            indptr, indices, blocked, st, rs, vacant, table, row_of, loc, dest, tfree, mode,
            intent, resv, tpu, jt, step, prio, work, last,
        )
    return _outcome(decisions > horizon, mode, tfree, work, last, st, vacant, tpu, jt, step)


class _Rows:
    """Hop-count rows of the vacant vertices of one known graph, kept across decisions while
    its obstacles stay the same (a row depends only on them; vacant vertices only become
    fewer, so a row once made serves until the next obstacle)."""

    def __init__(self, known: KnownGraph) -> None:
        self.known = known  # held, so that its id is not reused while this cache lives
        n = known.graph.n_nodes
        self.version = -1
        self.table = np.empty((0, n), dtype=np.int32)
        self.row_of = np.full(n, -1, dtype=np.int64)
        self.used = 0
        self.queue = np.empty(n, dtype=np.int32)

    def get(self, vacant: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(table, row_of): ``table[row_of[v]]`` holds the hop counts from each ``v`` in
        ``vacant`` on the known graph (-1: unreachable)."""
        known = self.known
        if known.version != self.version:
            self.version = known.version
            self.row_of[:] = -1
            self.used = 0
        missing = vacant[self.row_of[vacant] < 0]
        if missing.size:
            if self.used + missing.size > self.table.shape[0]:
                # full: a new table with the rows still needed
                keep = vacant[self.row_of[vacant] >= 0]
                table = np.empty((max(2 * vacant.size, 64), self.row_of.size), dtype=np.int32)
                table[: keep.size] = self.table[self.row_of[keep]]
                self.row_of[:] = -1
                self.row_of[keep] = np.arange(keep.size)
                self.table = table
                self.used = keep.size
            rows = np.arange(self.used, self.used + missing.size, dtype=np.int64)
            g = known.graph
            _fill_rows(g.indptr, g.indices, known.blocked, missing, rows, self.table,
                       self.queue)
            self.row_of[missing] = rows
            self.used += missing.size
        return self.table, self.row_of
