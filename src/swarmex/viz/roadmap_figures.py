"""Charts of the roadmap reproduction: Fig. 6 (coverage against sample points) and the
improvement comparison (steps to complete coverage per planner)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


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
