"""The analysis of ``swarmex reproduce roadmap``: Tables 1–2 beside the paper's, and ours.

Pure post-processing of the run journal: per table row the mean ± SD coverage (Table 1) or
the success rate (Table 2) of each planner next to the paper's numbers, the takeover
improvement, and the unreachable-goal runs of Figs. 14–17.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from swarmex.engine.stats import (
    mean_difference_ci,
    proportion_difference_ci,
    summarize,
    wilson_ci,
)


def pick(results: Iterable[dict[str, Any]], **want: Any) -> list[dict[str, Any]]:
    return [r for r in results if all(r.get(k) == v for k, v in want.items())]


def row_key(row: dict[str, str], exp: str) -> dict[str, Any]:
    """What the runs of reference table row ``row`` in experiment ``exp`` share, as
    :func:`pick` matches them (the table's strings in the journal's types): one spelling for
    every table, so a row never picks another row's runs."""
    return {"exp": exp, "nodes": int(row["nodes"]), "step": float(row["step"]),
            "mult": row["sensor_range"]}


def mean_sd(vals: list[float]) -> tuple[float, float]:
    """Mean and sample SD (the SD NaN for one value, both for none): cells "mean ± sd"."""
    s = summarize(vals)
    return s.mean, s.std


def table1(results: list[dict[str, Any]], ref: list[dict[str, str]],
           exp: str = "t1") -> list[dict[str, Any]]:
    rows = []
    for row in ref:
        key = row_key(row, exp)
        cell = {}
        for planner in ("wma-rrt", "prm"):
            runs = pick(results, planner=planner, **key)
            cell[planner] = mean_sd([100 * r["coverage"] for r in runs]) + (len(runs),)
        prm_runs = pick(results, planner="prm", **key)
        rows.append({
            "nodes": key["nodes"], "step": int(key["step"]), "sensor": row["sensor_range"],
            "paper_wma": float(row["wma_rrt_coverage_pct"]),
            "ours_wma": cell["wma-rrt"][0], "ours_wma_sd": cell["wma-rrt"][1],
            "paper_prm": float(row["prm_coverage_pct"]),
            "ours_prm": cell["prm"][0], "ours_prm_sd": cell["prm"][1],
            "runs": cell["wma-rrt"][2],
            "prm_components": mean_sd([r["components"] for r in prm_runs])[0],
        })
    return rows


def table2(results: list[dict[str, Any]], ref: list[dict[str, str]],
           exp: str = "t2") -> list[dict[str, Any]]:
    rows = []
    for row in ref:
        key = row_key(row, exp)
        out: dict[str, Any] = {"nodes": key["nodes"], "step": int(key["step"]),
                               "sensor": row["sensor_range"],
                               "paper_wma": float(row["wma_rrt_success_pct"]),
                               "paper_prm": float(row["prm_success_pct"])}
        for planner, name in (("wma-rrt", "wma"), ("prm", "prm")):
            runs = pick(results, planner=planner, **key)
            k = sum(bool(r["goal_found"]) for r in runs)
            out[f"ours_{name}"] = 100.0 * k / len(runs) if runs else float("nan")
            out[f"found_{name}"] = k
            out["runs"] = len(runs)
        rows.append(out)
    return rows


def nanmean(values: Iterable[float]) -> float:
    a = np.asarray(list(values), dtype=float)
    a = a[~np.isnan(a)]
    return float(a.mean()) if len(a) else float("nan")


def mae(rows: list[dict[str, Any]], planner: str = "wma") -> float:
    """Mean |ours − paper| of one planner's column over ``rows`` (NaN cells skipped)."""
    return nanmean(np.abs([r[f"ours_{planner}"] - r[f"paper_{planner}"] for r in rows]))


def gain_summary(rows: list[dict[str, Any]]) -> dict[str, float]:
    ours = np.array([r["ours_wma"] - r["ours_prm"] for r in rows])
    paper = np.array([r["paper_wma"] - r["paper_prm"] for r in rows])
    return {
        "ours_ge": int((ours >= -1e-9).sum()), "paper_ge": int((paper >= 0).sum()),
        "ours_mean": nanmean(ours), "paper_mean": float(paper.mean()),
        "mae_wma": mae(rows), "mae_prm": mae(rows, "prm"),
        "n": len(rows),
    }


def improvement(results: list[dict[str, Any]]) -> tuple[list[dict[str, Any]], list[dict]]:
    cov: list[dict[str, Any]] = []
    srch: list[dict[str, Any]] = []
    for exp, target in (("t1", cov), ("t2", srch)):
        configs = sorted({(r["nodes"], r["step"]) for r in results if r["exp"] == exp},
                         key=lambda c: (c[1], c[0]))
        for nodes, step in configs:
            row: dict[str, Any] = {"nodes": nodes, "step": int(step)}
            for planner, name in (("wma-rrt", "base"), ("wma-rrt-takeover", "takeover")):
                runs = pick(results, exp=exp, planner=planner, nodes=nodes, step=step, mult="r")
                row[f"runs_{name}"] = len(runs)
                if exp == "t1":
                    row[f"steps_{name}"] = mean_sd([r["steps"] for r in runs])[0]
                    row[f"path_{name}"] = mean_sd([r["path_length"] for r in runs])[0]
                    row[f"revisits_{name}"] = mean_sd([r["edge_revisits"] for r in runs])[0]
                else:
                    found = [r for r in runs if r["goal_found"]]
                    row[f"success_{name}"] = 100.0 * len(found) / len(runs) if runs else np.nan
                    row[f"found_{name}"] = mean_sd([r["found_step"] for r in found])[0]
                    row[f"all_{name}"] = mean_sd([r["all_at_goal_step"] for r in found])[0]
            if row["runs_base"] and row["runs_takeover"]:
                target.append(row)
    return cov, srch


def unreachable(results: list[dict[str, Any]]) -> list[dict[str, Any]]:
    rows = []
    for env in ("fig14", "fig17"):
        for planner in ("wma-rrt", "wma-rrt-takeover", "prm", "ompl-prm"):
            runs = pick(results, exp="unreach", env=env, planner=planner)
            if not runs:
                continue
            rows.append({
                "env": env, "planner": planner, "runs": len(runs),
                "found": sum(bool(r["goal_found"]) for r in runs),
                "unreachable": sum(bool(r["goal_unreachable"]) for r in runs),
                "complete": sum(bool(r["complete"]) for r in runs),
                "budget": sum(bool(r["budget_exhausted"]) for r in runs),
                "steps": mean_sd([r["steps"] for r in runs])[0],
                "revisits": mean_sd([r["edge_revisits"] for r in runs])[0],
                "components": mean_sd([r["components"] for r in runs])[0],
                "cycles": mean_sd([r["cycles"] for r in runs])[0],
                "off": sum(int(r.get("agents_off_roadmap") or 0) > 0 for r in runs),
                "coverage": mean_sd([100 * r["coverage"] for r in runs])[0],
            })
    return rows


VERSUS = ("wma-rrt", "prm", "ompl-prm")  # the planners the per-row comparison puts side by side
EQUAL = "ompl-prm@wma-travel"  # OMPL's PRM stopped where WMA-RRT's team had walked as far


def at_travel(effort: list[list[float]], walked: float) -> float:
    """Coverage of a run when its team had walked ``walked`` units (its ``effort`` curve of
    ``[path, coverage]``, linearly interpolated; its final coverage if it never walked as
    far)."""
    e = np.asarray(effort, dtype=np.float64).reshape(-1, 2)
    return float(np.interp(walked, e[:, 0], e[:, 1]))


def _winner(cells: dict[str, dict[str, Any]],
            diff: Callable[[str, str], tuple[float, float, float]]) -> str:
    """The planner whose mean is highest, if its lead over the runner-up is significant (the
    95 % interval of the difference excludes 0); else ``"tie: a ≈ b"``."""
    ranked = sorted((p for p in cells if cells[p]["n"]), key=lambda p: -cells[p]["mean"])
    if len(ranked) < 2:
        return ranked[0] if ranked else "–"
    best, second = ranked[0], ranked[1]
    _, low, _ = diff(best, second)
    return best if low > 0 else f"tie: {best} ≈ {second}"


def _difference(cells: dict[str, dict[str, Any]], values: dict[str, list[float]] | None,
                a: str, b: str) -> tuple[float, float, float]:
    """Planner ``a`` − planner ``b`` with its 95 % interval, in points: coverage values
    (Welch) when ``values`` are given, else goal-found rates (Newcombe)."""
    if values is not None:
        return mean_difference_ci(values[a], values[b])
    d = proportion_difference_ci(cells[a]["k"], cells[a]["n"], cells[b]["k"], cells[b]["n"])
    return (100.0 * d[0], 100.0 * d[1], 100.0 * d[2])


def versus(results: list[dict[str, Any]], ref: list[dict[str, str]],
           exp: str) -> list[dict[str, Any]]:
    """Per table row: each planner of :data:`VERSUS` with its 95 % interval over the seeds
    (coverage: Student's t on the mean; goal found: Wilson on the rate), the winner (a lead
    whose difference interval — Welch / Newcombe — excludes 0) and WMA-RRT − OMPL PRM with
    its interval (the paper's claim: WMA-RRT at least as good as PRM)."""
    coverage = exp.startswith("t1")
    rows = []
    for row in ref:
        key = row_key(row, exp)
        runs = {p: pick(results, planner=p, **key) for p in VERSUS}
        cells: dict[str, dict[str, Any]] = {}
        values: dict[str, list[float]] = {}
        for p, rs in runs.items():
            if coverage:
                values[p] = [100.0 * r["coverage"] for r in rs]
                s = summarize(values[p])
                cells[p] = {"n": s.n, "mean": s.mean, "low": s.ci_low, "high": s.ci_high}
            else:
                k = sum(bool(r["goal_found"]) for r in rs)
                lo, hi = wilson_ci(k, len(rs))
                cells[p] = {"n": len(rs), "k": k,
                            "mean": 100.0 * k / len(rs) if rs else float("nan"),
                            "low": 100.0 * lo, "high": 100.0 * hi}
            cells[p]["path"] = mean_sd([r["path_length"] for r in rs])[0]
        if coverage and cells["wma-rrt"]["n"] and runs["ompl-prm"]:
            # OMPL's walkers step farther: its coverage when its team had walked as far as
            # WMA-RRT's team did in all (mean over this row's WMA-RRT runs)
            walked = cells["wma-rrt"]["path"]
            values[EQUAL] = [100.0 * at_travel(r["effort"], walked)
                             for r in runs["ompl-prm"] if r.get("effort")]
            s = summarize(values[EQUAL])
            cells[EQUAL] = {"n": s.n, "mean": s.mean, "low": s.ci_low, "high": s.ci_high,
                            "path": walked}
        diff = functools.partial(_difference, cells, values if coverage else None)
        out: dict[str, Any] = {"nodes": key["nodes"], "step": int(key["step"]),
                               "sensor": row["sensor_range"], "cells": cells,
                               "winner": _winner({p: cells[p] for p in VERSUS}, diff)}
        if cells["wma-rrt"]["n"] and cells["ompl-prm"]["n"]:
            out["wma_minus_ompl"] = diff("wma-rrt", "ompl-prm")
        if cells.get(EQUAL, {}).get("n"):
            out["wma_minus_ompl_equal"] = diff("wma-rrt", EQUAL)
        rows.append(out)
    return rows
