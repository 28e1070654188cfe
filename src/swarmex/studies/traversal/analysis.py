"""The analysis of ``swarmex reproduce traversal``: our statistics beside the thesis's.

Everything here reads the raw per-run records (``traversal.json``) and never reruns anything.
Per table group and figure bar: the summary the thesis's candlesticks and tables show (min,
max, median, mean, STD and the normal 95 % interval mean ± 1.96·STD/√n that its intervals
are consistent with, :func:`swarmex.engine.stats.summarize`), one-way ANOVAs across bars, the
optimum of the 6×6 tables, a verdict per figure, and the best fleet size for a preparation
time (Figs. 5.13–5.14).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import stats as sps

from swarmex.engine.stats import Z95, Summary, summarize
from swarmex.studies.traversal.design import (
    JOB_TIME,
    PER_AGENT_METRICS,
    THESIS_METRIC,
    TRAVEL_SPEED,
    FigureSpec,
    Group,
    Plan,
    ReferenceRow,
    reference_rows,
)

#: The thesis's best fleet size by preparation time p (Figs. 5.13–5.14, §5.1.2 text).
THESIS_FLEET = ((10, 0.0, 48.0), (7, 81.0, 104.0), (4, 227.0, 377.0), (2, 764.0, math.inf))
CORNER_CI = (450.45, 453.07)


@dataclass
class GroupResult:
    group: Group
    runs: list[dict[str, Any]]
    ours: dict[str, Summary]  # thesis metric name → our summary
    thesis: dict[str, ReferenceRow]
    optimal_hits: int  # runs with 35 moves (no travel without a job): the true optimum
    madgta_floor_hits: int  # runs at the best total MADGTA's always-move rule allows


@dataclass
class BarResult:
    label: str
    summary: Summary | None
    runs: list[dict[str, Any]]


@dataclass
class FigureResult:
    spec: FigureSpec
    bars: list[BarResult]
    verdict: str = ""
    stated_rows: list[tuple[str, str, float, Summary | None]] = field(default_factory=list)


def runs_for(runs: dict[str, dict], key: str, reps: int) -> list[dict[str, Any]]:
    return [runs[f"{key}#{r}"] for r in range(reps) if f"{key}#{r}" in runs]


def per_run(rec: dict[str, Any], metric: str) -> float:
    return float(rec["totals"][metric])


def optimum_6x6(size: int = 6, side: float = 40.0, nest_degree: int = 4, agents: int = 3):
    """Lower bounds on totalTimeAll for one nest on an empty grid: (optimum, MADGTA floor).

    Every vertex but the nest must be entered at least once, so ≥ size²−1 moves and size²
    jobs: the optimum of the §3.1 objective (one agent can snake through a Hamiltonian path;
    idle agents cost nothing). MADGTA never lets an agent idle while work remains, so each
    agent's first move enters a neighbour of the nest; with fewer neighbours than agents some
    first moves repeat a vertex: ≥ size²−1 + max(0, agents − degree) moves.
    """
    edge = side / size / TRAVEL_SPEED
    jobs = size * size * JOB_TIME
    moves = size * size - 1
    return jobs + moves * edge, jobs + (moves + max(0, agents - nest_degree)) * edge


def _degree(k: int, size: int) -> int:
    x, y = (k - 1) % size, (k - 1) // size
    return sum(
        0 <= x + dx < size and 0 <= y + dy < size for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
    )


def analyse_groups(groups: Sequence[Group], runs: dict[str, dict]) -> list[GroupResult]:
    """Our Table 5.1–5.2 statistics per group, beside the thesis's rows for that group."""
    by_group: dict[str, dict[str, ReferenceRow]] = {}
    for row in reference_rows():
        by_group.setdefault(row.group, {})[row.metric] = row
    results = []
    for g in groups:
        rs = runs_for(runs, g.config.key, g.reps)
        ours: dict[str, Summary] = {}
        if rs:
            for name, metric in THESIS_METRIC.items():
                if metric in PER_AGENT_METRICS:
                    values = [v for r in rs for v in r["agents"][metric]]
                else:
                    values = [per_run(r, metric) for r in rs]
                ours[name] = summarize(values, z=Z95)
        opt_hits = sum(1 for r in rs if r["totals"]["nodes_without_job_all"] == 0)
        floor_hits = 0
        for r in rs:
            _, floor = optimum_6x6(nest_degree=_degree(r["nest"], 6))
            floor_hits += per_run(r, "total_time_all") <= floor + 1e-6
        results.append(GroupResult(g, rs, ours, by_group.get(g.label, {}), opt_hits, floor_hits))
    return results


def analyse_figures(plan: Plan, runs: dict[str, dict]) -> list[FigureResult]:
    out: list[FigureResult] = []
    for f in plan.figures:
        bars: list[BarResult] = []
        for b in f.bars:
            rs = runs_for(runs, b.config.key, b.reps)
            s = summarize([per_run(r, f.metric) for r in rs], z=Z95) if rs else None
            bars.append(BarResult(b.label, s, rs))
        fr = FigureResult(f, bars)
        labels = [b.label for b in bars]
        for st in f.stated:
            if st.bar is None:
                for br in bars:
                    fr.stated_rows.append((st.text, br.label, st.value, br.summary))
            elif st.bar in labels:
                summary = bars[labels.index(st.bar)].summary
                fr.stated_rows.append((st.text, st.bar, st.value, summary))
        fr.verdict = _verdict(fr)
        out.append(fr)
    return out


def _anova(bars: Sequence[BarResult], metric: str) -> float:
    samples = [[per_run(r, metric) for r in b.runs] for b in bars if len(b.runs) >= 2]
    if len(samples) < 2:
        return math.nan
    if all(np.ptp(s) == 0 for s in samples):
        return math.nan
    return float(sps.f_oneway(*samples).pvalue)


def bar_means(fr: FigureResult) -> list[tuple[str, float]]:
    return [(b.label, b.summary.mean) for b in fr.bars if b.summary]


def _verdict(fr: FigureResult) -> str:
    """One paragraph comparing the thesis's claim about a figure with our bars."""
    means = bar_means(fr)
    if not means:
        return "No runs."
    f = fr.spec
    p = _anova(fr.bars, f.metric)
    p_text = f"one-way ANOVA across the bars: p = {p:.3g}" if math.isfinite(p) else ""
    lo = min(means, key=lambda t: t[1])
    hi = max(means, key=lambda t: t[1])
    if f.number in ("5.3", "5.4", "5.5", "5.6"):
        avg = float(np.mean([m for _, m in means]))
        text = (
            f"Our bar means span {lo[1]:.1f}–{hi[1]:.1f} s (lowest at {lo[0]}, highest at "
            f"{hi[0]}; spread {hi[1] - lo[1]:.1f} s = {100 * (hi[1] - lo[1]) / avg:.2f} % of the "
            f"average {avg:.1f} s); {p_text}. "
        )
        whisk = float(np.mean([b.summary.max - b.summary.min for b in fr.bars if b.summary]))
        nmin = min(b.summary.n for b in fr.bars if b.summary)
        if math.isfinite(p):
            text += (
                "No detectable nest effect, as the thesis says."
                if p > 0.05
                else f"With {nmin} or more runs per bar the nest location has a statistically "
                f"detectable effect, but it is small next to the min–max whiskers (on average "
                f"{whisk:.0f} s long) that the thesis's candlesticks show, so it agrees with "
                "the thesis's reading of its plots."
            )
        if f.stated:
            v = f.stated[0].value
            text += f" Against the stated ≈{v:.0f} s our average is {100 * (avg - v) / v:+.2f} %."
        return text
    if f.number in ("5.7", "5.8", "5.9", "5.11"):
        first, last = means[0], means[-1]
        rise = last[1] - first[1]
        text = (
            f"Mean totalTimeAll goes from {first[1]:.1f} s with {first[0]} agents to "
            f"{last[1]:.1f} s with {last[0]} ({rise:+.1f} s, {100 * rise / first[1]:+.2f} %); "
            f"the lowest mean is at {lo[0]} agents. "
        )
        if f.number == "5.9":
            text += (
                'The thesis\'s "best number of agents < 5" holds.'
                if int(lo[0]) < 5
                else "Unlike the thesis (best < 5), our minimum is at 5 or more agents."
            )
        elif f.number in ("5.7", "5.8"):
            text += (
                "The rising trend matches the thesis."
                if rise > 0
                else "We do not see the thesis's rising trend."
            )
        return text
    if f.number == "5.10":
        order = [m for _, m in means]
        mono = all(b <= a for a, b in zip(order, order[1:], strict=False))
        per_free = [(b.label, b.summary.mean / (400 - int(b.label))) for b in fr.bars if b.summary]
        return (
            "Mean totalTimeAll by obstacle count: "
            + ", ".join(f"{lab}: {m:.0f} s" for lab, m in means)
            + (
                ". It decreases monotonically, as in the thesis"
                if mono
                else ". It does not decrease monotonically"
            )
            + "; per free node it is "
            + ", ".join(f"{v:.2f}" for _, v in per_free)
            + " s, so the drop is the saved jobs (10 s each) minus some extra detours."
        )
    if f.number == "5.12":
        return (
            "Mean mission duration (max totalTime_i) by agents: "
            + ", ".join(f"{lab}: {m:.0f} s" for lab, m in means)
            + ". More agents shorten the mission roughly as 1/m, as in the thesis."
        )
    return p_text


def best_fleet(t_max: dict[int, float], p_max: float = 2000.0) -> list[tuple[int, float, float]]:
    """Intervals of preparation time p on which n minimises n·p + T_max(n) (spec [derived]).

    Returns ``(n, p_from, p_to)`` in increasing p; the lower envelope of straight lines, found
    exactly from their pairwise crossings.
    """
    ns = sorted(t_max)
    if not ns:
        return []
    cuts = {0.0, p_max}
    for i, a in enumerate(ns):
        for b in ns[i + 1 :]:
            p = (t_max[a] - t_max[b]) / (b - a)
            if 0 < p < p_max:
                cuts.add(p)
    pts = sorted(cuts)
    out: list[tuple[int, float, float]] = []
    for lo, hi in zip(pts, pts[1:], strict=False):
        mid = (lo + hi) / 2
        n = min(ns, key=lambda k: (k * mid + t_max[k], k))
        if out and out[-1][0] == n:
            out[-1] = (n, out[-1][1], hi)
        else:
            out.append((n, lo, hi))
    if out:
        n, lo, _ = out[-1]
        out[-1] = (n, lo, math.inf)
    return out


def anova_groups(groups: list[GroupResult]) -> float:
    samples = [[per_run(r, "total_time_all") for r in g.runs] for g in groups if len(g.runs) > 1]
    if len(samples) < 2:
        return math.nan
    return float(sps.f_oneway(*samples).pvalue)


def fleet_t_max(figs: list[FigureResult]) -> dict[int, float]:
    for fr in figs:
        if fr.spec.number == "5.12":
            return {int(b.label): b.summary.mean for b in fr.bars if b.summary}
    return {}
