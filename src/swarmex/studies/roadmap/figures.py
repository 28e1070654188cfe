"""The figures of ``swarmex reproduce roadmap``: Fig. 6 (coverage against sample points), the
improvement comparison (steps to complete coverage per planner), and single runs of the
paper's environments redrawn (:func:`draw_examples`, Figs. 8–17)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from swarmex.studies.roadmap.analysis import pick  # noqa: E402
from swarmex.studies.roadmap.design import AGENTS, R_BASE, world  # noqa: E402


def fig6(path: Path, nodes: Sequence[int], series: dict[str, tuple[list[float], list[float]]],
         title: str) -> Path:
    """``series``: label → (means, standard deviations) over ``nodes`` (sd may be zeros)."""
    fig, ax = plt.subplots(figsize=(6, 4), dpi=110)
    styles = {"paper": "--", "ours": "-"}
    for label, (mean, sd) in series.items():
        ls = styles["paper"] if "paper" in label else styles["ours"]
        ax.errorbar(nodes, mean, yerr=sd, fmt="o" + ls, capsize=3, label=label)
    ax.set_xlabel("number of sample points (nodes)")
    ax.set_ylabel("area coverage (%)")
    ax.set_xticks(list(nodes))
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def bars(path: Path, groups: Sequence[str], series: dict[str, list[float]], ylabel: str,
         title: str) -> Path:
    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    x = np.arange(len(groups))
    width = 0.8 / max(len(series), 1)
    for k, (label, vals) in enumerate(series.items()):
        ax.bar(x + (k - (len(series) - 1) / 2) * width, vals, width, label=label)
    ax.set_xticks(x, groups, fontsize=8)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def draw_examples(out: Path, results: list[dict[str, Any]]) -> dict[str, str]:
    """Rerun a few single seeds and draw them (cheap; the sweep keeps no trajectories)."""
    from swarmex.missions.roadmap.scenario import make_scenario
    from swarmex.viz.roadmap_plot import render_png

    prm15 = [r for r in pick(results, exp="unreach", env="fig14", planner="prm")
             if not r.get("agents_off_roadmap")]
    seed15 = prm15[0]["seed"] if prm15 else 0
    r = f"r={R_BASE:g}"  # the sensor range these pictures use (the title said a bare "r")
    specs = {
        "fig8_wma_rrt.png": ("fig8", "coverage", "wma-rrt", 400, 20, 0,
                             f"Fig. 8 environment, WMA-RRT coverage (400 nodes, ε=20, {r})"),
        "fig8_prm.png": ("fig8", "coverage", "prm", 400, 20, 0,
                         f"Fig. 8 environment, PRM coverage (400 nodes, ε=20, {r})"),
        "fig11_wma_rrt.png": ("fig11", "search", "wma-rrt", 200, 20, 0,
                              f"Fig. 11 environment, WMA-RRT goal search (200 nodes, ε=20, {r})"),
        "fig16_wma_rrt.png": ("fig14", "search", "wma-rrt", 400, 20, 0,
                              "Figs. 14/16: walled-in team, WMA-RRT establishes unreachable"),
        "fig15_prm.png": ("fig14", "search", "prm", 400, 20, seed15,
                          f"Fig. 15: walled-in team on a PRM (seed {seed15}): no end"),
        "fig17_wma_rrt.png": ("fig17", "search", "wma-rrt", 400, 20, 0,
                              "Fig. 17: start moved outside, WMA-RRT finds the goal"),
    }
    made = {}
    for name, (env, task, planner, nodes, step, seed, title) in specs.items():
        sc = make_scenario(world(env), agents=AGENTS, nodes=nodes, step=step,
                           sensor_range=R_BASE, task=task, planner=planner, seed=seed)
        run = sc.run()
        render_png(run, out / name, title=f"{title}\n" + _title_tail(run))
        made[name] = title
    return made


def _title_tail(run: Any) -> str:
    s = f"steps {run.steps}, coverage {100 * run.raster.coverage():.1f}%"
    if run.task == "search":
        s += (", goal found" if run.goal_found
              else ", goal unreachable (all branches COMPLETE)" if run.goal_unreachable
              else ", goal not found, step budget exhausted")
    return s
