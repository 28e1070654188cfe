"""The figures of ``swarmex reproduce traversal``: Figs. 5.1–5.14 redrawn from the analysis.

Candlesticks as in the thesis (:mod:`swarmex.viz.candles`: whiskers min–max, body the 95 %
CI of the mean) with the thesis's own numbers overlaid, and the fleet-cost charts of
Figs. 5.13–5.14.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from swarmex.engine.stats import Summary
from swarmex.studies.traversal.analysis import (
    THESIS_FLEET,
    FigureResult,
    GroupResult,
    best_fleet,
    fleet_t_max,
)
from swarmex.studies.traversal.design import ReferenceRow
from swarmex.viz.candles import OURS, THEIRS, Reference, candle_chart


def _fleet_chart(
    path: Path, t_max: dict[int, float], ns: list[int], number: str, p_max: float
) -> Path:
    """Cost lines n·p + T_max(n), their lower envelope, our and the thesis's best-n bands;
    the title names the fleets drawn (a quick plan simulates 2, 3 and 10 agents only, and
    "2–6 agents" over two lines said otherwise)."""
    import matplotlib.pyplot as plt

    ps = np.linspace(0, p_max, 401)
    fig, ax = plt.subplots(figsize=(6.2, 4.4), dpi=110)
    present = [n for n in ns if n in t_max]
    title = f"Fig. {number}: fleet cost n·p + T_max(n), {agent_counts(present or ns)} agents"
    for n in present:
        ax.plot(ps, n * ps + t_max[n], label=f"{n} agents", linewidth=1.3)
    env = np.min([n * ps + t_max[n] for n in t_max], axis=0)
    # named: the envelope also runs over fleets this panel does not draw, and then lies below
    # every drawn line
    every = agent_counts(sorted(t_max))
    ax.plot(ps, env, color="black", linewidth=2.4, alpha=0.35,
            label=f"best over all fleets ({every} agents)")
    ax.set_xlim(0, p_max)
    lo_y, hi_y = ax.get_ylim()
    band = (hi_y - lo_y) * 0.06
    ax.set_ylim(lo_y - 2.4 * band, hi_y)

    def bands(items, y: float, color: str, label: str) -> None:
        for j, (n, lo, hi) in enumerate(items):
            hi = min(hi, p_max)
            if hi <= lo or lo >= p_max:
                continue
            ax.add_patch(
                plt.Rectangle(
                    (lo, y),
                    hi - lo,
                    band * 0.8,
                    color=color,
                    alpha=0.25,
                    label=label if j == 0 else None,
                )
            )
            ax.annotate(
                str(n),
                ((lo + hi) / 2, y + band * 0.4),
                ha="center",
                va="center",
                fontsize=7,
                color=color,
            )

    bands(best_fleet(t_max), lo_y - band, OURS, "best n (ours)")
    bands(THESIS_FLEET, lo_y - 2.2 * band, THEIRS, "best n (thesis)")
    ax.set_xlabel("preparation time per UAV p (s)")
    ax.set_ylabel("n·p + mean max totalTime_i (s)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _thesis_summary(row: ReferenceRow | None) -> Summary | None:
    if row is None:
        return None
    return Summary(108, row.min, row.max, row.median, row.mean, row.std, row.ci_low, row.ci_high)


def draw_figures(groups: list[GroupResult], figs: list[FigureResult], out: Path) -> list[Path]:
    paths: list[Path] = []
    by_nest = {k: g for g in groups for k in g.group.config.nests}

    def group_fig(number: str, nodes: list[tuple[str, int]], title: str) -> None:
        chosen = [(lab, by_nest[k]) for lab, k in nodes if k in by_nest and by_nest[k].ours]
        if not chosen:
            return
        paths.append(
            candle_chart(
                out / f"fig_{number.replace('.', '_')}.png",
                [lab for lab, _ in chosen],
                [g.ours["totalTimeAll"] for _, g in chosen],
                f"Fig. {number}: {title}",
                "nest node (its symmetry group)",
                "totalTimeAll (s)",
                theirs=[_thesis_summary(g.thesis.get("totalTimeAll")) for _, g in chosen],
            )
        )

    group_fig("5.1", [("1", 1), ("2", 2), ("3", 3)], "6×6, 40×40 m, 3 agents, nest on the border")
    group_fig("5.2", [("8", 8), ("15 = 22", 15)], "6×6, 40×40 m, 3 agents, nest in the middle")
    for fr in figs:
        f = fr.spec
        present = [(b.label, b.summary) for b in fr.bars if b.summary]
        if not present:
            continue
        labels = [label for label, _ in present]
        summaries = [summary for _, summary in present]
        refs = []
        for st in f.stated:
            if st.bar is None:
                refs.append(Reference(st.value, f"thesis: {st.text}"))
            elif st.bar in labels:
                refs.append(Reference(st.value, "thesis (stated)", labels.index(st.bar)))
        ylabel = "max totalTime_i (s)" if f.metric == "max_total_time" else "totalTimeAll (s)"
        paths.append(
            candle_chart(
                out / f"fig_{f.number.replace('.', '_')}.png",
                labels,
                summaries,
                f"Fig. {f.number}: {f.title}",
                f.xlabel,
                ylabel,
                references=refs,
                note=_n_note([s.n for s in summaries]),
            )
        )
    t_max = fleet_t_max(figs)
    if t_max:
        for number, ns, p_max in (("5.13", range(2, 7), 1000.0), ("5.14", range(6, 11), 250.0)):
            paths.append(_fleet_chart(out / f"fig_{number.replace('.', '_')}.png", t_max,
                                      list(ns), number, p_max))
    return paths


def agent_counts(ns: list[int]) -> str:
    """"2–6" for a run of consecutive counts, else "2, 3" (how a fleet chart's title names
    the fleets it draws)."""
    if len(ns) > 2 and ns == list(range(ns[0], ns[-1] + 1)):
        return f"{ns[0]}–{ns[-1]}"
    return ", ".join(map(str, ns))


def _n_note(ns: list[int]) -> str:
    lo, hi = min(ns), max(ns)
    return f"n = {lo} runs per bar" if lo == hi else f"n = {lo}–{hi} runs per bar"
