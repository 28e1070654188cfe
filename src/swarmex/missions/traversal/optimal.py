"""The exact offline optimum of the traversal mission: a yardstick for MADGTA's gap.

MADGTA (seed 000) is online and greedy, and the thesis never compares it with an optimum.
When the thesis says "optimal" (spec §5) it only means "no extra travel". This module
computes the true optimum on small maps, with *full knowledge* (obstacles known in advance)
and central planning, so that MADGTA's distance to it is a measured number. It is a
baseline, not a policy: it reads the true world, which no mission policy may do.

Problem (seed 000 §3.1, with obstacles)
---------------------------------------
Agents start at their nests. Every free vertex reachable from a nest must get exactly one
job. Agent a's walk costs ``Σ_{v∈V'_a} J(a,v) + Σ_edges T(a,e)``, with ``J(a,v) = job_time_a``
and ``T(a,e) = length(e) · unit_length / travel_speed_a``. A walk may pass through a vertex
without doing its job there. A walk does not return: §3.1 has no return leg, and RTL is
``additional_time``. So a walk is fully described by the *order* of the agent's jobs,
joined by shortest paths. The problem is an **open, multi-depot, heterogeneous-fleet mTSP**
on the metric closure ``τ_a(i,j) = d(i,j) · unit_length / speed_a``, where ``d`` is the true
shortest-path length (:func:`swarmex.planning.distance.distance_field`, obstacles never
entered). Agents may share a nest, and an agent may do no job at all. With
``c_a(S) = τ_a · L(nest_a, S) + J_a · |S|`` the cheapest cost for agent a to do exactly the
jobs S (L is the shortest open path from the nest through S in the closure):

* ``"sum"`` minimises ``Σ_a c_a(S_a)`` over partitions ``(S_a)`` of the vertices. This is
  the thesis's objective, ``total_time_all``.
* ``"makespan"`` minimises ``max_a c_a(S_a)``. Among the plans with that makespan it then
  takes one of least sum, so the reported plan has no gratuitous detours.

Formulation "flow", the default for "sum": a compact MILP solved by HiGHS
--------------------------------------------------------------------------
Agents equal in (nest, speed, job time) form a class g of k_g agents. For "sum" they share
one set of variables and one start ``s_g``, a copy of their nest. This removes the k_g!
relabellings of every plan instead of merely ordering them. The arcs are ``s_g→j``,
``i→j`` and ``i→e``, where e is a common sink that means "stop here" (paths are open)::

    x[g,i,j] ∈ {0,1}   an agent of g goes from its job at i (or its start) to its job at j
    y[g,j]   ∈ {0,1}   an agent of g does the job at j
    F ≥ 0              single-commodity flow, aggregated over classes on job→job arcs

    Σ_g y[g,j] = 1                                 every vertex gets exactly one job
    Σ_i x[g,i,j] = y[g,j] = Σ_k x[g,j,k]           routes enter and leave their jobs
    Σ_j x[g,s_g,j] ≤ k_g                           at most k_g routes; other agents idle
    Σ_in F − Σ_out F = 1  at each job             each job consumes one unit of flow
    F[s_g,j] ≤ n·x[g,s_g,j],  Σ_g x[g,i,j] ≤ F[i,j] ≤ (n−1)·Σ_g x[g,i,j]
    min Σ_g Σ τ_g(i,j)·x[g,i,j] + J_g·Σ_j y[g,j]

Flow enters only at the starts. Each job has exactly one incoming arc, summed over all
classes. So a cycle of jobs detached from every start can receive no flow and cannot
satisfy conservation, and one aggregated flow is enough. For "makespan" every agent is its
own class with ``C_a ≤ T``. Identical agents then get ``Σ_j y[a,j] ≥ Σ_j y[b,j]``
(a < b), and ``min T`` is followed by the same least-sum pass.

On grids the LP bound of this model is usually already the optimum: 227 on the worked
example. HiGHS's time goes into *finding* a plan that reaches the bound. On the worked
example that took 5–25 s from a greedy start and under 1 s from an optimal one. The solve
therefore starts from a greedy dispatch improved by local search (:func:`_local_search`).

Formulation "partition", the default for "makespan": routes priced exactly, then a MILP
----------------------------------------------------------------------------------------
For n ≤ :data:`MAX_FREE_VERTICES`["makespan"], every subset can be priced. An open-path
Held–Karp per distinct nest (:func:`held_karp`, O(2ⁿ n²) in vectorised numpy, 0.4 s at
n = 16) gives ``c_a(S)`` for all 2ⁿ subsets. Agents equal in (nest, speed, job time) form a
class g of size k_g that shares its columns, which removes the symmetric copies of a plan::

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

Both formulations solve both objectives (``formulation=``). The tests check that they
agree with each other and with a brute force.

Size limit
----------
:data:`MAX_FREE_VERTICES` was measured on this machine (2 shared cores) with
``bench/gap_traversal_optimal.py --scaling``. The full table is in docs/traversal-optimal.md.

* "sum": 36. Every 6×6 grid fits, which is the thesis's smallest simulation grid. Among 76
  measured solves with n ≤ 36 (2–4 agents, with and without obstacles) the slowest took
  22 s. The first ones that were not proven within 60 s came at n = 44–56.
* "makespan": 16. Every 4×4 grid fits. At n = 16 the slowest solve took 9.5 s; one
  n = 18 instance was not proven within 60 s. The 2ⁿ tables and the column count double
  with each vertex.

Above the limit, :func:`solve_optimal` refuses with :class:`~swarmex.errors.InputError`,
which the CLI turns into exit status 2. Within it, a time-out still returns the best plan
found (the improved greedy one at worst), with ``proven_optimal`` false and the remaining
gap.

Timing
------
The offline optimum starts every agent at ``t = 0`` at its nest, with no takeoff and no
staggered start (the simulator starts clients 0.5 s apart, plus takeoff). Neither enters
``total_time``, which is travel + job time only.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import highspy
import numpy as np
from scipy import sparse

from swarmex.engine.record import AgentRecord, ResultRecord
from swarmex.errors import InputError
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.sim import validate_nests
from swarmex.planning.distance import distance_field, steps_towards

if TYPE_CHECKING:
    from swarmex.worlds.graph import GraphWorld
    from swarmex.worlds.grid import GridWorld
    from swarmex.worlds.nodegraph import NodeGraph

    World = GridWorld | GraphWorld

Objective = Literal["sum", "makespan"]
Formulation = Literal["auto", "partition", "flow"]

#: Most vertices needing a job that :func:`solve_optimal` accepts by default, per objective
#: (measured: docs/traversal-optimal.md). ``max_vertices`` overrides it knowingly.
MAX_FREE_VERTICES: dict[str, int] = {"sum": 36, "makespan": 16}

#: Hard ceiling of the partition formulation: its tables hold 2ⁿ·n floats.
_PARTITION_CEILING = 20

_REL = 1e-9  # relative tolerance when comparing costs computed along different float paths


@dataclass(frozen=True)
class AgentPlan:
    """One agent's share of the optimum: its job order, the walk doing them, and its times."""

    id: int  # 1-based, as in the simulator's logs
    spec: AgentSpec
    jobs: list[int]  # vertices where this agent does a job, in order
    walk: list[int]  # every vertex held, from the nest, along shortest paths
    travel_time: float
    job_time: float

    @property
    def total_time(self) -> float:
        return self.travel_time + self.job_time

    @property
    def moves(self) -> int:
        return len(self.walk) - 1


@dataclass(frozen=True)
class OptimalPlan:
    """Result of :func:`solve_optimal`.

    ``value`` is the objective of the returned plan, recomputed from the plan itself rather
    than taken from the solver's floating-point objective. ``bound`` is a proven lower bound
    on the optimum, and ``gap = (value − bound) / value``. ``proven_optimal`` is true only when
    the solver closed the primary objective.
    """

    objective: str
    formulation: str
    agents: list[AgentPlan]
    vertices: list[int]  # the vertices that needed a job (free, reachable from a nest)
    value: float
    bound: float
    gap: float
    proven_optimal: bool
    status: str
    solve_seconds: float
    secondary_status: str | None = None  # makespan: the least-sum pass at that makespan
    extra: dict = field(default_factory=dict)

    @property
    def total_time_all(self) -> float:
        return float(sum(a.total_time for a in self.agents))

    @property
    def makespan(self) -> float:
        return float(max(a.total_time for a in self.agents))


@dataclass
class _Instance:
    """The closure: n job vertices, their distances, and the agents' cost rates."""

    verts: list[int]
    dist: np.ndarray  # (n, n) shortest-path lengths in world length units
    nest_idx: list[int]  # each agent's nest as an index into verts
    tpu: np.ndarray  # seconds per length unit, per agent
    job: np.ndarray  # seconds per job, per agent
    classes: list[list[int]]  # agents equal in (nest, speed, job time), in index order

    @property
    def n(self) -> int:
        return len(self.verts)

    @property
    def m(self) -> int:
        return len(self.nest_idx)

    def route_cost(self, a: int, route: list[int]) -> float:
        seq = [self.nest_idx[a], *route]
        travel = sum(self.dist[i, j] for i, j in zip(seq, seq[1:], strict=False))
        return float(travel * self.tpu[a] + self.job[a] * len(route))


@dataclass
class _Outcome:
    """What a formulation returns: job orders (indices into verts) and the proof status."""

    routes: list[list[int]]
    bound: float
    proven: bool
    status: str
    secondary: str | None = None
    extra: dict = field(default_factory=dict)


# ------------------------------------------------------------------------------ HiGHS glue
@dataclass
class _MilpResult:
    status: str
    optimal: bool
    infeasible: bool
    x: np.ndarray | None
    bound: float


_FIRST_HIGHS = threading.Lock()
_banner_muted = False


def _highs() -> highspy.Highs:
    """A silent HiGHS instance.

    Why not ``highspy.Highs()`` then ``silent()``: the first instance in a process writes
    HiGHS's two-line banner ("Running HiGHS 1.16.0 ...") from C++ straight to file
    descriptor 1 while it is constructed, before any option can be set. That banner landed in
    a library user's stdout (and before the summary of ``swarmex traverse --algorithm
    optimal``, in a pipe too). So the first construction runs with descriptor 1 pointed at
    the null device for its few microseconds; later ones print nothing.
    """
    global _banner_muted
    with _FIRST_HIGHS:
        if _banner_muted:
            h = highspy.Highs()
        else:
            _banner_muted = True
            h = _muted(highspy.Highs)
    h.silent()
    return h


def _muted(make: Any) -> Any:
    """``make()`` with file descriptor 1 sent to the null device (as is, if it cannot be)."""
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError, AttributeError):
        return make()  # no descriptor 1 (a closed or replaced stdout): nothing to protect
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        return make()
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)


def _run_milp(
    cost: np.ndarray,
    a_mat: sparse.csc_matrix,
    row_lo: np.ndarray,
    row_hi: np.ndarray,
    col_hi: np.ndarray,
    n_int: int,
    time_limit: float,
    presolve: bool,
    start: np.ndarray | None = None,
) -> _MilpResult:
    """Solve ``min cost·x, row_lo ≤ A x ≤ row_hi, 0 ≤ x ≤ col_hi``; the first n_int integer.

    The relative gap is zero, so "optimal" means optimal to within HiGHS's absolute gap of
    1e-6 s. The default relative gap of 1e-4 could stop at a plan a few hundredths of a
    second worse, which would spoil a gap measured in per cent of a few hundred seconds.
    """
    n_col = a_mat.shape[1]
    inf = highspy.kHighsInf
    lp = highspy.HighsLp()
    lp.num_col_ = n_col
    lp.num_row_ = a_mat.shape[0]
    lp.col_cost_ = np.asarray(cost, dtype=np.float64)
    lp.col_lower_ = np.zeros(n_col)
    lp.col_upper_ = np.where(np.isfinite(col_hi), col_hi, inf).astype(np.float64)
    lp.row_lower_ = np.where(np.isfinite(row_lo), row_lo, -inf).astype(np.float64)
    lp.row_upper_ = np.where(np.isfinite(row_hi), row_hi, inf).astype(np.float64)
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = a_mat.indptr.astype(np.int32)
    lp.a_matrix_.index_ = a_mat.indices.astype(np.int32)
    lp.a_matrix_.value_ = a_mat.data.astype(np.float64)
    lp.integrality_ = [highspy.HighsVarType.kInteger] * n_int + [
        highspy.HighsVarType.kContinuous
    ] * (n_col - n_int)
    h = _highs()
    h.setOptionValue("random_seed", 0)
    h.setOptionValue("mip_rel_gap", 0.0)
    h.setOptionValue("mip_abs_gap", 1e-6)
    h.setOptionValue("time_limit", float(max(time_limit, 0.01)))
    if not presolve:
        h.setOptionValue("presolve", "off")
    h.passModel(lp)
    if start is not None:
        sol = highspy.HighsSolution()
        sol.col_value = [float(v) for v in start]
        sol.value_valid = True
        h.setSolution(sol)
    h.run()
    st = h.getModelStatus()
    info = h.getInfo()
    has_x = info.primal_solution_status == highspy.kSolutionStatusFeasible
    x = np.asarray(h.getSolution().col_value, dtype=float)[:n_col] if has_x else None
    return _MilpResult(
        status=h.modelStatusToString(st),
        optimal=st == highspy.HighsModelStatus.kOptimal,
        infeasible=st == highspy.HighsModelStatus.kInfeasible,
        x=x,
        bound=float(info.mip_dual_bound),
    )


# ------------------------------------------------------------------------ greedy incumbent
def _greedy(inst: _Instance, objective: str) -> list[list[int]]:
    """A feasible plan: repeatedly hand out the cheapest (agent, vertex) pair.

    For "sum" the cheapest pair is the smallest marginal cost; for "makespan" it is the
    earliest finish. This is what a dispatcher with full knowledge would do greedily. It
    gives the solvers an incumbent, so a time-out still returns a complete plan.
    """
    here = list(inst.nest_idx)
    clock = np.zeros(inst.m)
    routes: list[list[int]] = [[] for _ in range(inst.m)]
    left = list(range(inst.n))
    while left:
        best: tuple[float, int, int] | None = None
        for a in range(inst.m):
            step = inst.dist[here[a], left] * inst.tpu[a] + inst.job[a]
            key = clock[a] + step if objective == "makespan" else step
            k = int(np.argmin(key))
            if best is None or key[k] < best[0]:
                best = (float(key[k]), a, k)
        assert best is not None, "no agents"
        _, a, k = best
        v = left.pop(k)
        clock[a] += inst.dist[here[a], v] * inst.tpu[a] + inst.job[a]
        here[a] = v
        routes[a].append(v)
    return routes


def _path_length(dist: np.ndarray, seq: list[int]) -> float:
    return float(dist[seq[:-1], seq[1:]].sum()) if len(seq) > 1 else 0.0


def _local_search(
    inst: _Instance, routes: list[list[int]], max_steps: int = 500
) -> list[list[int]]:
    """Best-improvement descent on the sum objective: the incumbent the MILP starts from.

    Measured on the worked example (seed 000 §3.2.4), HiGHS's LP bound is already the
    optimum, 227. Almost all of its 5–25 s goes into finding a plan that reaches it, and from
    a plan of 227 it closes in under a second. Three classic moves find such plans. Moving a
    segment of 1–3 jobs, either way round, to any place in any route. Reversing part of a
    route (2-opt). Exchanging the tails of two routes, which moves a long stretch of jobs to
    another agent in one step. Every move is priced in O(1) or with one numpy expression
    over the insertion points.
    """
    d, tpu, job, m = inst.dist, inst.tpu, inst.job, inst.m
    routes = [list(r) for r in routes]
    for _ in range(max_steps):
        seqs = [[inst.nest_idx[a], *routes[a]] for a in range(m)]
        lens = [_path_length(d, s) for s in seqs]
        cost = [tpu[a] * lens[a] + job[a] * len(routes[a]) for a in range(m)]
        best_gain, best_new = 1e-9 * max(1.0, sum(cost)), None
        # 1. relocate a segment of 1-3 jobs, either orientation, anywhere
        for a in range(m):
            ra = routes[a]
            for k in range(len(ra)):
                for ln in (1, 2, 3):
                    if k + ln > len(ra):
                        break
                    seg = ra[k : k + ln]
                    rest = ra[:k] + ra[k + ln :]
                    rest_len = _path_length(d, [inst.nest_idx[a], *rest])
                    inner = _path_length(d, seg)
                    rest_cost = tpu[a] * rest_len + job[a] * len(rest)
                    for b in range(m):
                        base = rest if b == a else routes[b]
                        bseq = np.array([inst.nest_idx[b], *base])
                        blen = rest_len if b == a else lens[b]
                        old_b = 0.0 if b == a else cost[b]
                        gap = np.append(d[bseq[:-1], bseq[1:]], 0.0)
                        for s in (seg, seg[::-1]) if ln > 1 else (seg,):
                            after = np.append(d[s[-1], bseq[1:]], 0.0)
                            ins = d[bseq, s[0]] + inner + after - gap
                            p = int(np.argmin(ins))
                            new_b = tpu[b] * (blen + ins[p]) + job[b] * (len(base) + ln)
                            before = cost[a] + old_b
                            after_cost = new_b + (rest_cost if b != a else 0.0)
                            if before - after_cost > best_gain:
                                best_gain = before - after_cost
                                new = [list(r) for r in routes]
                                new[a] = rest
                                new[b] = list(base[:p]) + list(s) + list(base[p:])
                                best_new = new
        # 2. reverse part of a route (open path: the tail end has no successor)
        for a in range(m):
            sq = seqs[a]
            for i in range(1, len(sq)):
                for j in range(i + 1, len(sq)):
                    delta = d[sq[i - 1], sq[j]] - d[sq[i - 1], sq[i]]
                    if j + 1 < len(sq):
                        delta += d[sq[i], sq[j + 1]] - d[sq[j], sq[j + 1]]
                    if -tpu[a] * delta > best_gain:
                        best_gain = -tpu[a] * delta
                        new = [list(r) for r in routes]
                        new[a] = sq[1:i] + sq[i : j + 1][::-1] + sq[j + 1 :]
                        best_new = new
        # 3. exchange the tails of two routes
        pre = [np.concatenate([[0.0], np.cumsum(d[s[:-1], s[1:]])]) for s in seqs]
        for a in range(m):
            for b in range(a + 1, m):
                sa, sb = seqs[a], seqs[b]
                for i in range(1, len(sa) + 1):
                    for j in range(1, len(sb) + 1):
                        tail_a = pre[a][-1] - pre[a][i - 1] - (d[sa[i - 1], sa[i]] if i < len(sa)
                                                               else 0.0)
                        tail_b = pre[b][-1] - pre[b][j - 1] - (d[sb[j - 1], sb[j]] if j < len(sb)
                                                               else 0.0)
                        len_a = pre[a][i - 1] + (d[sa[i - 1], sb[j]] + tail_b if j < len(sb)
                                                 else 0.0)
                        len_b = pre[b][j - 1] + (d[sb[j - 1], sa[i]] + tail_a if i < len(sa)
                                                 else 0.0)
                        n_a = (i - 1) + (len(sb) - j)
                        n_b = (j - 1) + (len(sa) - i)
                        new_cost = tpu[a] * len_a + job[a] * n_a + tpu[b] * len_b + job[b] * n_b
                        if cost[a] + cost[b] - new_cost > best_gain:
                            best_gain = cost[a] + cost[b] - new_cost
                            new = [list(r) for r in routes]
                            new[a] = sa[1:i] + sb[j:]
                            new[b] = sb[1:j] + sa[i:]
                            best_new = new
        if best_new is None:
            break
        routes = best_new
    return routes


# ------------------------------------------------------------------ partition formulation
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


def _incumbent(inst: _Instance, objective: str) -> list[list[int]]:
    routes = _greedy(inst, objective)
    return _local_search(inst, routes) if objective == "sum" else routes


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


# ----------------------------------------------------------------------- flow formulation
@dataclass
class _FlowModel:
    """Column layout of the flow MILP, so that building, starts and decoding agree.

    Variables are per *group* of agents. For "sum", a group is a class of identical agents
    (same nest, speed, job time). Its ``k_g`` routes all leave one start node, which removes
    their symmetric relabellings, not just orders them. For "makespan" each agent is its own
    group, because the bound ``C_a ≤ T`` needs each route's cost separately.
    """

    n: int
    groups: list[list[int]]  # agent indices per group
    arcs: list[tuple[int, int]]  # per-group arcs; i == -1 is the start, j == n the sink
    y0: int  # y[g, j] at y0 + g*n + j; x[g, k] at g*len(arcs) + k
    f_cc: dict[tuple[int, int], int]  # aggregated flow on job→job arc (i, j)
    f_dep0: int  # F[s_g, j] at f_dep0 + g*n + j
    t_col: int  # the makespan column, or -1
    n_cols: int
    n_int: int

    def x(self, g: int, k: int) -> int:
        return g * len(self.arcs) + k

    def y(self, g: int, j: int) -> int:
        return self.y0 + g * self.n + j


def _flow_layout(n: int, groups: list[list[int]], makespan: bool) -> _FlowModel:
    arcs = [(-1, j) for j in range(n)]
    arcs += [(i, j) for i in range(n) for j in range(n) if i != j]
    arcs += [(i, n) for i in range(n)]
    n_groups = len(groups)
    y0 = n_groups * len(arcs)
    col = y0 + n_groups * n
    n_int = col
    f_cc = {}
    for i in range(n):
        for j in range(n):
            if i != j:
                f_cc[(i, j)] = col
                col += 1
    f_dep0 = col
    col += n_groups * n
    t_col = col if makespan else -1
    col += 1 if makespan else 0
    return _FlowModel(n, groups, arcs, y0, f_cc, f_dep0, t_col, col, n_int)


def _flow_matrix(
    mod: _FlowModel, inst: _Instance, arc_cost: np.ndarray
) -> tuple[sparse.csc_matrix, np.ndarray, np.ndarray]:
    """Rows of the flow model (module docstring), with ``arc_cost[g, k]`` finite."""
    n, n_groups = mod.n, len(mod.groups)
    rows: list[int] = []
    cols: list[int] = []
    vals: list[float] = []
    lo: list[float] = []
    hi: list[float] = []

    def row(entries: list[tuple[int, float]], lb: float, ub: float) -> None:
        r = len(lo)
        for c, v in entries:
            rows.append(r)
            cols.append(c)
            vals.append(v)
        lo.append(lb)
        hi.append(ub)

    arc_at = {arc: k for k, arc in enumerate(mod.arcs)}
    for j in range(n):
        row([(mod.y(g, j), 1.0) for g in range(n_groups)], 1.0, 1.0)
    for g, members in enumerate(mod.groups):
        for j in range(n):
            into = [arc_at[(i, j)] for i in range(-1, n) if i != j]
            out = [arc_at[(j, k)] for k in range(n + 1) if k != j]
            row([(mod.x(g, k), 1.0) for k in into] + [(mod.y(g, j), -1.0)], 0.0, 0.0)
            row([(mod.x(g, k), 1.0) for k in out] + [(mod.y(g, j), -1.0)], 0.0, 0.0)
        # at most one route per agent of the group leaves the start; the others stay idle
        row([(mod.x(g, arc_at[(-1, j)]), 1.0) for j in range(n)], 0.0, float(len(members)))
    for j in range(n):
        ent = [(mod.f_dep0 + g * n + j, 1.0) for g in range(n_groups)]
        ent += [(mod.f_cc[(i, j)], 1.0) for i in range(n) if i != j]
        ent += [(mod.f_cc[(j, k)], -1.0) for k in range(n) if k != j]
        row(ent, 1.0, 1.0)
    for (i, j), fc in mod.f_cc.items():
        xs = [mod.x(g, arc_at[(i, j)]) for g in range(n_groups)]
        row([(fc, 1.0)] + [(c, -(n - 1.0)) for c in xs], -np.inf, 0.0)
        row([(fc, 1.0)] + [(c, -1.0) for c in xs], 0.0, np.inf)
    for g in range(n_groups):
        for j in range(n):
            fc, xc = mod.f_dep0 + g * n + j, mod.x(g, arc_at[(-1, j)])
            row([(fc, 1.0), (xc, -float(n))], -np.inf, 0.0)
            row([(fc, 1.0), (xc, -1.0)], 0.0, np.inf)
    if mod.t_col >= 0:
        for g, (a,) in enumerate(mod.groups):
            ent = [(mod.x(g, k), float(arc_cost[g, k])) for k in range(len(mod.arcs))]
            ent += [(mod.y(g, j), float(inst.job[a])) for j in range(n)]
            row(ent + [(mod.t_col, -1.0)], -np.inf, 0.0)
        # identical agents, one group each: the earlier one does at least as many jobs
        group_of = {members[0]: g for g, members in enumerate(mod.groups)}
        for members in inst.classes:
            for a, b in zip(members, members[1:], strict=False):
                ga, gb = group_of[a], group_of[b]
                ent = [(mod.y(ga, j), 1.0) for j in range(n)]
                row(ent + [(mod.y(gb, j), -1.0) for j in range(n)], 0.0, np.inf)
    mat = sparse.csc_matrix((vals, (rows, cols)), shape=(len(lo), mod.n_cols))
    return mat, np.array(lo), np.array(hi)


def _flow_encode(mod: _FlowModel, inst: _Instance, routes: list[list[int]]) -> np.ndarray:
    sol = np.zeros(mod.n_cols)
    arc_at = {arc: k for k, arc in enumerate(mod.arcs)}
    for g, members in enumerate(mod.groups):
        for a in members:
            route = routes[a]
            seq = [-1, *route, mod.n] if route else []
            remaining = len(route)
            for i, j in zip(seq, seq[1:], strict=False):
                sol[mod.x(g, arc_at[(i, j)])] = 1.0
                if j < mod.n:
                    fc = mod.f_dep0 + g * mod.n + j if i < 0 else mod.f_cc[(i, j)]
                    sol[fc] = remaining
                    remaining -= 1
                    sol[mod.y(g, j)] = 1.0
            if mod.t_col >= 0:
                sol[mod.t_col] = max(sol[mod.t_col], inst.route_cost(a, route))
    return sol


def _flow_decode(mod: _FlowModel, x: np.ndarray) -> list[list[int]] | None:
    """Routes per agent from a solution, or None if it is not a set of simple paths."""
    routes: list[list[int]] = [[] for _ in range(sum(len(g) for g in mod.groups))]
    for g, members in enumerate(mod.groups):
        chosen = [arc for k, arc in enumerate(mod.arcs) if x[mod.x(g, k)] > 0.5]
        succ = {i: j for i, j in chosen if i >= 0}
        firsts = sorted(j for i, j in chosen if i < 0)
        if len(firsts) > len(members):
            return None
        for a, first in zip(members, firsts, strict=False):
            cur = first
            while cur != mod.n:
                if cur in routes[a] or cur not in succ:
                    return None
                routes[a].append(cur)
                cur = succ[cur]
    return routes


def _solve_flow(inst: _Instance, objective: str, deadline: float) -> _Outcome:
    makespan = objective == "makespan"
    groups = [[a] for a in range(inst.m)] if makespan else inst.classes
    mod = _flow_layout(inst.n, groups, makespan)
    arc_cost = np.zeros((len(groups), len(mod.arcs)))
    for g, (a, *_) in enumerate(groups):
        for k, (i, j) in enumerate(mod.arcs):
            if j < inst.n:
                arc_cost[g, k] = inst.dist[inst.nest_idx[a] if i < 0 else i, j] * inst.tpu[a]
    dead = ~np.isfinite(arc_cost)  # arcs into another component of the map: never usable
    arc_cost[dead] = 0.0
    mat, lo, hi = _flow_matrix(mod, inst, arc_cost)
    sum_cost = np.zeros(mod.n_cols)
    col_hi = np.ones(mod.n_cols)
    col_hi[mod.n_int :] = float(inst.n)
    for g, (a, *_) in enumerate(groups):
        xs = slice(mod.x(g, 0), mod.x(g, 0) + len(mod.arcs))
        sum_cost[xs] = arc_cost[g]
        col_hi[xs][dead[g]] = 0.0
        sum_cost[mod.y(g, 0) : mod.y(g, 0) + inst.n] = inst.job[a]
    routes = _incumbent(inst, objective)
    primary = sum_cost
    if makespan:
        primary = np.zeros(mod.n_cols)
        primary[mod.t_col] = 1.0
        col_hi[mod.t_col] = np.inf
    res = _run_milp(
        primary, mat, lo, hi, col_hi, mod.n_int, deadline - time.perf_counter(),
        presolve=True, start=_flow_encode(mod, inst, routes),
    )
    found = _flow_decode(mod, res.x) if res.x is not None else None
    if found is not None:
        routes = found
    bound = res.bound if np.isfinite(res.bound) else 0.0
    secondary = None
    left = deadline - time.perf_counter()
    if makespan and left > 0:
        best = max(inst.route_cost(a, r) for a, r in enumerate(routes))
        col_hi[mod.t_col] = best * (1 + _REL) + _REL
        res2 = _run_milp(
            sum_cost, mat, lo, hi, col_hi, mod.n_int, left, presolve=True,
            start=_flow_encode(mod, inst, routes),
        )
        secondary = res2.status
        cand = _flow_decode(mod, res2.x) if res2.x is not None else None
        if cand is not None and max(inst.route_cost(a, r) for a, r in enumerate(cand)) <= (
            best * (1 + _REL) + _REL
        ):
            routes = cand
    return _Outcome(routes, bound, res.optimal, res.status, secondary,
                    extra={"columns": mod.n_cols, "rows": int(mat.shape[0])})


# ------------------------------------------------------------------------------------- API
def _prepare(
    world: World, agents: list[AgentSpec], unit_length: float, max_vertices: int, objective: str
) -> tuple[_Instance, dict[int, np.ndarray]]:
    validate_nests(world, agents)
    graph = world.graph
    blocked = np.asarray(world.blocked, dtype=bool)
    nests = [int(s.nest) for s in agents]
    reach = np.isfinite(distance_field(graph, nests, blocked)) & ~blocked
    verts = [int(v) for v in np.nonzero(reach)[0]]
    if len(verts) > max_vertices:
        raise InputError(
            f"optimal: the map has {len(verts)} free vertices reachable from the nests; the "
            f"exact MILP for objective {objective!r} is limited to {max_vertices} "
            "(use madgta or nearest on larger maps)"
        )
    fields = {v: distance_field(graph, v, blocked) for v in verts}
    dist = np.array([[fields[u][v] for v in verts] for u in verts]).reshape(len(verts), -1)
    index = {v: i for i, v in enumerate(verts)}
    tpu = np.array([unit_length / s.travel_speed for s in agents], dtype=float)
    job = np.array([float(s.job_time) for s in agents])
    classes: dict[tuple, list[int]] = {}
    for a, s in enumerate(agents):
        classes.setdefault((s.nest, float(tpu[a]), float(job[a])), []).append(a)
    inst = _Instance(verts, dist, [index[v] for v in nests], tpu, job, list(classes.values()))
    return inst, fields


def _walk(
    graph: NodeGraph, blocked: np.ndarray, field_to_dst: np.ndarray, src: int, dst: int
) -> list[int]:
    """Vertices after ``src`` up to ``dst`` on a shortest path; lowest-index next hop."""
    path = []
    cur = src
    while cur != dst:
        hops = steps_towards(graph, field_to_dst, cur)
        cur = int(hops[~blocked[hops]].min())
        path.append(cur)
    return path


def solve_optimal(
    world: World,
    agents: list[AgentSpec],
    objective: Objective = "sum",
    unit_length: float = 1.0,
    time_limit: float = 60.0,
    *,
    formulation: Formulation = "auto",
    max_vertices: int | None = None,
) -> OptimalPlan:
    """Exact open multi-depot mTSP optimum of the traversal mission (see the module docstring).

    ``world`` is a :class:`~swarmex.worlds.GridWorld` or :class:`~swarmex.worlds.GraphWorld`.
    The vertices needing a job are the free vertices reachable from some nest.
    ``formulation="auto"`` uses the flow model for "sum" and the partition model for
    "makespan", the faster of the two in each case as measured. ``max_vertices`` defaults to
    :data:`MAX_FREE_VERTICES` for the objective.

    Raises :class:`InputError` for a bad objective or formulation, bad nests, or more than
    ``max_vertices`` such vertices. ``time_limit`` (seconds) bounds all solver calls
    together. If it runs out, the best plan found is returned with ``proven_optimal`` false.
    """
    if objective not in ("sum", "makespan"):
        raise InputError(f"optimal: objective must be 'sum' or 'makespan', got {objective!r}")
    if formulation not in ("auto", "partition", "flow"):
        raise InputError(
            f"optimal: formulation must be 'auto', 'partition' or 'flow', got {formulation!r}"
        )
    if not unit_length > 0:
        raise InputError(f"optimal: unit length must be > 0, got {unit_length}")
    if not time_limit > 0:
        raise InputError(f"optimal: time limit must be > 0, got {time_limit}")
    if formulation == "auto":
        formulation = "flow" if objective == "sum" else "partition"
    limit = MAX_FREE_VERTICES[objective] if max_vertices is None else int(max_vertices)
    if formulation == "partition":
        limit = min(limit, _PARTITION_CEILING)  # its 2ⁿ·n tables would not fit in memory
    t0 = time.perf_counter()
    inst, fields = _prepare(world, agents, unit_length, limit, objective)
    deadline = t0 + time_limit
    if formulation == "partition":
        out = _solve_partition(inst, objective, deadline)
    else:
        out = _solve_flow(inst, objective, deadline)

    graph = world.graph
    blocked = np.asarray(world.blocked, dtype=bool)
    plans = []
    for a, (spec, route) in enumerate(zip(agents, out.routes, strict=True)):
        jobs = [inst.verts[i] for i in route]
        walk = [int(spec.nest)]
        for v in jobs:
            walk += _walk(graph, blocked, fields[v], walk[-1], v)
        length = sum(graph.edge_length(u, v) for u, v in zip(walk, walk[1:], strict=False))
        plans.append(
            AgentPlan(a + 1, spec, jobs, walk, float(length * inst.tpu[a]),
                      float(inst.job[a] * len(jobs)))
        )
    totals = [p.total_time for p in plans]
    value = float(sum(totals)) if objective == "sum" else float(max(totals))
    bound = min(out.bound, value)
    if out.proven:
        bound = value  # the solver's bound equals the value up to its tolerances
    gap = 0.0 if value <= 0 else max(0.0, (value - bound) / value)
    return OptimalPlan(
        objective=objective,
        formulation=formulation,
        agents=plans,
        vertices=inst.verts,
        value=value,
        bound=float(bound),
        gap=float(gap),
        proven_optimal=out.proven,
        status=out.status,
        solve_seconds=time.perf_counter() - t0,
        secondary_status=out.secondary,
        extra=out.extra,
    )


# ----------------------------------------------------------------------------------- record
def plan_metrics(
    plan: OptimalPlan, world: World, unit_length: float = 1.0
) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """The traversal record's metrics for a plan, under MADGTA's names (metrics.py).

    ``nodes_traveled`` counts edge moves plus one when the agent's first job is at its nest,
    as :func:`~swarmex.missions.traversal.metrics.agent_metrics` does, so the two records
    compare column by column. ``additional_time`` is takeoff + RTL from the last vertex +
    landing. ``messages`` are 0 because a central offline plan sends none.
    """
    per_agent = []
    for p in plan.agents:
        spec = p.spec
        home = distance_field(world.graph, spec.nest, world.blocked)[p.walk[-1]]
        rtl = float(home) * unit_length / spec.travel_speed
        traveled = p.moves + (1 if p.jobs and p.jobs[0] == spec.nest else 0)
        per_agent.append({
            "nodes_done": len(p.jobs),
            "nodes_traveled": traveled,
            "nodes_without_job": traveled - len(p.jobs),
            "travel_time": p.travel_time,
            "job_time": p.job_time,
            "total_time": p.total_time,
            "additional_time": spec.takeoff_time + rtl + spec.landing_time,
            "failed_jobs": 0,
            "finished_at": p.total_time,
        })
    total_times = [m["total_time"] for m in per_agent]
    done = [v for p in plan.agents for v in p.jobs]
    totals = {
        "total_time_all": float(sum(total_times)),
        "nodes_without_job_all": int(sum(m["nodes_without_job"] for m in per_agent)),
        "nodes_done_all": len(done),
        "travel_time_all": float(sum(m["travel_time"] for m in per_agent)),
        "job_time_all": float(sum(m["job_time"] for m in per_agent)),
        "additional_time_all": float(sum(m["additional_time"] for m in per_agent)),
        "max_total_time": float(max(total_times)),
        "mission_end": float(max(total_times)),
        "reachable_nodes": len(plan.vertices),
        "nodes_missed": len(set(plan.vertices) - set(done)),
        "duplicate_jobs": len(done) - len(set(done)),
        "messages": 0,
        "message_bytes": 0,
        "objective_value": plan.value,
        "lower_bound": plan.bound,
        "mip_gap": plan.gap,
        "proven_optimal": plan.proven_optimal,
    }
    return totals, per_agent


def optimal_record(
    world: World,
    agents: list[AgentSpec],
    objective: Objective,
    seed: int,
    params: dict,
    unit_length: float = 1.0,
    time_limit: float = 60.0,
) -> ResultRecord:
    """Solve, then build the traversal :class:`ResultRecord` with algorithm ``"optimal"``.

    The schema and metric names are those of MADGTA's :func:`traversal_record`, so a sweep can
    set the two side by side. All agents start at ``t = 0``, with no staggered starts and no
    takeoff. Each trajectory lists every vertex held along the shortest-path walk with its
    arrival time, and each job its start time. ``seed`` is only recorded: the optimum uses no
    randomness.
    """
    plan = solve_optimal(world, agents, objective, unit_length, time_limit)
    totals, per_agent = plan_metrics(plan, world, unit_length)
    pos = world.graph.pos
    records = []
    for p, met in zip(plan.agents, per_agent, strict=True):
        tpu = unit_length / p.spec.travel_speed
        t = 0.0
        traj = [[t, *pos[p.walk[0]].tolist()]]
        jobs: list[list[float]] = []
        pending = list(p.jobs)
        if pending and pending[0] == p.walk[0]:
            jobs.append([t, *pos[p.walk[0]].tolist()])
            t += p.spec.job_time
            pending.pop(0)
        for u, v in zip(p.walk, p.walk[1:], strict=False):
            t += world.graph.edge_length(u, v) * tpu
            traj.append([t, *pos[v].tolist()])
            if pending and v == pending[0]:
                jobs.append([t, *pos[v].tolist()])
                t += p.spec.job_time
                pending.pop(0)
        records.append(AgentRecord(p.id, met, traj, jobs))
    return ResultRecord(
        mission="traversal",
        algorithm="optimal",
        params={**params, "objective": objective},
        seed=seed,
        world=world.describe(),
        complete=totals["nodes_missed"] == 0 and totals["duplicate_jobs"] == 0,
        makespan=totals["max_total_time"],
        time_unit="s",
        metrics=totals,
        agents=records,
        wall_seconds=plan.solve_seconds,
        extra={
            "solver": {
                "name": "HiGHS",
                "version": _highs().version(),
                "formulation": plan.formulation,
                "status": plan.status,
                "secondary_status": plan.secondary_status,
                "time_limit": time_limit,
                **plan.extra,
            }
        },
    )
