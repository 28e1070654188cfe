"""HiGHS glue for the exact optimum: one MILP call with the settings every model needs.

Both formulations (:mod:`~swarmex.missions.traversal.optimal_flow`,
:mod:`~swarmex.missions.traversal.optimal_partition`) hand a sparse model to
:func:`_run_milp`, which fixes the gaps, the seed and the time limit the same way for all,
and :func:`_highs` keeps HiGHS's start-up banner out of the caller's stdout. Apart from the
models so that the solver's API is touched in one place.
"""

from __future__ import annotations

import os
import sys
import threading
from dataclasses import dataclass
from typing import Any

import highspy
import numpy as np
from scipy import sparse


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
