"""The figures of ``swarmex reproduce exploration``: seed 003's Figs. 4.1–4.4, and strategies.

* Fig. 4.1 — mean exploration steps of a team member against team size, one curve per
  communication range, (a) laser 2 m, (b) laser 1.5 m; error bars are the spread (standard
  deviation) over the repetitions.
* Fig. 4.2 — the paths after exploration for 1, 2 and 5 robots, laser 2 m (top) and 1.5 m.
* Fig. 4.3 — 10 robots, 20 m radio: the team map at four moments, with the exclusion disc
  (laser-range radius, the thesis's yellow circle) around each robot's current goal.
* Fig. 4.4 — the interval between consecutive plan generations, per robot (thin) and for
  the robot with the median number of plans (bold: "an average robot"), for 1, 2, 5, 10.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from swarmex.engine.stats import summarize
from swarmex.viz.exploration import Snapshot, draw


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def fig4_1(table: dict[tuple[float, float, int], list[float]], lasers, comms, sizes,
           path: Path) -> Path:
    """``table[(laser, comm, n)]`` = the runs' mean steps."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(lasers), figsize=(5.2 * len(lasers), 3.8), dpi=120,
                             squeeze=False)
    for ax, laser, letter in zip(axes[0], lasers, "abcd", strict=False):
        for comm in comms:
            xs = [n for n in sizes if table.get((laser, comm, n))]
            mu = [float(np.mean(table[(laser, comm, n)])) for n in xs]
            sd = [_sd(table[(laser, comm, n)]) for n in xs]
            ax.errorbar(xs, mu, yerr=sd, marker="o", ms=3, capsize=2, label=f"comm {comm:g} m")
        ax.set_xlabel("team size")
        ax.set_ylabel("mean exploration steps of a team member")
        ax.set_title(f"({letter}) laser range {laser:g} m", fontsize=9)
        ax.set_xticks(list(sizes))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Fig. 4.1 — steps against team size (swarmex)", fontsize=10)
    return _save(fig, path, plt)


def fig4_2(panels: list[dict[str, Any]], path: Path) -> Path:
    """Panels (row-major, 2 × 3): each {"snap", "trajectories", "truth", "title"}."""
    plt = _plt()
    fig, axes = plt.subplots(2, 3, figsize=(10, 6.8), dpi=120)
    for ax, p, letter in zip(axes.ravel(), panels, "abcdef", strict=False):
        draw(ax, p["snap"], p["trajectories"], p["truth"], f"({letter}) {p['title']}")
    fig.suptitle("Fig. 4.2 — paths after exploration; laser 2 m (top), 1.5 m (bottom)",
                 fontsize=10)
    return _save(fig, path, plt)


def fig4_3(snaps: list[Snapshot], trajectories, truth, laser_cells: float, captions: list[str],
           path: Path) -> Path:
    plt = _plt()
    fig, axes = plt.subplots(1, len(snaps), figsize=(3.4 * len(snaps), 3.8), dpi=120)
    for ax, s, cap, letter in zip(axes, snaps, captions, "abcd", strict=False):
        draw(ax, s, trajectories, truth, f"({letter}) {cap}", laser_cells=laser_cells)
    fig.suptitle("Fig. 4.3 — 10 robots, 20 m radio, laser 2 m: paths and goals' exclusion "
                 "discs", fontsize=10)
    return _save(fig, path, plt)


def median_robot(plan_ticks: list[list[int]]) -> int:
    counts = [len(t) for t in plan_ticks]
    order = np.argsort(counts, kind="stable")
    return int(order[len(order) // 2])


def fig4_4(series: dict[int, list[list[int]]], period: int, path: Path) -> Path:
    """``series[n]`` = each robot's plan ticks in one run with ``n`` robots."""
    plt = _plt()
    sizes = sorted(series)
    fig, axes = plt.subplots(1, len(sizes), figsize=(3.6 * len(sizes), 3.2), dpi=120,
                             squeeze=False)
    for ax, n, letter in zip(axes[0], sizes, "abcdefgh", strict=False):
        ticks = series[n]
        for t in ticks:
            iv = np.diff(t)
            ax.plot(np.arange(1, len(iv) + 1), iv, "-", color="0.75", lw=0.6)
        m = median_robot(ticks)
        iv = np.diff(ticks[m])
        ax.plot(np.arange(1, len(iv) + 1), iv, "-", color="C3", lw=1.3, label=f"robot {m}")
        ax.axhline(period, color="C0", ls=":", lw=0.8)
        ax.set_title(f"({letter}) {n} robot{'s' if n > 1 else ''}", fontsize=9)
        ax.set_xlabel("plan generation")
        ax.set_ylabel("steps since the previous one")
        # the legend in a band of its own above the data (lower left, it covered the
        # median robot's line where the intervals fall to 1 at the end)
        ax.set_ylim(0, period * 1.9)
        ax.legend(fontsize=7, loc="upper right")
    fig.suptitle("Fig. 4.4 — plan-generation intervals (laser 2 m, 20 m radio); thin: every "
                 "robot, bold: the median robot", fontsize=10)
    return _save(fig, path, plt)


def fig_strategies(rows: list[dict[str, Any]], scenarios: list[str], strategies: list[str],
                   path: Path) -> Path:
    """Bars of the mean makespan (± spread) per scenario and strategy."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(scenarios), figsize=(3.6 * len(scenarios), 3.4), dpi=120,
                             squeeze=False)
    for ax, sc in zip(axes[0], scenarios, strict=False):
        mus, sds = [], []
        for st in strategies:
            vals = [r["makespan"] for r in rows if r["scenario"] == sc and r["strategy"] == st]
            mus.append(np.mean(vals) if vals else np.nan)
            sds.append(_sd(vals))
        ax.bar(range(len(strategies)), mus, yerr=sds, capsize=2,
               color=[f"C{i}" for i in range(len(strategies))])
        ax.set_xticks(range(len(strategies)))
        ax.set_xticklabels(strategies, rotation=35, ha="right", fontsize=7)
        ax.set_title(sc, fontsize=8)
        ax.set_ylabel("steps until the whole team finished")
        ax.grid(axis="y", alpha=0.3)
    fig.suptitle("Coordination strategies on the same maps and seeds", fontsize=10)
    return _save(fig, path, plt)


def _save(fig, path: Path, plt) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, bbox_inches="tight")
    plt.close(fig)
    return path


def _sd(vals: list[float]) -> float:
    """The error bar: the sample SD (n − 1) of the runs, as the report's "± sd"; none for
    fewer than two runs."""
    return float(np.nan_to_num(summarize(vals).std))
