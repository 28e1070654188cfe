"""A proven floor on two mean gaps at once: the least mean sum gap under a makespan budget.

Issue 17 asks one method for a mean sum gap ≤ 8 % *and* a mean makespan gap ≤ 2 % on the
mixed-agent gap instances. Whether any plan at all can do both is a question about the
optimum's own trade-off, answered here from exact solves, without trusting a heuristic.

Input, per instance: caps ``c_1 < … < c_m`` (makespan at most ``c × optimal``) and, for
each, a *lower bound* ``L(c)`` on the least sum gap of the plans within that cap (a proven
MILP optimum, or the MILP's dual bound when a solve timed out; both are valid). A plan whose
makespan ratio r lies in ``(c_j, c_{j+1}]`` has a makespan gap above ``c_j − 1`` and a sum gap
of at least ``L(c_{j+1})``, because the least sum only falls as the cap grows. Beyond the
last cap nothing is known but sum gap ≥ 0. So each instance offers the points
``(0, L(c_1)), (c_1 − 1, L(c_2)), …, (c_m − 1, 0)`` that lie on or below its true frontier.

A method's mean over instances (and over seeds, which only mixes plans on one instance) is a
convex combination of one plan per instance and run. The least mean sum gap reachable with a
mean makespan gap ≤ budget is therefore at least the value of the linear program that
mixes each instance's points with weights summing to one. If that value exceeds the target,
no method, online or offline, meets both targets. The LP relaxes the problem (it allows
any mix), which only makes the floor lower, never wrong.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.optimize import linprog

from swarmex.errors import InputError


def staircase(caps: Sequence[float], floors: Sequence[float]) -> list[tuple[float, float]]:
    """The (makespan gap, sum gap) points that lie on or below one instance's frontier.

    ``floors[j]`` is a lower bound on the least sum gap of plans with makespan at most
    ``caps[j]`` × optimal; caps ascend and start at ≥ 1."""
    c = np.asarray(caps, dtype=float)
    f = np.asarray(floors, dtype=float)
    if c.size == 0 or c.size != f.size:
        raise InputError("pareto: need one floor per cap, and at least one cap")
    if np.any(np.diff(c) <= 0) or c[0] < 1.0:
        raise InputError("pareto: caps must ascend and start at 1 or above")
    lows = np.concatenate([[1.0], c]) - 1.0  # makespan gap just above the previous cap
    sums = np.concatenate([np.maximum(f, 0.0), [0.0]])  # the floor of the next cap
    return [(float(m), float(s)) for m, s in zip(lows, sums, strict=True)]


def least_mean_sum_gap(points: Sequence[Sequence[tuple[float, float]]], budget: float) -> float:
    """The least mean sum gap over instances with a mean makespan gap ≤ ``budget``.

    ``points[i]`` is instance i's :func:`staircase`. The value is a lower bound for any
    method whose per-instance plans lie on or above those staircases."""
    if not points:
        raise InputError("pareto: no instances")
    n_inst = len(points)
    cost, spend, rows = [], [], []
    for i, pts in enumerate(points):
        for m, s in pts:
            cost.append(s / n_inst)
            spend.append(m / n_inst)
            rows.append(i)
    n_var = len(cost)
    a_eq = np.zeros((n_inst, n_var))
    a_eq[rows, np.arange(n_var)] = 1.0
    res = linprog(
        np.asarray(cost), A_ub=np.asarray([spend]), b_ub=[budget], A_eq=a_eq,
        b_eq=np.ones(n_inst), bounds=(0.0, None), method="highs",
    )
    if res.status == 2:
        raise InputError(f"pareto: no mix reaches a mean makespan gap of {budget}")
    if not res.success or res.fun is None:
        raise RuntimeError(f"pareto: the LP failed: {res.message}")
    return float(res.fun)
