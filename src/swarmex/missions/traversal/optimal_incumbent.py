"""The exact optimum's starting plan: a greedy dispatch, improved by local search for "sum".

Every solve starts from this incumbent, so a time-out still returns a complete plan, and a
good start is what makes the flow model fast (HiGHS's bound is usually already the optimum;
its time goes into finding a plan that reaches it). Kept apart from the formulations, which
both use it.
"""

from __future__ import annotations

import numpy as np

from swarmex.missions.traversal.optimal_instance import _Instance


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


def _incumbent(inst: _Instance, objective: str) -> list[list[int]]:
    routes = _greedy(inst, objective)
    return _local_search(inst, routes) if objective == "sum" else routes
