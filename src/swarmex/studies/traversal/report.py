"""The Markdown report of ``swarmex reproduce traversal`` (and its figures, via :mod:`.figures`).

Everything here reads the raw per-run records (``traversal.json``), never reruns anything:
the report can be rebuilt from the JSON alone (:func:`rebuild`). The report puts the thesis's
numbers and ours side by side for every row of Tables 5.1–5.2, and for every figure states
what the thesis says next to what we measured, then explains the differences.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.engine.stats import (
    implied_sample_size,
    intervals_overlap,
    position_in_interval,
    standard_errors_apart,
)
from swarmex.errors import InputError
from swarmex.experiments.runstore import existing, read_json
from swarmex.studies.traversal.analysis import (
    CORNER_CI,
    THESIS_FLEET,
    FigureResult,
    GroupResult,
    analyse_figures,
    analyse_groups,
    anova_groups,
    bar_means,
    best_fleet,
    fleet_t_max,
    optimum_6x6,
)
from swarmex.studies.traversal.design import (
    THESIS_METRIC,
    TRAVEL_SPEED,
    Plan,
    build_plan,
)
from swarmex.studies.traversal.figures import draw_figures


def _f(x: float, nd: int = 2) -> str:
    """A number, or "n/a" where it is undefined (the STD of a single run)."""
    return "n/a" if math.isnan(x) else f"{x:.{nd}f}"


def _ci(lo: float, hi: float, nd: int = 2) -> str:
    """An interval, or "n/a" where it is undefined (a single run has none)."""
    if math.isnan(lo) or math.isnan(hi):
        return "n/a"
    return f"[{lo:.{nd}f}, {hi:.{nd}f}]"


def write_outputs(
    plan: Plan, runs: dict[str, dict], out: Path, header: dict[str, Any]
) -> dict[str, Any]:
    """Figures + ``traversal.md`` from the stored runs.

    An InputError if ``runs`` lacks some of the plan's runs: the report's header states the
    plan's run count and its tables are drawn per plan group, so a quick sweep's JSON drawn
    as the full plan came out titled "4200 runs" over tables of 6 runs each.
    """
    out = Path(out)
    specs = plan.run_specs()
    missing = sum(1 for s in specs if s.id not in runs)
    if missing:
        options = (" --quick" if plan.quick else "") + (
            f" --runs {plan.reps}" if plan.reps else ""
        )
        raise InputError(
            f"{out} holds {len(specs) - missing} of the {len(specs)} runs of the "
            f"{'quick' if plan.quick else 'full'} plan{options and f' ({options.strip()})'}: "
            f"{missing} are missing, and the report would claim them. Run `swarmex reproduce "
            f"traversal{options} --out {out}` to add them (runs already there are kept), or "
            "rebuild the plan the runs were drawn for (rebuild(DIR) without quick/reps)"
        )
    groups = analyse_groups(plan.groups, runs)
    sens = analyse_groups(plan.sensitivity, runs)
    figs = analyse_figures(plan, runs)
    figures = draw_figures(groups, figs, out)
    report = out / "traversal.md"
    report.write_text(render_report(plan, groups, figs, header, sens), encoding="utf-8")
    return {"report": report, "figures": figures}


def rebuild(out: Path, quick: bool | None = None, reps: int | None = None) -> dict[str, Any]:
    """Re-plot and rewrite the report from ``out``/traversal.json without running anything.

    The plan is the one the JSON says its report was drawn for (``--quick``, ``--runs``), so
    a quick sweep's report is redrawn as a quick one; ``quick`` (with ``reps``) asks for
    another, which the JSON must hold every run of (an InputError names how many are
    missing otherwise: the report would state runs it does not have). Before, the full plan
    was always assumed: a quick sweep's report came back titled "full plan, 9072 runs",
    with bars of the full plan the quick one does not draw.

    A gzipped ``traversal.json.gz`` is read too: that is how the committed record in
    docs/reproduction/traversal/ keeps the ~10 MB of raw runs small.
    """
    path = existing(Path(out) / "traversal.json")
    if not path.exists():
        raise FileNotFoundError(f"no traversal.json (or traversal.json.gz) in {out}")
    data = read_json(path)
    header = {k: v for k, v in data.items() if k not in ("runs", "configs")}
    if quick is None:
        quick, reps = drawn_plan(header)
    return write_outputs(build_plan(quick, reps), data["runs"], Path(out), header)


def drawn_plan(header: dict[str, Any]) -> tuple[bool, int | None]:
    """(quick, reps) of the plan a ``traversal.json`` header says its report was drawn for.

    JSON written before the header named its plan: the last session's mode, else full.
    """
    plan = header.get("plan")
    if isinstance(plan, dict):
        reps = plan.get("reps")
        return bool(plan.get("quick")), int(reps) if reps else None
    sessions = header.get("sessions") or [{}]
    return sessions[-1].get("mode") == "quick", None


def _group_table(g: GroupResult) -> list[str]:
    lines = [
        "| metric | thesis min–max | ours min–max | thesis median | ours median "
        "| thesis mean (STD) | ours mean (STD) | thesis 95 % CI | ours 95 % CI (n) "
        "| CIs overlap | thesis n implied |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in THESIS_METRIC:
        t = g.thesis.get(name)
        o = g.ours.get(name)
        if t is None or o is None:
            continue
        if o.has_ci:
            overlap = "yes" if intervals_overlap((t.ci_low, t.ci_high), o.ci) else "**no**"
        else:
            overlap = "–"  # one run: no interval of ours, so no verdict
        n_imp = implied_sample_size(t.std, t.ci_low, t.ci_high)
        lines.append(
            f"| {name} | {_f(t.min)}–{_f(t.max)} | {_f(o.min)}–{_f(o.max)} | {_f(t.median)} "
            f"| {_f(o.median)} | {_f(t.mean)} ({_f(t.std)}) | {_f(o.mean)} ({_f(o.std)}) "
            f"| {_ci(t.ci_low, t.ci_high)} | {_ci(o.ci_low, o.ci_high)} ({o.n}) "
            f"| {overlap} | {n_imp:.0f} |"
        )
    return lines


def render_report(
    plan: Plan,
    groups: list[GroupResult],
    figs: list[FigureResult],
    header: dict[str, Any],
    sens: Sequence[GroupResult] = (),
) -> str:
    L: list[str] = []
    sessions = header.get("sessions", [])
    mode = "quick (reduced)" if plan.quick else "full"
    n_runs = len(plan.run_specs())
    options = (" --quick" if plan.quick else "") + (f" --runs {plan.reps}" if plan.reps else "")
    # --runs changes every group's and bar's n: the plan is not the full one any more
    per_bar = (
        f" with {plan.reps} run{'s' if plan.reps != 1 else ''} per table group and figure bar"
        if plan.reps
        else ""
    )
    L += [
        "# Seed 000, chapter 5: MADGTA simulations reproduced",
        "",
        f"Generated by `swarmex reproduce traversal{options}` "
        f"(swarmex {header.get('swarmex_version', '?')}): **{mode}** plan{per_bar}, "
        f"{n_runs} runs. " + _sessions_text(sessions),
        "",
        "Every raw per-run number is in `traversal.json` (key `runs`, one record per run: "
        "seed, nest, obstacles, totals and the per-agent metrics); figures and this report "
        "can be rebuilt from it with "
        "`swarmex.studies.traversal.report.rebuild(DIR)`.",
        "",
        "**Model.** Discrete-event simulation of MADGTA (`swarmex.missions.traversal`), "
        "thesis parameters: 3 identical agents (or 2–10 in the series), travel 3 m/s, job 10 s, "
        "altitude 5 m, climb 1.5 m/s, descent 0.3 m/s, clients started 0.5 s apart, node "
        "spacing side/nodesOnEdge (6.67 m on the 6×6/40 m grid: 2.22 s per edge), perfect "
        "instant broadcast. Seeds are hashes of (configuration, repetition), so results do "
        "not depend on the worker count. Statistics: sample STD (ddof = 1), 95 % CI = "
        "mean ± 1.96·STD/√n (the formula the thesis's intervals are consistent with).",
        "",
    ]
    # headline
    corner = next((g for g in groups if 1 in g.group.config.nests), None)
    if corner and corner.ours:
        o = corner.ours["totalTimeAll"]
        where = position_in_interval(o.mean, CORNER_CI)
        se = standard_errors_apart(o, 451.76)
        apart = (
            "one run has no standard error" if math.isnan(se)
            else f"{se:+.1f} of our standard errors"
        )
        if not o.has_ci:
            verdict = "; with one run we have no interval, so overlap is not judged."
        elif intervals_overlap(CORNER_CI, o.ci):
            verdict = "; the two intervals overlap."
        else:
            verdict = "; the two intervals do **not** overlap."
        L += [
            "## Headline: corner nests, totalTimeAll",
            "",
            f"Thesis: mean 451.76 s, 95 % CI {_ci(*CORNER_CI)} (≈108 runs). "
            f"Ours: mean **{o.mean:.2f} s**, 95 % CI **{_ci(o.ci_low, o.ci_high)}** "
            f"(n = {o.n}). Our mean is **{where}** the thesis's interval "
            f"({o.mean - 451.76:+.2f} s from its mean, {apart}){verdict}",
            "",
        ]
    # tables
    L += ["## Tables 5.1–5.2 (6×6 nodes, 40×40 m, no obstacles, 1 nest, 3 agents)", ""]
    L += [
        "Runs per group are spread round-robin over the group's nests (seed = hash of the "
        "group and the repetition). Per-agent rows pool all agents of all runs, so our n is "
        "3 × runs; the thesis's per-agent intervals imply n ≈ 108 (last column: "
        "(1.96·STD/half-width)²), i.e. they were computed with the number of runs and are "
        "√3 wider than their pooled sample supports, which makes overlap with them easier.",
        "",
    ]
    overlap_count = total_rows = 0
    for g in groups:
        if not g.ours:
            continue
        L += [
            f"### Table {g.group.table}: nest in node {g.group.label} ({g.group.name}), "
            f"{len(g.runs)} run{'s' if len(g.runs) != 1 else ''}",
            "",
        ]
        L += _group_table(g)
        for name in THESIS_METRIC:
            t_row, o_sum = g.thesis.get(name), g.ours.get(name)
            if t_row and o_sum and o_sum.has_ci:
                total_rows += 1
                overlap_count += intervals_overlap((t_row.ci_low, t_row.ci_high), o_sum.ci)
        L.append("")
    L += [
        f"Overall, {overlap_count} of {total_rows} rows have overlapping 95 % intervals."
        if total_rows
        else "With one run per group our intervals are undefined: no overlap is judged.",
        "",
        "Group ranking by mean totalTimeAll — thesis: "
        + ", ".join(
            f"{g.group.name} {g.thesis['totalTimeAll'].mean:.2f}"
            for g in sorted(groups, key=lambda g: g.thesis["totalTimeAll"].mean)
            if "totalTimeAll" in g.thesis
        )
        + "; ours: "
        + ", ".join(
            f"{g.group.name} {g.ours['totalTimeAll'].mean:.2f}"
            for g in sorted(
                (g for g in groups if g.ours), key=lambda g: g.ours["totalTimeAll"].mean
            )
        )
        + ".",
        "",
    ]
    p = anova_groups(groups)
    if math.isfinite(p):
        L += [f"One-way ANOVA of our totalTimeAll across the six groups: p = {p:.3g}.", ""]
    # optimum
    opt, _ = optimum_6x6()
    L += [
        "### How often is the optimum reached?",
        "",
        f"Every vertex but the nest has to be entered once and all 36 jobs done, so the §3.1 "
        f"objective is at least 36·10 s + 35 moves · 2.222 s = **{opt:.2f} s**, and one agent "
        "snaking through the grid reaches it (idle agents cost nothing): the optimum is "
        "35 moves for any nest, the spec's 437.8 s. The thesis's 437.66 s is that with a "
        "slightly shorter GPS edge (2.219 s). Under MADGTA's rules, though, no agent may idle, "
        "and each agent's first move enters a neighbour of the nest; a corner nest has only "
        "2 neighbours for 3 agents, so MADGTA needs ≥ 36 moves (440.0 s) there. The thesis's "
        "tables agree: only the mid-border group ever had numNodesWoJAll = 0 (min 437.66 s); "
        "corner and near-corner minima are 439.89 / 439.86 s = one extra move.",
        "",
        "| group | runs | 35-move optimum hit (numNodesWoJAll = 0) | at MADGTA's floor "
        "(35 + max(0, 3 − nest degree) moves) | thesis min totalTimeAll / numNodesWoJAll |",
        "|---|---|---|---|---|",
    ]
    all_runs = sum(len(g.runs) for g in groups)
    for g in groups:
        if not g.runs:
            continue
        n = len(g.runs)
        th = g.thesis
        L.append(
            f"| {g.group.name} | {n} | {g.optimal_hits} ({100 * g.optimal_hits / n:.1f} %) "
            f"| {g.madgta_floor_hits} ({100 * g.madgta_floor_hits / n:.1f} %) "
            f"| {th['totalTimeAll'].min:.2f} / {th['numNodesWoJAll'].min:.0f} |"
        )
    hits = sum(g.optimal_hits for g in groups)
    floor = sum(g.madgta_floor_hits for g in groups)
    if all_runs:
        L += [
            "",
            f"Over all {all_runs} runs: {hits} ({100 * hits / all_runs:.1f} %) reach the 35-move "
            f"optimum and {floor} ({100 * floor / all_runs:.1f} %) the best MADGTA can do from "
            'their nest. The thesis\'s "optimal in 2–5 % of runs" cannot be checked exactly '
            "(it gives no counts); its tables show a 35-move run only in the mid-border group.",
            "",
        ]
    # figures
    L += ["## Figures", ""]
    L += [
        "Candlesticks as in the thesis: whiskers = min/max over runs, body = 95 % CI of the "
        "mean (black tick = mean). Red: the thesis (hollow candles where its tables give the "
        "numbers, diamonds/dashed lines where its text states a value).",
        "",
    ]
    names = {g.group.config.nests: g for g in groups}
    for number, nodes in (("5.1", (1, 2, 3)), ("5.2", (8, 15))):
        rows = []
        for k in nodes:
            grp = next((g for cfg, g in names.items() if k in cfg), None)
            if grp and grp.ours:
                t, o = grp.thesis["totalTimeAll"], grp.ours["totalTimeAll"]
                rows.append(
                    f"| {k} ({grp.group.name}) | {_ci(t.ci_low, t.ci_high)} | "
                    f"{_ci(o.ci_low, o.ci_high)} | {t.min:.2f}–{t.max:.2f} | "
                    f"{o.min:.2f}–{o.max:.2f} |"
                )
        if rows:
            L += [
                f"### Fig. {number} (6×6, from the table runs)",
                "",
                "| nest | thesis CI | our CI | thesis min–max | our min–max |",
                "|---|---|---|---|---|",
                *rows,
                "",
                f"![Fig. {number}](fig_{number.replace('.', '_')}.png)",
                "",
            ]
    for fr in figs:
        f = fr.spec
        L += [f"### Fig. {f.number}: {f.title}", "", f"*Thesis:* {f.claim}"]
        if f.choice:
            L.append(f"*Our choice (not stated in the thesis):* {f.choice}.")
        L.append("")
        if fr.stated_rows:
            L += [
                "| stated in the thesis | bar | stated value | our mean | our 95 % CI "
                "| our min–max | difference |",
                "|---|---|---|---|---|---|---|",
            ]
            for text, bar, value, s in fr.stated_rows:
                if s is None:
                    continue
                L.append(
                    f"| {text} | {bar} | {value:.0f} | {s.mean:.1f} | "
                    f"{_ci(s.ci_low, s.ci_high, 1)} | {s.min:.1f}–{s.max:.1f} | "
                    f"{s.mean - value:+.1f} s ({100 * (s.mean - value) / value:+.2f} %) |"
                )
            L.append("")
        L += [
            "| bar | n | min | max | median | mean | STD | 95 % CI |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for b in fr.bars:
            if b.summary is None:
                continue
            s = b.summary
            L.append(
                f"| {b.label} | {s.n} | {s.min:.1f} | {s.max:.1f} | {s.median:.1f} | "
                f"{s.mean:.1f} | {_f(s.std, 1)} | {_ci(s.ci_low, s.ci_high, 1)} |"
            )
        L += ["", fr.verdict, "", f"![Fig. {f.number}](fig_{f.number.replace('.', '_')}.png)", ""]
    L += _fleet_section(figs)
    L += _sensitivity_section(groups, sens)
    L += _explanations(groups, figs, sens)
    return "\n".join(L) + "\n"


def _sessions_text(sessions: list[dict[str, Any]]) -> str:
    """How long the sweep took, summed over resumed sessions (the JSON keeps each one)."""
    if not sessions:
        return ""
    executed = sum(int(x.get("runs_executed", 0)) for x in sessions)
    elapsed = sum(float(x.get("elapsed_s", 0.0)) for x in sessions)
    workers = sorted({x["workers"] for x in sessions if x.get("workers")})
    return (
        f"The runs were executed in {len(sessions)} session(s), {executed} runs in "
        f"{elapsed:.0f} s of wall time on {'/'.join(map(str, workers))} worker(s) "
        "(a rerun skips the runs already in `traversal.json`)."
    )


def _fleet_section(figs: list[FigureResult]) -> list[str]:
    t_max = fleet_t_max(figs)
    if not t_max:
        return []
    ours = best_fleet(t_max)
    L = [
        "### Figs. 5.13–5.14: best fleet size for a preparation time p",
        "",
        "The thesis prepares the UAVs one after another (p seconds each) and picks the n "
        "that minimises n·p + T_max(n), T_max = mean mission duration of Fig. 5.12 (spec "
        "[derived]; the thesis does not print the formula). Our T_max: "
        + ", ".join(f"{n}: {t:.0f} s" for n, t in sorted(t_max.items()))
        + ".",
        "",
        "| best n | thesis p range (s) | our p range (s) |",
        "|---|---|---|",
    ]
    thesis = {n: (lo, hi) for n, lo, hi in THESIS_FLEET}
    for n in sorted({n for n, _, _ in ours} | set(thesis), reverse=True):
        t = thesis.get(n)
        o = [(lo, hi) for k, lo, hi in ours if k == n]
        L.append(
            f"| {n} | {_range(*t) if t else '–'} | "
            f"{', '.join(_range(lo, hi) for lo, hi in o) if o else 'never best'} |"
        )
    if 2 in t_max and 3 in t_max:
        L += [
            "",
            f"The 2↔3 threshold is T_max(2) − T_max(3): ours {t_max[2] - t_max[3]:.0f} s, "
            "thesis 764 s (≈ 2300 − 1536 s).",
        ]
    L += ["", "![Fig. 5.13](fig_5_13.png)", "", "![Fig. 5.14](fig_5_14.png)", ""]
    return L


def _nest_spread(by_num: dict[str, FigureResult]) -> str:
    """The spread of bar means in Figs. 5.5–5.6 as a share of their average."""
    parts = []
    for number in ("5.5", "5.6"):
        fr = by_num.get(number)
        means = [m for _, m in bar_means(fr)] if fr else []
        if means:
            avg = float(np.mean(means))
            parts.append(
                f"Fig. {number}: bar means within {100 * (max(means) - min(means)) / avg:.1f} %"
            )
    return "; ".join(parts) or "not simulated"


def _fleet_agreement(t_max: dict[int, float]) -> str:
    """One sentence: how far our thresholds are from each one the thesis states."""
    ours = {n: (lo, hi) for n, lo, hi in best_fleet(t_max)}
    diffs = []
    missing = []
    for n, lo, hi in THESIS_FLEET:
        if n not in ours:
            missing.append(n)
            continue
        for a, b in ((lo, ours[n][0]), (hi, ours[n][1])):
            if math.isfinite(a) and math.isfinite(b) and a > 0:
                diffs.append(abs(a - b))
    text = ""
    if diffs:
        text = (
            f"Every threshold the thesis states is matched within {max(diffs):.0f} s "
            f"(mean {np.mean(diffs):.1f} s), so our T_max(n) curve has the thesis's shape."
        )
    if missing:
        text += (
            f" Fleet sizes {', '.join(map(str, missing))}, best in the thesis for some p, "
            "are never best for us (or were not simulated in this plan)."
        )
    return text


def _range(lo: float, hi: float) -> str:
    if math.isinf(hi):
        return f"> {lo:.0f}"
    if lo <= 0:
        return f"< {hi:.0f}"
    return f"{lo:.0f}–{hi:.0f}"


def _sensitivity_section(groups: list[GroupResult], sens: Sequence[GroupResult]) -> list[str]:
    if not any(g.ours for g in sens):
        return []
    L = [
        "## Sensitivity: uneven client starts",
        "",
        "Our clients start 0.5 s apart and then run exactly at their nominal speeds. To test "
        "whether uneven progress of the thesis's real-time clients explains its much wider "
        "per-agent spread, the table groups are rerun with every client starting an extra "
        "U(0, J) s late (same seeds otherwise; implemented as a slower climb, which also "
        "changes additionalTime_i, so that row is not used here).",
        "",
        "| group | setting | runs | totalTimeAll mean [95 % CI] | numNodesWoJAll mean "
        "| numNodesDone_i STD (min–max) | totalTime_i STD (min–max) |",
        "|---|---|---|---|---|---|---|",
    ]
    base = {g.group.label: g for g in groups if g.ours}
    by_label: dict[str, list[GroupResult]] = {}
    for g in sens:
        if g.ours:
            by_label.setdefault(g.group.label, []).append(g)

    def row(name: str, setting: str, n: object, t, w, d, tt) -> str:
        return (
            f"| {name} | {setting} | {n} | {t.mean:.2f} {_ci(t.ci_low, t.ci_high)} "
            f"| {w.mean:.2f} | {_f(d.std)} ({d.min:.0f}–{d.max:.0f}) "
            f"| {_f(tt.std)} ({tt.min:.1f}–{tt.max:.1f}) |"
        )

    for label, variants in by_label.items():
        g0 = base.get(label)
        if g0 is None:
            continue
        th = g0.thesis
        if th:
            L.append(
                row(
                    g0.group.name,
                    "**thesis**",
                    "≈108",
                    th["totalTimeAll"],
                    th["numNodesWoJAll"],
                    th["numNodesDone_i"],
                    th["totalTime_i"],
                )
            )
        for g, setting in (
            (g0, "ours, J = 0"),
            *((v, f"ours, J = {v.group.config.jitter:g} s") for v in variants),
        ):
            o = g.ours
            L.append(
                row(
                    g.group.name,
                    setting,
                    len(g.runs),
                    o["totalTimeAll"],
                    o["numNodesWoJAll"],
                    o["numNodesDone_i"],
                    o["totalTime_i"],
                )
            )
    L.append("")
    return L


def _per_group(groups: Sequence[GroupResult]) -> str:
    """"N runs per group" for the plan drawn (108 in the full plan, 6 in the quick one)."""
    counts = sorted({g.group.reps for g in groups})
    if not counts:
        return "no runs"
    n = "/".join(map(str, counts))
    return f"{n} run{'s' if counts != [1] else ''} per group"


def _mean_of(groups: Sequence[GroupResult], metric: str, field_: str, thesis: bool = False):
    vals = [
        getattr(g.thesis[metric] if thesis else g.ours[metric], field_)
        for g in groups
        if g.ours and metric in g.thesis
    ]
    return float(np.mean(vals)) if vals else math.nan


def _explanations(
    groups: list[GroupResult], figs: list[FigureResult], sens: Sequence[GroupResult] = ()
) -> list[str]:
    """Why our numbers differ from the thesis's, with the numbers of this run plugged in."""
    L = ["## Why the numbers differ", ""]
    have = [g for g in groups if g.ours and g.thesis]
    L += [
        "**1. Geometry and timing agree to 0.3 %.** Every time in the thesis's tables is a "
        "multiple of one edge time of 2.20–2.235 s: its optimum is 437.66 s = 360 s + 35 × "
        "2.219 s, and its largest corner-nest additionalTime_i is 42.22 s = 20 s + 10 edges × "
        "2.222 s, a return path with 5 east–west edges. So its GPS grid had the same spacing "
        "east–west as north–south (spec §6.11 feared a missing cos(latitude), which would "
        "have made east–west edges 27 % shorter; the tables rule that out). Our edge time is "
        "(40/6 m)/(3 m/s) = 2.222 s; over the ~40 moves of a 6×6 mission the difference is "
        "below 0.2 s.",
        "",
    ]
    if have:
        d_ours = _mean_of(have, "numNodesDone_i", "std")
        d_th = _mean_of(have, "numNodesDone_i", "std", thesis=True)
        t_ours = _mean_of(have, "totalTime_i", "std")
        t_th = _mean_of(have, "totalTime_i", "std", thesis=True)
        text = (
            "**2. Per-agent spread: the thesis's clients progressed unevenly, ours cannot.** "
            f"Averaged over the six groups, the STD of numNodesDone_i is {_f(d_ours)} for us "
            f"and {d_th:.2f} in the thesis, that of totalTime_i {_f(t_ours, 1)} s vs "
            f"{t_th:.1f} s; the thesis has agents doing anywhere from 4 to 18 of the 36 jobs. "
            "In a discrete-event model of identical agents with an instant broadcast, the "
            "three agents alternate 10 s jobs and 2.22 s moves in lock-step from starts 0.5 s "
            "apart, and when the last vertex is taken they all stop within about one job of "
            "each other, so each does 12 ± 1 jobs. The thesis ran its virtual agents as "
            "real-time processes (a TCP server relaying and acknowledging every message, "
            "clients with timed stages), whose progress evidently diverged. The per-agent "
            "*means* are untouched (jobTime_i = 360 s / 3 = 120 s in both, travel and "
            "totalTime_i means within a few seconds), so the per-agent rows whose CIs do not "
            "overlap differ in spread (min, max, STD) or by the travel differences of point 3, "
            "not in the workload split on average."
        )
        s60 = [
            g
            for g in sens
            if g.ours
            and g.group.config.jitter == max((x.group.config.jitter for x in sens), default=0)
        ]
        if s60:
            j = s60[0].group.config.jitter
            sd = float(np.mean([g.ours["numNodesDone_i"].std for g in s60]))
            st = float(np.mean([g.ours["totalTime_i"].std for g in s60]))
            base = {g.group.label: g.ours["totalTimeAll"].mean for g in have}
            shift = [
                g.ours["totalTimeAll"].mean - base[g.group.label]
                for g in s60
                if g.group.label in base
            ]
            text += (
                f" The sensitivity series supports this: with starts spread by up to {j:g} s, "
                f"the STDs become {_f(sd)} jobs and {_f(st, 1)} s (thesis {d_th:.2f} and "
                f"{t_th:.1f}), while the group means of totalTimeAll move by only "
                f"{min(shift):+.1f} to {max(shift):+.1f} s."
            )
        L += [text, ""]
        ranked_th = sorted(have, key=lambda g: g.thesis["totalTimeAll"].mean)
        ranked = sorted(have, key=lambda g: g.ours["totalTimeAll"].mean)
        span_th = (
            ranked_th[-1].thesis["totalTimeAll"].mean - ranked_th[0].thesis["totalTimeAll"].mean
        )
        span = ranked[-1].ours["totalTimeAll"].mean - ranked[0].ours["totalTimeAll"].mean
        woj = [g.ours["numNodesWoJAll"].mean for g in have]
        woj_th = [g.thesis["numNodesWoJAll"].mean for g in have]
        corner = next((g for g in have if 1 in g.group.config.nests), None)
        mid = next((g for g in have if 3 in g.group.config.nests), None)
        opt_mid = (
            f"{100 * mid.optimal_hits / len(mid.runs):.0f} % of our mid-border runs are optimal"
            if mid and mid.runs
            else "no mid-border runs"
        )
        L += [
            "**3. Nest location: our broadcast is instant, theirs was not.** The thesis's group "
            f"means span {span_th:.1f} s, from {ranked_th[0].group.name} (best) to "
            f"{ranked_th[-1].group.name} (worst); ours span {span:.1f} s, from "
            f"{ranked[0].group.name} to {ranked[-1].group.name}. Ours are ordered by how the "
            "three agents can leave the nest: the C05 announcement of a rival's next vertex "
            "arrives instantly, so they never head for the same first vertex, and from a "
            "border nest with 3 exits they fan out along the border without a wasted move "
            f"({opt_mid}), while a corner (2 exits for 3 agents) forces at least one travel "
            "without a job (MADGTA floor 440.00 s; the thesis's corner minimum, 439.89 s, is "
            "that same "
            "bound). The thesis explains its worse middle nests by agents that start almost "
            'synchronously and "are not able to distinguish a first movement of rivals", so '
            "they pick the same direction: that is message latency, which a perfect-broadcast "
            "model does not have. The same latency shows in travels without a job: "
            f"numNodesWoJAll means are {min(woj):.2f}–{max(woj):.2f} for us vs "
            f"{min(woj_th):.2f}–{max(woj_th):.2f} in the thesis."
            + (
                f" For the corner group, where geometry forces the waste anyway, the two agree "
                f"({corner.ours['numNodesWoJAll'].mean:.2f} vs "
                f"{corner.thesis['numNodesWoJAll'].mean:.2f}), which is why the headline "
                "totalTimeAll matches there."
                if corner
                else ""
            )
            + " A direct test with a delayed channel is left for later (see the end).",
            "",
        ]
    by_num = {fr.spec.number: fr for fr in figs}
    f511 = by_num.get("5.11")
    if f511:
        m = {b.label: b.summary for b in f511.bars if b.summary}
        if "2" in m and "10" in m:
            gap = 4760.0 - m["10"].mean
            L += [
                "**4. Larger grids: the same shapes, fewer collisions.** With 2 agents on the "
                f"20×20 grid our totalTimeAll is {m['2'].mean:.0f} s (thesis ≈4580 s); with 10 "
                f"agents {m['10'].mean:.0f} s, {gap:.0f} s below the thesis's ≈4760 s, i.e. "
                f"≈{gap / (4.0 / TRAVEL_SPEED):.0f} fewer travels without a job at 1.33 s per "
                "edge: the thesis's ten real-time clients collided more (point 3), and more so "
                "the more agents there are. The trends are reproduced: totalTimeAll rises with "
                "the number of agents (Figs. 5.7–5.9, 5.11), and on large grids the nest "
                f"location matters little ({_nest_spread(by_num)}).",
                "",
            ]
    f512 = by_num.get("5.12")
    if f512:
        m = {b.label: b.summary for b in f512.bars if b.summary}
        if "10" in m:
            L += [
                "**5. Mission duration with 10 agents.** Our mean max totalTime_i for 10 agents "
                f"is {m['10'].mean:.0f} s (min {m['10'].min:.0f} s). The largest of ten totals "
                "is at least their mean, so with the thesis's own totalTimeAll ≈4760 s its "
                'duration is ≥ 476 s; "up to 450 s" cannot be a mean (spec §6.13) and is '
                "probably read off the lower end of a bar.",
                "",
            ]
    t_max = fleet_t_max(figs)
    if len(t_max) >= 3:
        L += [
            "**6. Fleet sizes.** The best n switches where the lines n·p + T_max(n) cross, "
            "i.e. at differences of T_max between fleet sizes, so the thresholds test the "
            "mission durations of Fig. 5.12 rather than totalTimeAll. " + _fleet_agreement(t_max),
            "",
        ]
    L += [
        "**7. Obstacles (Fig. 5.10).** The thesis does not give its obstacle counts or "
        "layouts, so only the direction can be compared: each obstacle removes a 10 s job "
        "and adds some detour, and totalTimeAll falls with the count in both.",
        "",
        "**8. Statistics.** The thesis gives no run counts; inverting its intervals gives "
        "n ≈ 108 for every row, per-run and per-agent alike, so its per-agent intervals "
        f"treat ~324 pooled agent values as 108 samples. We use {_per_group(groups)} and the "
        "honest n (runs for per-run rows, 3 × runs for per-agent rows).",
        "",
        "**Left for later.** Message latency is the main suspected cause of the remaining "
        "gaps (points 3–4). The simulator has a delayed channel (`swarmex traverse --delay`). "
        "An earlier version could make two agents swap forever under a 1 s delay on the 6×6 "
        "grid; that is gone: 180 runs (6×6, 3 agents, a nest of each of the six groups, "
        "delays 0.5, 1 and 2 s, seeds 0–9) all completed. The latency experiment itself is "
        "not yet part of this reproduction.",
        "",
    ]
    return L


__all__ = ["rebuild", "render_report", "write_outputs"]
