"""The exact optimum's "partition" formulation: routes priced exactly, then a MILP over them.

For n ≤ :data:`~swarmex.missions.traversal.optimal.MAX_FREE_VERTICES`["makespan"], every
subset can be priced. An open-path Held–Karp per distinct nest (:func:`held_karp`,
O(2ⁿ n²) in vectorised numpy, 0.4 s at n = 16) gives ``c_a(S)`` for all 2ⁿ subsets. Agents
equal in (nest, speed, job time) form a class g of size k_g that shares its columns, which
removes the symmetric copies of a plan::

    z[g,S] ∈ {0,1}        some agent of class g does exactly the jobs S
    Σ_{g,S∋j} z[g,S] = 1  (partition)   or ≥ 1 (cover);   Σ_S z[g,S] ≤ k_g

The direct makespan model ``min T, Σ_S c·z ≤ T`` has a weak LP bound: HiGHS does not close
it in 60 s on 4×4 grids with 3 agents, and the flow model's ``min T, C_a ≤ T`` is no
better. The makespan is instead found exactly by **bisection over the candidate values**
``{c_g(S)}``. Each step asks a feasibility MILP. ``c`` is monotone: dropping a job never
lengthens a path in a metric closure. So the sets an agent can finish by T are closed under
taking subsets, and "makespan ≤ T is possible" becomes a *set cover* by the **maximal** such
sets. Any cover becomes a partition by giving each vertex to the first set that covers it.
Every feasible answer also lowers the upper end of the bisection to that plan's actual
makespan. A final partition MILP (``min Σ c·z`` over columns with ``c ≤ T*``) picks the
least-sum plan. HiGHS presolve is switched off for these models. It reduces nothing on
set-partitioning columns, yet it spent 35 s looking for dominated columns among 20 000.

It is the default for "makespan" (:func:`~swarmex.missions.traversal.optimal.solve_optimal`).
"""

from __future__ import annotations

import time

import numpy as np
from scipy import sparse

from swarmex.missions.traversal.optimal_highs import _MilpResult, _run_milp
from swarmex.missions.traversal.optimal_incumbent import _incumbent
from swarmex.missions.traversal.optimal_instance import _REL, _Instance, _Outcome


def held_karp(d0: np.ndarray, dist: np.ndarray) -> np.ndarray:
    """Open-path Held–Karp: ``g[S, j]`` is the shortest path from the start through S ending at j.

    ``d0[j]`` is the distance from the start to j, and ``dist`` the closure among the n
    vertices. ``g[S, j]`` is ``inf`` unless ``j ∈ S``. Layers of equal |S| are filled with
    one numpy operation per (|S|, j) pair, O(2ⁿ n²) work in all.
    """
    n = dist.shape[0]
    full = 1 << n
    g = np.full((full, n), np.inf)
    sets = np.arange(full)
    size = _popcount(sets, n)
    for j in range(n):
        g[1 << j, j] = d0[j]
    for k in range(2, n + 1):
        layer = sets[size == k]
        for j in range(n):
            ends = layer[(layer >> j) & 1 == 1]
            g[ends, j] = (g[ends ^ (1 << j)] + dist[:, j]).min(axis=1)
    return g


def _popcount(sets: np.ndarray, n: int) -> np.ndarray:
    size = np.zeros(sets.shape, dtype=np.int64)
    for j in range(n):
        size += (sets >> j) & 1
    return size


def _best_order(inst: _Instance, a: int, subset: int) -> list[int]:
    """An optimal job order for agent a over the vertex set ``subset`` (a bitmask).

    Held–Karp runs again on the subset alone and is then traced back. Ties go to the
    lowest vertex index, so the result is deterministic.
    """
    members = [j for j in range(inst.n) if subset >> j & 1]
    if not members:
        return []
    sub = inst.dist[np.ix_(members, members)]
    g = held_karp(inst.dist[inst.nest_idx[a], members], sub)
    mask = (1 << len(members)) - 1
    j = int(np.argmin(g[mask]))
    order = [j]
    while mask != 1 << j:
        prev = mask ^ (1 << j)
        j = int(np.argmin(g[prev] + sub[:, j]))
        mask = prev
        order.append(j)
    return [members[k] for k in reversed(order)]


def _class_costs(inst: _Instance) -> tuple[np.ndarray, np.ndarray]:
    """``c[g, S]`` for every class and subset (``c[g, ∅] = 0``), plus every subset's size."""
    full = 1 << inst.n
    size = _popcount(np.arange(full), inst.n)
    lengths: dict[int, np.ndarray] = {}
    for nest in sorted({inst.nest_idx[c[0]] for c in inst.classes}):
        path = held_karp(inst.dist[nest], inst.dist).min(axis=1)
        path[0] = 0.0
        lengths[nest] = path
    cost = np.empty((len(inst.classes), full))
    for g, members in enumerate(inst.classes):
        a = members[0]
        cost[g] = inst.tpu[a] * lengths[inst.nest_idx[a]] + inst.job[a] * size
    return cost, size


def _arrival_bounds(inst: _Instance) -> np.ndarray:
    """``lb_j``: every plan pays at least this for vertex j's job and its arrival there."""
    others = inst.dist + np.diag(np.full(inst.n, np.inf))
    nearest = others.min(axis=1) if inst.n > 1 else np.zeros(inst.n)
    arrival = np.where(np.isin(np.arange(inst.n), inst.nest_idx), 0.0, nearest)
    return inst.job.min() + inst.tpu.min() * arrival


def _columns(
    keep: np.ndarray, n: int
) -> tuple[np.ndarray, np.ndarray, sparse.csc_matrix]:
    """Column list (class, subset) and its incidence on the vertex and class rows."""
    col_g, col_s = np.nonzero(keep)
    k = col_g.size
    bits = (col_s[:, None] >> np.arange(n)) & 1 == 1
    cols, rows = np.nonzero(bits)
    n_class = keep.shape[0]
    r = np.concatenate([rows, n + col_g])
    c = np.concatenate([cols, np.arange(k)])
    a_mat = sparse.csc_matrix(
        (np.ones(r.size), (r, c)), shape=(n + n_class, k)
    )
    return col_g, col_s, a_mat


def _assign(inst: _Instance, picks: list[tuple[int, int]]) -> list[list[int]]:
    """Give chosen (class, subset) routes to the class's agents, in index order."""
    masks = [0] * inst.m
    taken = [0] * len(inst.classes)
    for g, s in sorted(picks):
        masks[inst.classes[g][taken[g]]] = s
        taken[g] += 1
    return [_best_order(inst, a, s) for a, s in enumerate(masks)]


def _partition_sum(
    inst: _Instance,
    cost: np.ndarray,
    size_cap: np.ndarray | None,
    incumbent: list[list[int]],
    time_limit: float,
) -> tuple[_MilpResult, list[tuple[int, int]], int]:
    """Least-sum partition among columns with ``cost ≤ size_cap[g]`` (all if None).

    Returns the solver result, the chosen (class, subset) columns and the model's column
    count. The incumbent's columns always stay in the model and start the search, so a
    time-out still yields a plan.
    """
    n = inst.n
    full = 1 << n
    lb = _arrival_bounds(inst)
    sets = np.arange(full)
    inside = np.zeros(full)
    for j in range(n):
        inside += ((sets >> j) & 1) * lb[j]
    rest = lb.sum() - inside
    inc_masks = [sum(1 << v for v in r) for r in incumbent]
    ub = sum(inst.route_cost(a, r) for a, r in enumerate(incumbent))
    keep = cost + rest[None, :] <= ub * (1 + _REL) + _REL
    if size_cap is not None:
        keep &= cost <= size_cap[:, None]
    keep[:, 0] = False
    cls_of = np.empty(inst.m, dtype=int)
    for g, members in enumerate(inst.classes):
        cls_of[members] = g
    for a, s in enumerate(inc_masks):  # the incumbent's own columns always stay
        if s:
            keep[cls_of[a], s] = True
    col_g, col_s, a_mat = _columns(keep, n)
    k = col_g.size
    counts = np.array([len(c) for c in inst.classes], dtype=float)
    row_lo = np.concatenate([np.ones(n), np.zeros(len(inst.classes))])
    row_hi = np.concatenate([np.ones(n), counts])
    position = {(int(g), int(s)): i for i, (g, s) in enumerate(zip(col_g, col_s, strict=True))}
    start = np.zeros(k)
    for a, s in enumerate(inc_masks):
        if s:
            start[position[(int(cls_of[a]), s)]] = 1.0
    res = _run_milp(
        cost[col_g, col_s], a_mat, row_lo, row_hi, np.ones(k), k, time_limit,
        presolve=False, start=start,
    )
    x = res.x if res.x is not None else start
    picks = [(int(col_g[i]), int(col_s[i])) for i in np.nonzero(x > 0.5)[0]]
    return res, picks, k


def _maximal(ok: np.ndarray, n: int) -> np.ndarray:
    """Subsets in the down-closed family ``ok`` to which no vertex can be added."""
    sets = np.arange(ok.size)
    out = ok.copy()
    for j in range(n):
        free = (sets >> j) & 1 == 0
        out[free] &= ~ok[sets[free] | (1 << j)]
    return out


def _cover_to_partition(picks: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Give each vertex to the first chosen set covering it (monotone costs: no worse)."""
    used = 0
    out = []
    for g, s in sorted(picks):
        s &= ~used
        used |= s
        out.append((g, s))
    return out


def _solve_partition(inst: _Instance, objective: str, deadline: float) -> _Outcome:
    cost, _ = _class_costs(inst)
    greedy = _incumbent(inst, objective)
    counts = np.array([len(c) for c in inst.classes], dtype=float)
    if objective == "sum":
        res, picks, k = _partition_sum(inst, cost, None, greedy, deadline - time.perf_counter())
        routes = _assign(inst, picks)
        bound = res.bound if np.isfinite(res.bound) else 0.0
        return _Outcome(routes, bound, res.optimal, res.status, extra={"columns": k})

    # makespan: bisection over the candidate values with a set-cover feasibility MILP
    routes = [list(r) for r in greedy]
    best = max(inst.route_cost(a, r) for a, r in enumerate(routes))
    values = np.unique(cost[cost <= best * (1 + _REL) + _REL])
    lo, hi = 0, int(np.searchsorted(values, best * (1 - _REL) - _REL))
    hi = min(hi, values.size - 1)
    status = "Optimal"
    solves = 0
    n = inst.n
    while lo < hi:
        left = deadline - time.perf_counter()
        if left <= 0:
            status = "Time limit reached"
            break
        mid = (lo + hi) // 2
        t = values[mid] * (1 + _REL) + _REL
        ok = cost <= t
        keep = np.stack([_maximal(ok[g], n) for g in range(len(inst.classes))])
        keep[:, 0] = False
        col_g, col_s, a_mat = _columns(keep, n)
        k = col_g.size
        if np.bitwise_or.reduce(col_s, initial=0) != (1 << n) - 1:
            lo = mid + 1  # some vertex is in no set any agent can finish by t
            continue
        row_lo = np.concatenate([np.ones(n), np.zeros(len(inst.classes))])
        row_hi = np.concatenate([np.full(n, np.inf), counts])
        res = _run_milp(
            np.zeros(k), a_mat, row_lo, row_hi, np.ones(k), k, left, presolve=False
        )
        solves += 1
        if res.infeasible:
            lo = mid + 1
        elif res.x is not None:
            chosen = [(int(col_g[i]), int(col_s[i])) for i in np.nonzero(res.x > 0.5)[0]]
            routes = _assign(inst, _cover_to_partition(chosen))
            best = max(inst.route_cost(a, r) for a, r in enumerate(routes))
            hi = min(mid, int(np.searchsorted(values, best * (1 - _REL) - _REL)))
        else:
            status = res.status
            break
    proven = lo >= hi and status == "Optimal"
    bound = float(values[lo]) if values.size else 0.0

    # secondary: the least-sum plan among those within the makespan found
    secondary = None
    left = deadline - time.perf_counter()
    if left > 0:
        cap = np.full(len(inst.classes), best * (1 + _REL) + _REL)
        res, picks, _ = _partition_sum(inst, cost, cap, routes, left)
        secondary = res.status
        cand = _assign(inst, picks)
        cand_best = max(inst.route_cost(a, r) for a, r in enumerate(cand))
        if cand_best <= best * (1 + _REL) + _REL:
            routes = cand
    return _Outcome(routes, bound, proven, status, secondary, extra={"bisection_solves": solves})
