"""The analysis of ``swarmex reproduce exploration``: the thesis's stated trends, checked.

Seed 003 prints no numbers for chapter 4, only figures and trends, so the analysis is a list
of checks (:func:`checks`: teamwork, radio and laser range, the plan-interval plateau, the
optimal team size, completeness) plus the tables the report and figures read.
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Any

import numpy as np

from swarmex.studies.exploration.design import TEAM_VARIANTS, Design


def steps_table(results, d: Design) -> dict[tuple[float, float, int], list[float]]:
    table: dict[tuple[float, float, int], list[float]] = {}
    for r in results.values():
        j = r["job"]
        if j["kind"] == "sweep":
            table.setdefault((j["laser"], j["comm"], j["robots"]), []).append(r["mean_steps"])
    return table


def mean(table, key) -> float:
    v = table.get(key)
    return float(np.mean(v)) if v else math.nan


def phase_intervals(plan_ticks: list[list[int]], end: int) -> list[list[int]]:
    """Intervals ending in the first, middle and last third of the run."""
    out: list[list[int]] = [[], [], []]
    for ticks in plan_ticks:
        for a, b in zip(ticks, ticks[1:], strict=False):
            out[min(2, int(3 * b / max(end, 1)))].append(b - a)
    return out


def checks(results, d: Design, period: int = 20) -> list[dict[str, Any]]:
    tab = steps_table(results, d)
    teams = [n for n in d.sizes if n > 1]
    out = []
    # 1. teamwork
    combos = [(la, c) for la in d.lasers for c in d.comms]
    ok = [all(mean(tab, (la, c, n)) < mean(tab, (la, c, 1)) for n in teams) for la, c in combos]
    out.append(
        {
            "trend": "teamwork cuts time: every team size beats one robot",
            "holds": all(ok),
            "evidence": f"{sum(ok)}/{len(ok)} (laser, radio) pairs; one robot "
            + ", ".join(f"{mean(tab, (la, max(d.comms), 1)):.0f}" for la in d.lasers)
            + f" steps vs {max(teams)} robots "
            + ", ".join(f"{mean(tab, (la, max(d.comms), max(teams))):.0f}" for la in d.lasers)
            + f" (radio {max(d.comms):g} m)",
        }
    )
    # 2. communication range
    lo_c, hi_c = min(d.comms), max(d.comms)
    diffs = [mean(tab, (la, lo_c, n)) - mean(tab, (la, hi_c, n)) for la in d.lasers for n in teams]
    rho = []
    for la in d.lasers:
        for n in teams:
            ys = [mean(tab, (la, c, n)) for c in d.comms]
            rho.append(_spearman(list(d.comms), ys))
    out.append(
        {
            "trend": f"a shorter radio costs steps ({lo_c:g} m vs {hi_c:g} m)",
            "holds": bool(np.nanmean(diffs) > 0),
            "evidence": f"{lo_c:g} m is slower for {sum(x > 0 for x in diffs)}/{len(diffs)} "
            f"(laser, team) pairs, by {np.nanmean(diffs):+.0f} steps on average; "
            f"mean Spearman(range, steps) {np.nanmean(rho):+.2f}",
        }
    )
    # 3. laser range and the shape of the curves
    if len(d.lasers) > 1:
        short, long_ = min(d.lasers), max(d.lasers)
        pairs = [(n, c) for n in d.sizes for c in d.comms]
        ok3 = [mean(tab, (short, c, n)) > mean(tab, (long_, c, n)) for n, c in pairs]
        ratio = []
        for c in d.comms:
            a = [mean(tab, (long_, c, n)) / mean(tab, (long_, c, 1)) for n in d.sizes]
            b = [mean(tab, (short, c, n)) / mean(tab, (short, c, 1)) for n in d.sizes]
            ratio.append(float(np.nanmax(np.abs(np.subtract(a, b)))))
        slow = np.nanmean([mean(tab, (short, c, n)) / mean(tab, (long_, c, n)) for n, c in pairs])
        out.append(
            {
                "trend": f"a shorter laser costs steps ({short:g} m vs {long_:g} m)",
                "holds": sum(ok3) >= 0.9 * len(ok3),
                "evidence": f"{sum(ok3)}/{len(ok3)} (team, radio) pairs; {short:g} m needs "
                f"{slow:.2f}× the steps of {long_:g} m on average",
            }
        )
        out.append(
            {
                "trend": "steps relative to one robot keep their shape across lasers",
                "holds": max(ratio) < 0.15,
                "evidence": "largest gap between the normalised curves "
                f"{max(ratio):.3f} (per radio: " + ", ".join(f"{x:.3f}" for x in ratio) + ")",
            }
        )
    # 4. plateau and crowding (10 robots, longest radio, laser 2 m)
    big = max(d.sizes)
    runs = [
        r
        for r in results.values()
        if r["job"]["kind"] == "sweep"
        and r["job"]["robots"] == big
        and r["job"]["comm"] == hi_c
        and r["job"]["laser"] == max(d.lasers)
    ]
    phases: list[list[int]] = [[], [], []]
    for r in runs:
        for i, p in enumerate(phase_intervals(r["plan_ticks"], r["makespan"])):
            phases[i].extend(p)
    mode_mid = Counter(phases[1]).most_common(1)[0][0] if phases[1] else None
    share = [float(np.mean(np.array(p) < period)) if p else math.nan for p in phases]
    out.append(
        {
            "trend": f"{big} robots, {hi_c:g} m radio: flat part at {period} steps (timer "
            "only) in the middle of the run",
            "holds": mode_mid == period,
            "evidence": f"most common interval in the middle third: {mode_mid}; "
            f"{np.mean(np.array(phases[1]) == period):.0%} of them are "
            f"exactly {period}"
            if phases[1]
            else "no intervals",
        }
    )
    out.append(
        {
            "trend": "crowding at the end: plan generations become more frequent",
            "holds": bool(share[2] > share[1]),
            "evidence": "share of unscheduled (< timer) intervals in the first/middle/last "
            "third: "
            + " / ".join(f"{s:.0%}" for s in share)
            + f"; plans in each third: {len(phases[0])} / {len(phases[1])} / "
            f"{len(phases[2])}",
        }
    )
    # 5. optimal team size
    best = {}
    for la in d.lasers:
        for c in d.comms:
            ms = [mean(tab, (la, c, n)) for n in d.sizes]
            best[(la, c)] = d.sizes[int(np.nanargmin(ms))]
    rises = [b < max(d.sizes) for b in best.values()]
    out.append(
        {
            "trend": "an optimal team size: steps fall, then rise for big teams",
            "holds": sum(rises) > len(rises) / 2,
            "evidence": "fastest team size per (laser, radio): "
            + ", ".join(f"{la:g}/{c:g} m → {n}" for (la, c), n in best.items()),
        }
    )
    allruns = [r for r in results.values() if r["job"]["kind"] == "sweep"]
    out.append(
        {
            "trend": "every run completes with the reachable free space mapped",
            "holds": all(r["complete"] and r["explored_fraction"] >= 0.99 for r in allruns),
            "evidence": f"{sum(r['complete'] for r in allruns)}/{len(allruns)} complete; "
            f"lowest explored fraction "
            f"{min((r['explored_fraction'] for r in allruns), default=1):.4f}",
        }
    )
    return out


def _spearman(x, y) -> float:
    x, y = np.asarray(x, float), np.asarray(y, float)
    if np.isnan(y).any() or len(x) < 2:
        return math.nan
    rx, ry = np.argsort(np.argsort(x)), np.argsort(np.argsort(y))
    if rx.std() == 0 or ry.std() == 0:
        return 0.0
    return float(np.corrcoef(rx, ry)[0, 1])


def team_table(results, d: Design) -> dict[str, dict[int, list[dict[str, Any]]]]:
    """variant → team size → its runs (from ``team_jobs``; other runs in ``results`` are
    skipped)."""
    out: dict[str, dict[int, list[dict[str, Any]]]] = {}
    for r in results.values():
        j = r["job"]
        if j["kind"] not in ("sweep", "teamsize") or j["strategy"] != "greedy-exclusion":
            continue
        if j["laser"] != max(d.lasers) or j["comm"] != max(d.comms):
            continue
        for name, opts in TEAM_VARIANTS.items():
            if all(j.get(k) == opts.get(k) for k in ("conflict_yield", "plan_pause")):
                out.setdefault(name, {}).setdefault(j["robots"], []).append(r)
    return out


def fastest_size(by_size: dict[int, list[dict[str, Any]]]) -> int:
    """The team size with the fewest mean steps of a team member."""
    ms = {n: float(np.mean([r["mean_steps"] for r in rs])) for n, rs in by_size.items()}
    return min(ms, key=lambda k: ms[k])
