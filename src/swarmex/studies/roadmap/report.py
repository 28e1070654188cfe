"""The report of ``swarmex reproduce roadmap``: ``roadmap.md``, the CSV tables and figures.

Pure post-processing of the run journal written by :mod:`.runs` (through :mod:`.analysis`;
:mod:`.figures` reruns a handful of single seeds to draw the environment figures), so the
report can be rebuilt without rerunning the sweep.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.studies.roadmap.analysis import (
    EQUAL,
    VERSUS,
    gain_summary,
    improvement,
    mae,
    table1,
    table2,
    unreachable,
    versus,
)
from swarmex.studies.roadmap.design import OMPL_PRM, R_BASE, reference
from swarmex.studies.roadmap.figures import bars, draw_examples, fig6

SENSOR_ORDER = ("r", "2r", "4r", "inf")


def _fmt(mean: float, sd: float | None = None, digits: int = 1) -> str:
    if np.isnan(mean):
        return "–"
    if sd is None:
        return f"{mean:.{digits}f}"
    # one run has no sample SD: "± 0.0" claimed a spread of none
    return f"{mean:.{digits}f} ± {'n/a' if np.isnan(sd) else f'{sd:.{digits}f}'}"


def _label(mult: str) -> str:
    return "∞" if mult == "inf" else mult


def _write_csv(path: Path, rows: list[dict[str, Any]]) -> None:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (round(v, 3) if isinstance(v, float) else v) for k, v in r.items()})


def write_report(out: Path, results: list[dict[str, Any]], quick: bool, seconds: float,
                 version: str, new_runs: int | None = None,
                 study: dict[str, Any] | None = None,
                 builds: dict[str, Any] | None = None) -> Path:
    ref1, ref2 = reference("roadmap_table1.csv"), reference("roadmap_table2.csv")
    t1, t2 = table1(results, ref1), table2(results, ref2)
    _write_csv(out / "table1.csv", t1)
    _write_csv(out / "table2.csv", t2)
    g1, g2 = gain_summary(t1), gain_summary(t2)
    # Fig. 6: step 40, range r
    f6 = [r for r in t1 if r["step"] == 40 and r["sensor"] == "r"]
    nodes = [r["nodes"] for r in f6]
    fig6(out / "fig6_coverage_vs_samples.png", nodes, {
        "WMA-RRT (ours)": ([r["ours_wma"] for r in f6], [r["ours_wma_sd"] for r in f6]),
        "PRM (ours)": ([r["ours_prm"] for r in f6], [r["ours_prm_sd"] for r in f6]),
        "WMA-RRT (paper)": ([r["paper_wma"] for r in f6], [0.0] * len(f6)),
        "PRM (paper)": ([r["paper_prm"] for r in f6], [0.0] * len(f6)),
    }, f"Fig. 6: coverage vs sample points (step 40, sensor range r = {R_BASE:g})")
    cov_imp, srch_imp = improvement(results)
    if cov_imp:
        bars(out / "improvement_coverage_steps.png",
             [f"{r['nodes']}/{r['step']}" for r in cov_imp],
             {"wma-rrt": [r["steps_base"] for r in cov_imp],
              "wma-rrt-takeover": [r["steps_takeover"] for r in cov_imp]},
             "steps until every branch is COMPLETE",
             "Coverage makespan on the Fig. 8 environment (nodes/step, 3 agents)")
    un = unreachable(results)
    figs = draw_examples(out, results)
    prm_all = [r for r in results if r["planner"] == "prm" and r["exp"] in ("t1", "t2")]
    multi = sum(r["components"] > 1 for r in prm_all)
    lines = _markdown(t1, t2, g1, g2, cov_imp, srch_imp, un, figs, quick, seconds, version,
                      R_BASE, prm_all, multi, results,
                      len(results) if new_runs is None else new_runs)
    t1e = [r for r in table1(results, ref1, "t1eps")
           if r["sensor"] != "inf" and not np.isnan(r["ours_wma"])]
    t2e = [r for r in table2(results, ref2, "t2eps")
           if r["sensor"] != "inf" and r["runs"]]
    if t1e:
        _write_csv(out / "table1_r_eps.csv", t1e)
    if t2e:
        _write_csv(out / "table2_r_eps.csv", t2e)
    at = lines.index("## Figures")
    lines[at:at] = readings_section(t1, t2, t1e, t2e, study)
    v1, v2 = versus(results, ref1, "t1"), versus(results, ref2, "t2")
    ompl = any(r["planner"] == OMPL_PRM for r in results)
    if ompl:
        _write_csv(out / "versus_ompl_prm.csv", [_flat(r, "t1") for r in v1] +
                   [_flat(r, "t2") for r in v2])
    at = lines.index("## Figs. 12–13: components")
    lines[at:at] = standard_prm_section(v1, v2, builds, ompl)
    path = out / "roadmap.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _flat(r: dict[str, Any], table: str) -> dict[str, Any]:
    """A row of :func:`versus` as CSV columns."""
    out: dict[str, Any] = {"table": table, "nodes": r["nodes"], "step": r["step"],
                           "sensor": r["sensor"]}
    for p in VERSUS:
        c = r["cells"][p]
        out.update({f"{p}_mean": c["mean"], f"{p}_low": c["low"], f"{p}_high": c["high"],
                    f"{p}_runs": c["n"], f"{p}_path": c["path"]})
    d = r.get("wma_minus_ompl", (float("nan"),) * 3)
    out.update({"winner": r["winner"], "wma_minus_ompl": d[0], "wma_minus_ompl_low": d[1],
                "wma_minus_ompl_high": d[2]})
    return out


def _row_key(r: dict[str, Any]) -> tuple[int, int, str]:
    return (r["nodes"], r["step"], r["sensor"])


def _cov(rows: list[dict[str, Any]], nodes: int, step: int, sensor: str = "r") -> float:
    hit = [r["ours_wma"] for r in rows if _row_key(r) == (nodes, step, sensor)]
    return hit[0] if hit else float("nan")


def _eps(c: float) -> str:
    return "ε" if c == 1 else f"{c:g} ε"


def _rerun_table(
    eps_rows: list[dict[str, Any]], base_rows: list[dict[str, Any]],
    cells: Callable[[dict[str, Any], dict[str, Any]], tuple[str, str, str]],
) -> tuple[list[str], list[dict[str, Any]]]:
    """A table's r = ε rerun beside its r = 25 run: the markdown lines, and the r = 25 rows
    of the same (nodes, step, sensor). ``cells(r25_row, eps_row)`` formats ours at r = 25,
    ours at r = ε and ours PRM at r = ε."""
    base = {_row_key(r): r for r in base_rows}
    same = [base[_row_key(r)] for r in eps_rows]
    lines = ["| nodes | step | sensor | paper WMA-RRT | ours, r = 25 | ours, r = ε | "
             "paper PRM | ours PRM, r = ε |", "|---:|---:|:---:|---:|---:|---:|---:|---:|"]
    for r, b in zip(eps_rows, same, strict=True):
        at25, eps, prm = cells(b, r)
        lines.append(f"| {r['nodes']} | {r['step']} | {_label(r['sensor'])} | "
                     f"{r['paper_wma']:.0f} | {at25} | {eps} | {r['paper_prm']:.0f} | {prm} |")
    return lines, same


def readings_section(t1: list[dict[str, Any]], t2: list[dict[str, Any]],
                     t1e: list[dict[str, Any]], t2e: list[dict[str, Any]],
                     study: dict[str, Any] | None) -> list[str]:
    """The report's answer to "why do 200 nodes at ε = 40 not beat 800 at ε = 20 here?"."""
    out = ["## The unreproduced claim: 200 nodes at ε = 40 against 800 at ε = 20", "",
           "The paper's Table 1 (range r) has 200 nodes at step 40 covering 88 % and 800 nodes "
           "at step 20 covering 83 %, and 200/40 beating 400/20 (74 %) although both trees "
           "have the same total edge length (200 × 40 = 400 × 20). What each reading does:",
           ""]
    if study:
        fixed = [f for f in study["fits"] if f["model"] == "fixed"]
        scaled = [f for f in study["fits"] if f["model"] == "eps"]
        bf = min(fixed, key=lambda f: f["rmse"])
        bs = min(scaled, key=lambda f: f["rmse"])
        out += [
            f"**Growth readings** (complete runs, so coverage = what the tree's edges and the "
            f"entry legs see; mean of {study['seeds']} trees; range r = {study['r_base']:g} "
            f"and r = {_eps(study['c_eps'])}):", "",
            "| reading of ε and N | nodes | step | nodes built | tree length | coverage "
            f"r = {study['r_base']:g} | coverage r = {_eps(study['c_eps'])} | paper (r) |",
            "|---|---:|---:|---:|---:|---:|---:|---:|",
        ]
        paper = {_row_key(r): r["paper_wma"] for r in t1}
        for g in study["growth"]:
            pv = paper.get((g["nodes"], int(g["step"]), "r"), float("nan"))
            out.append(f"| {g['reading']} | {g['nodes']} | {g['step']:g} | "
                       f"{g['tree_nodes']:.0f} | {g['tree_length']:.0f} | "
                       f"{g['coverage_r25']:.1f} | {g['coverage_eps']:.1f} | {pv:.0f} |")
        out += [
            "", "Both alternatives to our reading shorten the trees, and they shorten the "
            "ε = 40 trees most (longer extensions collide more often, and at ε = 40 more "
            "samples fall within ε of the tree): they move 200/40 further below 800/20, "
            "not above it.", "",
            f"**Sensor range fitted** to the 15 finite-range rows of Table 1 (same trees): "
            f"as one fixed length, the best is r = {bf['param']:g} (RMSE {bf['rmse']:.1f} "
            f"points); as a multiple of the step, r = {_eps(bs['param'])} (RMSE "
            f"{bs['rmse']:.1f}). Both are one-parameter fits.", "",
            "| model | " + " | ".join(f"{f['param']:g}" for f in fixed) + " |",
            "|---|" + "---:|" * len(fixed),
            "| r fixed (units): RMSE | " + " | ".join(f"{f['rmse']:.1f}" for f in fixed) + " |",
            "", "| model | " + " | ".join(f"{f['param']:g}" for f in scaled) + " |",
            "|---|" + "---:|" * len(scaled),
            "| r = c·ε (c): RMSE | " + " | ".join(f"{f['rmse']:.1f}" for f in scaled) + " |",
            "",
            "**Coverage against ε at a fixed node budget** (ours, complete runs):", "",
            f"| nodes | step | tree length | coverage r = {study['r_base']:g} | "
            f"coverage r = {_eps(study['c_eps'])} |",
            "|---:|---:|---:|---:|---:|",
        ]
        for w in study["sweep"]:
            out.append(f"| {w['nodes']} | {w['step']:g} | {w['tree_length']:.0f} | "
                       f"{w['coverage_r25']:.1f} | {w['coverage_eps']:.1f} |")
        # the largest budget at the finest step, against the smallest budget at every step
        sizes = [w["nodes"] for w in study["sweep"]]
        finest = min((w["step"] for w in study["sweep"]), default=None)
        big = [w for w in study["sweep"] if w["nodes"] == max(sizes) and w["step"] == finest]
        small = [w for w in study["sweep"] if w["nodes"] == min(sizes)]
        if big and small:
            ref_r, ref_e = big[0]["coverage_r25"], big[0]["coverage_eps"]
            beat_r = [w["step"] for w in small if w["coverage_r25"] > ref_r]
            beat_e = [w["step"] for w in small if w["coverage_eps"] > ref_e]
            def steps(xs: list[float]) -> str:
                return ("at ε = " + ", ".join(f"{x:g}" for x in xs)) if xs else \
                    "at none of the steps tried"

            out += ["", f"{big[0]['nodes']} nodes at ε = {big[0]['step']:g} cover "
                    f"{ref_r:.1f} % at r = {study['r_base']:g} and {ref_e:.1f} % at "
                    f"r = {_eps(study['c_eps'])}. {min(sizes)} nodes do better "
                    f"{steps(beat_r)} with r = {study['r_base']:g}, and {steps(beat_e)} "
                    f"with r = {_eps(study['c_eps'])}. A 200/40 run is complete by its end, "
                    "so no step budget can raise its coverage above these values."]
        if study.get("scales"):
            out += ["", "**The map's scale** (unknown: the figures carry no units). A map s "
                    "times larger is ours with ε and r divided by s; 200/40 against 800/20 at "
                    "range r:", "",
                    f"| scale s | 200/40, r = {study['r_base']:g} | 800/20, r = "
                    f"{study['r_base']:g} | 200/40, r = {_eps(study['c_eps'])} | 800/20, "
                    f"r = {_eps(study['c_eps'])} |", "|---:|---:|---:|---:|---:|"]
            for row in study["scales"]:
                out.append(f"| {row['scale']:g} | {row['200_40_r25']:.1f} | "
                           f"{row['800_20_r25']:.1f} | {row['200_40_eps']:.1f} | "
                           f"{row['800_20_eps']:.1f} |")
    if t1e:
        table, fin = _rerun_table(t1e, t1, lambda b, r: (
            _fmt(b["ours_wma"], b["ours_wma_sd"]), _fmt(r["ours_wma"], r["ours_wma_sd"]),
            _fmt(r["ours_prm"], r["ours_prm_sd"])))
        out += ["", f"**Table 1 rerun with r = {_eps(study['c_eps'] if study else 1.0)}** "
                f"({t1e[0]['runs']} runs per row; the ∞ rows do not change):", "", *table]
        g = gain_summary(t1e)
        out += ["", f"- Mean |ours − paper| over these {len(t1e)} rows: WMA-RRT "
                f"{mae(fin):.1f} points with r = 25, {mae(t1e):.1f} with r = ε; PRM with "
                f"r = ε {g['mae_prm']:.1f}. WMA-RRT ≥ PRM in {g['ours_ge']}/{g['n']} rows "
                f"(paper {g['paper_ge']}/{g['n']}).",
                f"- At range r: 200/40 {_cov(fin, 200, 40):.1f} vs 800/20 "
                f"{_cov(fin, 800, 20):.1f} with r = 25; {_cov(t1e, 200, 40):.1f} vs "
                f"{_cov(t1e, 800, 20):.1f} with r = ε (paper 88 vs 83). 200/40 vs 400/20 "
                f"(equal tree length): {_cov(fin, 200, 40):.1f} vs {_cov(fin, 400, 20):.1f} "
                f"with r = 25, {_cov(t1e, 200, 40):.1f} vs {_cov(t1e, 400, 20):.1f} with "
                "r = ε (paper 88 vs 74)."]
    if t2e:
        table, b2 = _rerun_table(t2e, t2, lambda b, r: (
            _fmt(b["ours_wma"], None, 0),
            f"{_fmt(r['ours_wma'], None, 0)} ({r['found_wma']}/{r['runs']})",
            _fmt(r["ours_prm"], None, 0)))
        out += ["", "**Table 2 rerun with r = ε** (goal found, % of runs):", "", *table,
                "", "- Mean |ours − paper| (WMA-RRT) over these rows: "
                f"{mae(b2):.1f} points with r = 25, {mae(t2e):.1f} with r = ε."]
    out.append("")
    return out


def _markdown(t1, t2, g1, g2, cov_imp, srch_imp, un, figs, quick, seconds, version, r_base,
              prm_all, multi, results, new_runs) -> list[str]:
    n1 = t1[0]["runs"] if t1 else 0
    n2 = t2[0]["runs"] if t2 else 0
    wma_all = [r for r in results if r["planner"].startswith("wma-rrt")]
    out = [
        "# Seed 004 reproduction: WMA-RRT coverage and goal search against PRM",
        "",
        f"swarmex {version}; {'QUICK run (1 run per row: a smoke test, not a result)' if quick else 'full run'}; "  # noqa: E501
        f"{len(results)} runs, {new_runs} of them in this invocation ({seconds:.0f} s), the "
        f"rest read back from `roadmap_runs.jsonl`; the runs' own times add up to "
        f"{sum(r.get('wall_seconds') or 0 for r in results):.0f} s (a sum over runs, "
        "including those read back, not the wall time of an invocation: runs on parallel "
        "workers overlap). "
        f"Regenerate with `swarmex reproduce roadmap{' --quick' if quick else ''} --out DIR` "
        "(runs already in the journal are not rerun; delete it to start over).",
        "",
        "## Setup (what the paper leaves open, fixed here)",
        "",
        "- **Environments** (`examples/roadmap_fig8.json`, `roadmap_fig11.json`, "
        "`roadmap_fig14.json`, `roadmap_fig17.json`), 640 × 480 units, drawn after the "
        "figures, which are not in the text: Fig. 8 is cluttered with a walled room entered "
        "through one door; Fig. 11 hides the goal in a nook open towards the start region; "
        "Figs. 14–17 wall the team in, with the goal outside.",
        "- **Team**: 3 agents (Fig. 5), a tight cluster in the lower-left corner "
        "(radius 6.4 units). Their hull is a triangle, which has no diagonals to cross, so "
        "every tree here takes its Main Root at the hull's centroid (docs/roadmap.md §1); "
        "the paper's crossing of the two longest diagonals needs four or more agents, and "
        "is checked only in the tests.",
        f"- **Sensor range r = {r_base:g} units** (1.25 ε for ε = 20). The paper never gives r. "
        "A complete WMA-RRT run traverses every edge, so its coverage is fixed by the tree and "
        "the sensor alone; trees for 5 seeds of each (nodes, step) were swept with "
        "r ∈ {15, 20, …, 40}: r = 30 fitted the 15 finite-range rows of Table 1 best "
        "(RMSE 5.37 points) and r = 25 within 0.1 of it (5.45; 20 → 6.6, 15 → 10.1, "
        "35 → 5.7); we took the smaller of the two (\"Sensor range fitted\" below). "
        "So Table 1's r rows are a one-parameter fit; the 2r, 4r and ∞ rows, Table 2 and "
        "the PRM columns are predictions. The finite rows of both tables are also run with "
        "r = ε, the other reading of the unstated r (a one-parameter fit too, and a better "
        "one: see \"The unreproduced claim\").",
        "- **Sensor model**: disc of radius R cut by line of sight, swept continuously along "
        "every traversed segment (viewpoints one raster cell apart); coverage measured on a "
        "256 × 192 raster (2.5-unit cells) of the free space.",
        "- **Fig. 11 goal** at (250, 230): four positions were tried, (220, 200), (250, 230), "
        "(280, 220), (300, 250) — all gave the paper's regime (∞ rows 100 %, r rows 60–85 %); "
        "the second was kept. The placement rule came from the paper: at ∞ the goal must be "
        "in sight from the start region in every run.",
        "- **PRM baseline**: the paper's own description of multiple-query planners — "
        "max(2, n) trees grown from random free points with the same ε and node budget, "
        "merged PRM-style by joining nodes closer than 2ε with free segments. Agents enter "
        "at the nearest visible node, walk by the same minimum-weight rule, and stop at the "
        "step budget 2K (they have no completion test).",
        f"- **Runs**: Table 1 {n1} and Table 2 {n2} per row and planner; run i uses seed i, so "
        "any cell can be rerun with `swarmex roadmap --env examples/roadmap_fig8.json "
        f"--agents 3 --nodes K --step E --sensor-range {r_base:g} --seed i` "
        "(`--sensor-range 1eps` for the r = ε rows).",
        "",
        "## Table 1: coverage (%) of the Fig. 8 environment",
        "",
        "| nodes | step | sensor | paper WMA-RRT | ours WMA-RRT | paper PRM | ours PRM | "
        "ours PRM components |",
        "|---:|---:|:---:|---:|---:|---:|---:|---:|",
    ]
    for r in t1:
        out.append(
            f"| {r['nodes']} | {r['step']} | {_label(r['sensor'])} | {r['paper_wma']:.0f} | "
            f"{_fmt(r['ours_wma'], r['ours_wma_sd'])} | {r['paper_prm']:.0f} | "
            f"{_fmt(r['ours_prm'], r['ours_prm_sd'])} | {_fmt(r['prm_components'], None, 2)} |"
        )
    out += [
        "",
        f"- WMA-RRT ≥ PRM in {g1['ours_ge']}/{g1['n']} rows (paper: {g1['paper_ge']}/{g1['n']}); "
        f"mean gain {g1['ours_mean']:+.1f} points (paper {g1['paper_mean']:+.1f}).",
        f"- Mean |ours − paper|: WMA-RRT {g1['mae_wma']:.1f} points, PRM {g1['mae_prm']:.1f}.",
        "- Trends shared with the paper: coverage rises with the number of nodes, with the step "
        "size at equal nodes and with the sensor range; ∞ gives 99–100 % "
        "(occlusion by walls is why the paper's ∞ is 99 %, not 100).",
        "- Not shared: the paper has 200 nodes at step 40 beating 800 nodes at step 20 "
        "(88 vs 83 at r). With coverage set by where the tree goes, 800 × 20 units of tree "
        "outreach 200 × 40 here. Every reading we checked (below, \"The unreproduced "
        "claim\") keeps that order; r = ε reproduces the paper's other step effect "
        "(200/40 over 400/20 at equal tree length) but not this one.",
        "- `wma-rrt-takeover` builds the same tree from the same seed and also traverses every "
        "edge, so its coverage equals WMA-RRT's run for run; it differs in time (below).",
        "",
        "### Fig. 6: coverage against the number of sample points (step 40, range r)",
        "",
        "![Fig. 6](fig6_coverage_vs_samples.png)",
        "",
        "## Table 2: goal found by some agent (% of runs), Fig. 11 environment",
        "",
        "| nodes | step | sensor | paper WMA-RRT | ours WMA-RRT | paper PRM | ours PRM |",
        "|---:|---:|:---:|---:|---:|---:|---:|",
    ]
    for r in t2:
        out.append(
            f"| {r['nodes']} | {r['step']} | {_label(r['sensor'])} | {r['paper_wma']:.0f} | "
            f"{_fmt(r['ours_wma'], None, 0)} ({r['found_wma']}/{r['runs']}) | "
            f"{r['paper_prm']:.0f} | {_fmt(r['ours_prm'], None, 0)} ({r['found_prm']}/{r['runs']}) |"  # noqa: E501
        )
    out += [
        "",
        f"- WMA-RRT ≥ PRM in {g2['ours_ge']}/{g2['n']} rows (paper: {g2['paper_ge']}/{g2['n']}); "
        f"mean gain {g2['ours_mean']:+.1f} points (paper {g2['paper_mean']:+.1f}).",
        f"- Mean |ours − paper|: WMA-RRT {g2['mae_wma']:.1f} points, PRM {g2['mae_prm']:.1f}. "
        "(With 30 runs a row moves in steps of 3.3 points; the paper's PRM column has values "
        "that are not multiples of 1/30.)",
        "",
        "## Figs. 12–13: components",
        "",
        f"Every WMA-RRT built in this reproduction ({len(wma_all)} runs) has exactly 1 "
        f"component and 0 cycles. Of {len(prm_all)} PRM roadmaps in Tables 1–2, {multi} "
        f"({100 * multi / max(len(prm_all), 1):.0f} %) have more than one component; they "
        f"have {np.mean([r['cycles'] for r in prm_all]) if prm_all else float('nan'):.0f} "
        "independent cycles on average (Fig. 7's loops).",
        "",
        "## Figs. 14–17: unreachable goal",
        "",
        f"{UNREACH_DESC}",
        "",
        "| env | planner | runs | goal found | unreachable established | complete | ended by "
        "budget | mean steps | mean edge revisits | runs with agents off the roadmap | "
        "mean components |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in un:
        out.append(
            f"| {r['env']} | {r['planner']} | {r['runs']} | {r['found']} | {r['unreachable']} | "
            f"{r['complete']} | {r['budget']} | {r['steps']:.0f} | {r['revisits']:.0f} | "
            f"{r['off']} | {r['components']:.1f} |"
        )
    out += [
        "",
        "WMA-RRT agents always finish their branches, flag them COMPLETE and so *know* the goal "
        "cannot be reached from where they are (Fig. 16); PRM agents cannot: they walk until "
        "the step budget, re-traversing edges (Fig. 15), or — when no PRM tree happened to "
        "start inside the walls — cannot even join the roadmap (Fig. 12's failure). Moving "
        "the start outside (Fig. 17) lets the team find the goal.",
        "",
        "## Beyond the seed: helpers that take over the largest unfinished sub-branch",
        "",
        "`--planner wma-rrt-takeover` keeps the tree, the weights, Sync/Weight, the dedicated "
        "copies and the ½ marks, and adds two counters per edge to the roadmap: untraversed "
        "edges beneath it and agents beneath it. Agents pick the child edge with the largest "
        "fair share (untraversed / (agents + 1)); free agents go to the branch of largest "
        "share. In the paper's rule a helper trails the owner's frontier (weight-1 edges) and "
        "only picks up what lies next to it.",
        "",
        "Coverage, Fig. 8 environment, rows with range r (steps until every branch is "
        "COMPLETE; total path of the team):",
        "",
        "| nodes | step | runs | steps WMA-RRT | steps takeover | ratio | path WMA-RRT | "
        "path takeover | edge revisits WMA-RRT | takeover |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in cov_imp:
        out.append(
            f"| {r['nodes']} | {r['step']} | {r['runs_base']} | {r['steps_base']:.0f} | "
            f"{r['steps_takeover']:.0f} | {r['steps_takeover'] / r['steps_base']:.2f} | "
            f"{r['path_base']:.0f} | {r['path_takeover']:.0f} | {r['revisits_base']:.0f} | "
            f"{r['revisits_takeover']:.0f} |"
        )
    if cov_imp:
        st = np.array([r["steps_takeover"] / r["steps_base"] for r in cov_imp])
        pa = np.array([r["path_takeover"] / r["path_base"] for r in cov_imp])
        out += ["", f"Over these rows the takeover rule needs {np.mean(st):.2f}× the steps of "
                    f"the paper's rule (range {st.min():.2f}–{st.max():.2f}) and "
                    f"{np.mean(pa):.2f}× its total path: it trades extra walking by helpers "
                    "for an earlier end."]
    out += [
        "",
        "![coverage makespan](improvement_coverage_steps.png)",
        "",
        "Goal search, Fig. 11 environment, rows with range r (step of the first sighting and "
        "step when all three stand on the goal, over successful runs):",
        "",
        "| nodes | step | runs | success WMA-RRT | takeover | first found WMA-RRT | takeover | "
        "all at goal WMA-RRT | takeover |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in srch_imp:
        out.append(
            f"| {r['nodes']} | {r['step']} | {r['runs_base']} | {r['success_base']:.0f} % | "
            f"{r['success_takeover']:.0f} % | {_fmt(r['found_base'], None, 0)} | "
            f"{_fmt(r['found_takeover'], None, 0)} | {_fmt(r['all_base'], None, 0)} | "
            f"{_fmt(r['all_takeover'], None, 0)} |"
        )
    both = [r for r in srch_imp if not (np.isnan(r["found_base"]) or np.isnan(r["found_takeover"]))]
    verdict = ""
    if both:
        fr = np.array([r["found_takeover"] / r["found_base"] for r in both])
        al = np.array([r["all_takeover"] / r["all_base"] for r in both])
        verdict = (f" Here the takeover rule's first sighting comes at {np.mean(fr):.2f}× the "
                   f"paper's rule's step and all agents stand on the goal at {np.mean(al):.2f}× "
                   "(mean of row ratios). Search time depends on where the goal lies relative "
                   "to the large sub-branches the takeover rule visits first, so this part of "
                   "the improvement is environment-dependent; coverage makespan is the claim.")
    out += [
        "",
        "Success rates are equal by construction: the same seed builds the same tree, and "
        "every edge is eventually swept unless the goal is found first." + verdict,
        "",
        "## Figures",
        "",
    ]
    for name, title in figs.items():
        out += [f"### {title}", "", f"![{title}]({name})", ""]
    return out


UNREACH_DESC = (
    "Fig. 14 environment: the team starts in the lower-left corner, walled in by the bounds "
    "and two walls; the goal is outside. 400 nodes, ε = 20, range r. Fig. 17: the same walls, "
    "the start moved outside."
)


NAMES = {"wma-rrt": "WMA-RRT", "prm": "PRM (ours)", "ompl-prm": "OMPL PRM",
         "ompl-rrt": "OMPL RRT"}


def _ci_cell(c: dict[str, Any], digits: int = 1) -> str:
    if not c["n"]:
        return "–"
    if np.isnan(c["low"]):
        return f"{c['mean']:.{digits}f}"
    return f"{c['mean']:.{digits}f} [{c['low']:.{digits}f}, {c['high']:.{digits}f}]"


def _diff_cell(d: tuple[float, float, float] | None, digits: int) -> str:
    if d is None:
        return "–"
    if np.isnan(d[1]):
        return f"{d[0]:+.{digits}f}"
    return f"{d[0]:+.{digits}f} [{d[1]:+.{digits}f}, {d[2]:+.{digits}f}]"


def _winner_label(w: str) -> str:
    if w.startswith("tie: "):
        a, b = w[5:].split(" ≈ ")
        return f"tie ({NAMES.get(a, a)} ≈ {NAMES.get(b, b)})"
    return f"**{NAMES.get(w, w)}**"


def _claim_counts(rows: list[dict[str, Any]],
                  key: str = "wma_minus_ompl") -> tuple[int, int, int, int]:
    """Rows with the WMA-RRT − OMPL PRM difference ``key``: (rows, WMA-RRT significantly
    better, not significantly different, OMPL PRM significantly better)."""
    diffs = [r[key] for r in rows if key in r]
    better = sum(1 for _, lo, _hi in diffs if lo > 0)
    worse = sum(1 for _, _lo, hi in diffs if hi < 0)
    return len(diffs), better, len(diffs) - better - worse, worse


def standard_prm_section(v1: list[dict[str, Any]], v2: list[dict[str, Any]],
                         builds: dict[str, Any] | None, ompl: bool) -> list[str]:
    """OMPL's PRM beside the project's: per-row winners with intervals, and build times."""
    out = ["## A standard PRM: OMPL's (`--planner ompl-prm`)", ""]
    if not ompl:
        out += ["OMPL's PRM was not run: its Python bindings are not installed "
                "(`pip install 'swarmex[ompl]'`).", ""]
    else:
        out += [
            "The PRM the paper compares with is only described; ours (above) is built the way "
            "it describes multiple-query planners. Here the textbook planner runs beside it, "
            "as OMPL implements it (`ompl.geometric.PRM`: a free milestone at a time, joined "
            "to its 10 nearest milestones by free segments): the same environments, the same "
            "node budget K (milestones), the same team, sensor and walkers (the minimum-"
            "weight walk and the step budget 2K of our PRM), the run's seed drawing the "
            "milestones. OMPL's PRM has no step: its edges are as long as the nearest-"
            "neighbour connections make them, so a walker's step can cover several ε (the "
            "path columns show how much farther its team walks).",
            "",
            "Cells: mean [95 % interval] over the seeds (coverage: Student's t; goal found: "
            "Wilson). Winner: the highest mean when the 95 % interval of its difference to "
            "the runner-up excludes 0 (Welch for coverage, Newcombe for rates), else a tie. "
            "Then: WMA-RRT − OMPL PRM with its interval, and the team's path of OMPL PRM "
            "over WMA-RRT's. Since OMPL's walkers step farther, Table 1 also stops each "
            "OMPL PRM run where its team had walked as far as the WMA-RRT team of the row did "
            "in all (its coverage at equal travel, from the run's coverage-against-path "
            "curve) and compares again.",
            "",
        ]
        for title, rows, digits in (
                ("Table 1 rows: coverage (%), Fig. 8 environment", v1, 1),
                ("Table 2 rows: goal found (% of runs), Fig. 11 environment", v2, 0)):
            equal = digits == 1
            out += [f"**{title}**", "",
                    "| nodes | step | sensor | WMA-RRT | PRM (ours) | OMPL PRM | winner | "
                    "WMA-RRT − OMPL PRM | path OMPL / WMA |"
                    + (" OMPL PRM at WMA-RRT's travel | WMA-RRT − it |" if equal else ""),
                    "|---:|---:|:---:|---:|---:|---:|:---|---:|---:|"
                    + ("---:|---:|" if equal else "")]
            for r in rows:
                c = r["cells"]
                d = r.get("wma_minus_ompl")
                dcell = _diff_cell(d, digits)
                pw, po = c["wma-rrt"]["path"], c["ompl-prm"]["path"]
                ratio = f"{po / pw:.1f}×" if pw and not np.isnan(pw) and not np.isnan(po) \
                    else "–"
                tail = ""
                if equal:
                    e = r.get("wma_minus_ompl_equal")
                    tail = (f" {_ci_cell(c[EQUAL])} | " if EQUAL in c else " – | ") + \
                        _diff_cell(e, 1) + " |"
                out.append(f"| {r['nodes']} | {r['step']} | {_label(r['sensor'])} | "
                           f"{_ci_cell(c['wma-rrt'], digits)} | {_ci_cell(c['prm'], digits)} | "
                           f"{_ci_cell(c['ompl-prm'], digits)} | {_winner_label(r['winner'])} | "
                           f"{dcell} | {ratio} |" + tail)
            n, better, same, worse = _claim_counts(rows)
            wins: dict[str, int] = {}
            for r in rows:
                key = "tie" if r["winner"].startswith("tie") else r["winner"]
                wins[key] = wins.get(key, 0) + 1
            tally = ", ".join(f"{NAMES.get(k, k)} {v}" for k, v in sorted(wins.items()))
            out += ["", f"- Winners over the {len(rows)} rows: {tally}.",
                    f"- The paper's claim against OMPL's PRM: WMA-RRT significantly better in "
                    f"{better}/{n} rows, no significant difference in {same}, OMPL PRM "
                    f"significantly better in {worse}."]
            if equal:
                n, better, same, worse = _claim_counts(rows, "wma_minus_ompl_equal")
                out += [f"- At equal travel: WMA-RRT significantly better in {better}/{n} "
                        f"rows, no significant difference in {same}, OMPL PRM significantly "
                        f"better in {worse}."]
            out.append("")
    if builds and builds.get("rows"):
        names = builds["builders"]
        out += [f"**Build (pre-processing) time**, CPU milliseconds per roadmap (mean of "
                f"{builds['seeds']} seeds; Fig. 8 environment, the reproduction's team; "
                "`time.process_time` in one process, after a warm-up build of each; × = "
                "ratio to WMA-RRT measured in the same process). OMPL's planners call our "
                "sampler and our exact segment test from C++, once per sample and per motion "
                "check.", "",
                "| nodes | step | " + " | ".join(NAMES[b] for b in names) + " | edges: "
                + " / ".join(NAMES[b] for b in names) + " |",
                "|---:|---:|" + "---:|" * len(names) + "---:|"]
        for r in builds["rows"]:
            base = r["wma-rrt"]["ms"]
            cells = [f"{r[b]['ms']:.1f}" + ("" if b == "wma-rrt" else
                                             f" ({r[b]['ms'] / base:.1f}×)") for b in names]
            edges = " / ".join(f"{r[b]['edges']:.0f}" for b in names)
            out.append(f"| {r['nodes']} | {r['step']:g} | " + " | ".join(cells) +
                       f" | {edges} |")
        ratios = {b: float(np.mean([r[b]["ms"] / r["wma-rrt"]["ms"] for r in builds["rows"]]))
                  for b in names if b != "wma-rrt"}
        out += ["", "- Mean ratio to WMA-RRT over these configurations: "
                + ", ".join(f"{NAMES[b]} {v:.2f}×" for b, v in ratios.items()) + ".", ""]
    return out
