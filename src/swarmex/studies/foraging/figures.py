"""The figures of ``swarmex reproduce foraging``: seed 002's Figs. 56–77 from the mean table.

The thesis's figures are bar charts of mean times per pattern and number of robots; we draw the
same quantities with the same numbering so the report can refer to them one by one. Inputs are
the aggregated table ``{(band, pattern, n, transport): {column: mean}}`` and the single-robot
exploration means. Matplotlib's object API with the Agg canvas only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from swarmex.studies.foraging.design import TRANSPORT_CONFIGS

PATTERNS = ("strips", "zigzag", "hilbert", "sectors", "spiral", "loop-strips", "rings")
COLOURS = {
    "strips": "#1f77b4",
    "zigzag": "#ff7f0e",
    "hilbert": "#2ca02c",
    "sectors": "#d62728",
    "spiral": "#9467bd",
    "modified-zigzag": "#8c564b",
    "rings": "#17becf",
    "loop-strips": "#e377c2",
}
PHASES = ("exploration", "communication", "comm_transport", "transportation")
PHASE_COLOURS = ("#4c72b0", "#dd8452", "#c44e52", "#55a868")
BANDS = ("0-20", "20-40", "40-60", "60-80", "80-100")
BAND_TITLE = {b: f"{b.replace('-', '%-')}%" for b in BANDS} | {"random": "random placement"}
RF = "relay-food"


def _fig(title: str, ylabel: str, width: float = 8.0):
    fig = Figure(figsize=(width, 4.6), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(111)
    ax.set_title(title, fontsize=10)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    return fig, ax


def _legend_outside(ax, **kw) -> None:
    """The legend beside the axes: inside, it covered the tallest bars (the figures are
    saved with ``bbox_inches="tight"``, which takes it in)."""
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), **kw)


def _headroom(ax, top: float) -> None:
    """Room above the tallest bar: a zero-height top segment pinned the axis to its top, and
    the bar looked cut off."""
    if np.isfinite(top) and top > 0:
        ax.set_ylim(0, 1.05 * top)


def _grouped(ax, groups: list[int], series: dict[str, list[float | None]]) -> None:
    width = 0.8 / max(1, len(series))
    x = np.arange(len(groups))
    for i, (name, vals) in enumerate(series.items()):
        ys = [np.nan if v is None else v for v in vals]
        xs = x + (i - (len(series) - 1) / 2) * width
        ax.bar(xs, ys, width, label=name, color=COLOURS[name])
        for xi, v in zip(xs, vals, strict=True):
            if v is None:  # a pattern that cannot run this team: not a bar of 0 rounds
                ax.text(xi, 0, "n/a", rotation=90, fontsize=6, ha="center", va="bottom",
                        color="#777777")
    ax.set_xticks(x, [f"N={g}" for g in groups])
    _legend_outside(ax)


def _save(fig: Figure, path: Path) -> Path:
    """Write ``fig`` to ``path``, cropped to what is drawn (``bbox_inches="tight"`` takes in
    the legend beside the axes): how every figure of the report is saved, in one place."""
    fig.savefig(path, bbox_inches="tight")
    return path


def _get(table, band, pattern, n, col, transport=RF):
    row = table.get((band, pattern, n, transport))
    return None if row is None else row[col]


def exploration_fig(table, single, band: str, num: int, out: Path) -> Path:
    ns = [1, 4, 8, 16]
    series = {}
    for p in PATTERNS:
        vals = [
            single.get((band, p, 1)) if n == 1 else _get(table, band, p, n, "exploration")
            for n in ns
        ]
        series[p] = vals
    fig, ax = _fig(f"Fig. {num}: exploration time, {BAND_TITLE[band]}", "rounds")
    _grouped(ax, ns, series)
    return _save(fig, out / f"fig{num}.png")


def stacked_fig(table, band: str, num: int, out: Path, phases: tuple[str, ...], what: str):
    ns = [4, 8, 16]
    fig, ax = _fig(f"Fig. {num}: {what}, {BAND_TITLE[band]}", "rounds", width=10)
    labels, x, i = [], [], 0
    top = 0.0
    for n in ns:
        for p in PATTERNS:
            row = table.get((band, p, n, RF))
            if row is None:
                continue
            bottom = 0.0
            for ph, col in zip(phases, PHASE_COLOURS, strict=False):
                ax.bar(i, row[ph], 0.8, bottom=bottom, color=col, label=ph if i == 0 else None)
                bottom += row[ph]
            top = max(top, bottom)
            labels.append(f"{p[:4]}{n}")
            x.append(i)
            i += 1
        i += 1
    ax.set_xticks(x, labels, rotation=60, fontsize=7)
    _headroom(ax, top)
    _legend_outside(ax)
    return _save(fig, out / f"fig{num}.png")


def ratio_fig(table, out: Path) -> Path:
    fig, ax = _fig("Fig. 63: communication / exploration time (random)", "ratio")
    for p in PATTERNS:
        ns, ys = [], []
        for n in (4, 8, 16):
            row = table.get(("random", p, n, RF))
            if row:
                ns.append(n)
                ys.append((row["communication"] + row["comm_transport"]) / row["exploration"])
        ax.plot(ns, ys, marker="o", label=p, color=COLOURS[p])
    ax.set_xlabel("N")
    _legend_outside(ax)
    return _save(fig, out / "fig63.png")


def transport_fig(table, out: Path) -> Path:
    fig, ax = _fig("Fig. 69: transport algorithms (random, total time)", "rounds", width=9)
    kinds = ("relay-food", "relay-path", "end-to-end")
    width = 0.26
    for j, kind in enumerate(kinds):
        ys = [_get(table, "random", p, n, "total", kind) for p, n in TRANSPORT_CONFIGS]
        ys = [np.nan if v is None else v for v in ys]
        ax.bar(np.arange(len(ys)) + (j - 1) * width, ys, width, label=kind)
    ax.set_xticks(  # slanted: side by side the long names ran into each other
        np.arange(len(TRANSPORT_CONFIGS)), [f"{p} N={n}" for p, n in TRANSPORT_CONFIGS],
        fontsize=7, rotation=30, ha="right",
    )
    _legend_outside(ax)
    return _save(fig, out / "fig69.png")


def share_fig(table, out: Path) -> Path:
    fig, ax = _fig("Fig. 76: share of total time per phase (random)", "%", width=10)
    labels, i = [], 0
    for n in (4, 8, 16):
        for p in PATTERNS:
            row = table.get(("random", p, n, RF))
            if row is None:
                continue
            total = sum(row[ph] for ph in PHASES)
            bottom = 0.0
            for ph, col in zip(PHASES, PHASE_COLOURS, strict=True):
                share = 100 * row[ph] / total
                ax.bar(i, share, 0.8, bottom=bottom, color=col, label=ph if i == 0 else None)
                bottom += share
            labels.append(f"{p[:4]}{n}")
            i += 1
    ax.set_xticks(range(len(labels)), labels, rotation=60, fontsize=7)
    ax.set_ylim(0, 100)
    _legend_outside(ax)
    return _save(fig, out / "fig76.png")


def versus_fig(table, out: Path, subject: str, n: int, num: str, others: tuple[str, ...]):
    bands = (*BANDS, "random")
    label = f"Fig. {num}" if num[0].isdigit() else "Ours"
    fig, ax = _fig(f"{label}: {subject} vs the others, N={n} (total time)", "rounds", 10)
    names = [subject, *[p for p in others if p != subject]]
    width = 0.8 / len(names)
    for j, p in enumerate(names):
        ys = [_get(table, b, p, n, "total") for b in bands]
        ys = [np.nan if v is None else v for v in ys]
        xs = np.arange(len(bands)) + (j - (len(names) - 1) / 2) * width
        ax.bar(xs, ys, width, label=p, color=COLOURS[p])
    ax.set_xticks(np.arange(len(bands)), [BAND_TITLE[b] for b in bands], fontsize=8)
    _legend_outside(ax)
    return _save(fig, out / (f"fig{num}.png" if num[0].isdigit() else f"{num}.png"))


def all_figures(table, single, out: Path) -> dict[str, Path]:
    figs: dict[str, Path] = {}
    figs["56"] = exploration_fig(table, single, "random", 56, out)
    for num, band in zip(range(57, 62), BANDS, strict=True):
        figs[str(num)] = exploration_fig(table, single, band, num, out)
    ec = ("exploration", "communication", "comm_transport")
    figs["62"] = stacked_fig(table, "random", 62, out, ec, "exploration + communication")
    figs["63"] = ratio_fig(table, out)
    for num, band in zip(range(64, 69), BANDS, strict=True):
        figs[str(num)] = stacked_fig(table, band, num, out, ec, "search + communication")
    figs["69"] = transport_fig(table, out)
    figs["70"] = stacked_fig(table, "random", 70, out, PHASES, "total execution time")
    for num, band in zip(range(71, 76), BANDS, strict=True):
        figs[str(num)] = stacked_fig(table, band, num, out, PHASES, "total execution time")
    figs["76"] = share_fig(table, out)
    figs["77"] = versus_fig(
        table, out, "modified-zigzag", 8, "77", ("strips", "sectors", "spiral", "rings")
    )
    thesis = ("strips", "zigzag", "hilbert", "sectors", "spiral", "rings")
    for n in (4, 8, 16):
        figs[f"ours{n}"] = versus_fig(table, out, "loop-strips", n, f"ours_n{n}", thesis)
    return figs
