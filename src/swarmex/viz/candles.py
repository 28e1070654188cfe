"""Candlestick charts in the style of seed 000's figures, for any reproduction.

The thesis draws every result as a "candlestick": whiskers from the minimum to the maximum
over all runs, and a body spanning the 95 % confidence interval of the mean (§5.1.2). We draw
exactly that (plus a tick at the mean, which the thesis does not have but which makes small
bodies readable), and overlay the seed's own numbers where it states them: a full hollow
candle when the seed gives the statistics (Tables 5.1–5.2), otherwise a marker at the stated
value, so a reader sees at a glance how far our bars are from what the seed reports.
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: reproductions run headless, in workers and in CI
import matplotlib.pyplot as plt  # noqa: E402

from swarmex.engine.stats import Summary  # noqa: E402
from swarmex.viz.files import save_figure  # noqa: E402

OURS = "#1f77b4"
THEIRS = "#d62728"


@dataclass(frozen=True)
class Reference:
    """A value the seed states: at one bar (``index``) or for every bar (``index`` None)."""

    value: float
    label: str
    index: int | None = None


def draw_candles(
    ax,
    summaries: Sequence[Summary],
    positions: Sequence[float],
    color: str = OURS,
    width: float = 0.5,
    hollow: bool = False,
    label: str | None = None,
) -> None:
    """Whiskers min–max, body = CI (none where it is undefined), a tick at the mean."""
    # the legend entry goes on the first body, or on the first whisker if no bar has an
    # interval (one run each), so the series still has its entry
    labelled = False
    whisker_label = None if any(s.has_ci for s in summaries) else label
    for x, s in zip(positions, summaries, strict=True):
        ax.vlines(x, s.min, s.max, color=color, linewidth=1.2,
                  label=None if labelled else whisker_label)
        labelled = labelled or whisker_label is not None
        for y in (s.min, s.max):
            ax.hlines(y, x - width / 4, x + width / 4, color=color, linewidth=1.2)
        # the mean tick (lines are drawn above patches, so above the body too)
        ax.hlines(s.mean, x - width / 2, x + width / 2, color="black", linewidth=0.9)
        if not s.has_ci:  # no interval (a single run): whiskers and the mean tick only
            continue
        body = max(s.ci_high - s.ci_low, 1e-9)
        ax.add_patch(
            plt.Rectangle(
                (x - width / 2, s.ci_low),
                width,
                body,
                facecolor="none" if hollow else color,
                edgecolor=color,
                alpha=1.0 if hollow else 0.55,
                linewidth=1.4,
                label=None if labelled else label,
            )
        )
        labelled = True


def candle_chart(
    path: Path,
    labels: Sequence[str],
    ours: Sequence[Summary],
    title: str,
    xlabel: str,
    ylabel: str,
    theirs: Sequence[Summary | None] | None = None,
    references: Sequence[Reference] = (),
    note: str | None = None,
) -> Path:
    """One PNG: our candles per bar, the seed's candles beside them, stated values on top."""
    fig, ax = plt.subplots(figsize=(max(5.0, 0.75 * len(labels) + 2.5), 4.2), dpi=110)
    xs = list(range(len(labels)))
    paired = theirs is not None and any(t is not None for t in theirs)
    shift = 0.2 if paired else 0.0
    width = 0.36 if paired else 0.5
    draw_candles(ax, ours, [x - shift for x in xs], width=width, label="swarmex (95 % CI)")
    if paired and theirs is not None:  # paired implies theirs is given
        pairs = [(x + shift, t) for x, t in zip(xs, theirs, strict=True) if t is not None]
        draw_candles(
            ax,
            [t for _, t in pairs],
            [x for x, _ in pairs],
            color=THEIRS,
            width=width,
            hollow=True,
            label="thesis (95 % CI)",
        )
    for j, ref in enumerate(references):
        lab = ref.label if j == 0 or ref.label != references[j - 1].label else None
        if ref.index is None:
            ax.axhline(ref.value, color=THEIRS, linestyle="--", linewidth=1.0, label=lab)
        else:
            ax.plot(
                [ref.index + shift],
                [ref.value],
                marker="D",
                color=THEIRS,
                linestyle="none",
                markersize=7,
                markerfacecolor="none",
                markeredgewidth=1.6,
                label=lab,
            )
    ax.set_xticks(xs)
    ax.set_xticklabels(labels)
    ax.set_xlim(-0.7, len(labels) - 0.3)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    width_chars = int(fig.get_figwidth() * 11)  # ~11 characters per inch at 10 pt
    ax.set_title("\n".join(textwrap.wrap(title, width_chars)), fontsize=10)
    ax.grid(axis="y", alpha=0.3)
    # beside the axes: "best" does not avoid the whiskers (line collections), and covered
    # the thesis's caps
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    if note:
        fig.text(0.01, 0.01, note, fontsize=7, color="dimgray")
    fig.tight_layout(rect=(0, 0.03 if note else 0, 1, 1))
    try:
        return save_figure(fig, Path(path))
    finally:
        plt.close(fig)
