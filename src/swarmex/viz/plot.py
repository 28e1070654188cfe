"""Figures of a sweep: a metric against a parameter, as the seeds draw their results.

Two looks, chosen by the x parameter unless ``kind`` says otherwise: a numeric x (agents, grid
size in cells, a probability) gives lines with markers and a shaded 95 % confidence band, as
in seed 000's and 002's curves; a categorical x (algorithm, transport, map) gives grouped bars
with CI whiskers, as in their comparison charts. ``hue`` splits the data into coloured series.
Each point is the mean over the seeds of one configuration, with its Student-t interval
(:func:`swarmex.engine.stats.summarize`); parameters that vary but are neither x nor hue are
pooled, and the returned note says so, since pooling different configurations widens the bands.

matplotlib's object API with the Agg canvas, as in :mod:`swarmex.viz.traversal`: no pyplot
state, headless-safe.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from swarmex.engine.stats import Summary, summarize, wilson_ci
from swarmex.errors import InputError
from swarmex.viz.files import save_figure

KINDS = ("auto", "line", "bar")
SUFFIXES = (".png", ".svg")


def plot_sweep(
    rows: list[dict[str, Any]],
    meta: dict[str, Any],
    x: str,
    y: str,
    hue: str | None = None,
    where: list[str] | None = None,
    kind: str = "auto",
    path: str | Path = "plot.png",
) -> tuple[Path, str | None]:
    """Draw ``y`` against ``x`` (one series per ``hue`` value); returns the file and a note."""
    path = Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise InputError(f"--out: {path} must end in .png or .svg")
    fig, note = sweep_figure(rows, meta, x, y, hue, where, kind)
    save_figure(fig, path)
    return path, note


def column_name(columns: list[str], name: str) -> str:
    """The column ``name`` means: itself, else the one spelt with dashes for underscores or
    the reverse (a spec key keeps its dashes, ``travel-time``, while Python writes
    ``travel_time``), else ``metrics.NAME``'s plain ``NAME`` column (what ``--metric``
    accepts). ``name`` when none matches, for the caller's error."""
    if name in columns:
        return name
    wanted = name.replace("-", "_")
    alike = [c for c in columns if c.replace("-", "_") == wanted]
    if len(alike) == 1:
        return alike[0]
    bare = name.removeprefix("metrics.")
    return bare if bare != name and bare in columns else name


def sweep_figure(
    rows: list[dict[str, Any]],
    meta: dict[str, Any],
    x: str,
    y: str,
    hue: str | None = None,
    where: list[str] | None = None,
    kind: str = "auto",
) -> tuple[Figure, str | None]:
    """The figure of :func:`plot_sweep`, not saved (``swarmex.plot`` returns it), and the
    note on what it pools."""
    if kind not in KINDS:
        raise InputError(f"--kind must be one of {', '.join(KINDS)}, got {kind!r}")
    columns = list(rows[0]) if rows else []
    x, y = column_name(columns, x), column_name(columns, y)
    hue = None if hue is None else column_name(columns, hue)
    for option, name in (("--x", x), ("--y", y), ("--hue", hue)):
        if name is not None and name not in columns:
            raise InputError(f"{option}: no column {name!r} (have: {', '.join(columns)})")
    if hue is not None and hue in (x, y):  # one isolated point per series: nothing to compare
        raise InputError(f"--hue {hue} is also {'--x' if hue == x else '--y'}; give another"
                         " column, or none")
    rows = _filter(rows, where or [], columns, meta.get("mission"))
    ok = [r for r in rows if not r.get("error") and _num(r.get(y)) is not None]
    failed = [r for r in rows if r.get("error")]
    if not ok:
        raise InputError(f"no finished run has a numeric {y!r} to plot")
    xs = _levels([r[x] for r in ok])
    hues = _levels([r[hue] for r in ok]) if hue else [None]
    numeric_x = all(_is_number(v) for v in xs)
    if kind == "auto":
        kind = "line" if numeric_x and len(xs) > 1 else "bar"
    if kind == "line" and not numeric_x:
        raise InputError(f"--kind line needs a numeric --x; {x!r} is categorical (use bar)")

    # a time of a run that did not finish is where it stopped (its budget), not a finish
    stops = is_time(y) or "steps" in _words(y)  # roadmap's length is "steps"
    unfinished = [r for r in ok if r.get("complete") is False] if stops else []
    cut_at = {(r[hue] if hue else None, r[x]) for r in unfinished}  # (series, x) to mark
    fig = Figure(figsize=(6.4, 4.2), dpi=120)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    width = 0.8 / len(hues)
    points = 0  # (series, x) cells with a finished run: what a point's mean is over
    with_ci = 0  # of them, those with an interval (two runs or more)
    fraction = all(isinstance(r[y], bool) for r in ok)  # complete: a share of the runs
    for i, (h, stats) in enumerate(series(ok, x, y, hue, xs, hues).items()):
        mean = np.array([s.mean for s in stats])
        # a point of one run has no interval: no whisker (a flat cap read as "± 0")
        interval = np.array([s.has_ci for s in stats], dtype=bool)
        with_ci += int(interval.sum())
        lo, hi = interval_ends(stats, fraction)
        lo, hi = np.where(interval, lo, mean), np.where(interval, hi, mean)
        span = np.nan_to_num(np.array([mean - lo, hi - mean]))  # errorbar's yerr
        label = None if hue is None else f"{h}"
        cut = np.array([(h, v) in cut_at for v in xs], dtype=bool)
        # a configuration without a finished run has no point: no line across it, no bar
        have = np.isfinite(mean)
        points += int(have.sum())
        if kind == "line":
            xv = np.array([float(v) for v in xs])
            (line,) = ax.plot(xv, mean, marker="o", lw=1.8, ms=4, label=label)
            ax.fill_between(xv, lo, hi, where=have, color=line.get_color(), alpha=0.2, lw=0)
            # a band needs a neighbour: a point alone between gaps gets a whisker
            alone = have & ~np.r_[False, have[:-1]] & ~np.r_[have[1:], False] & interval
            if alone.any():
                ax.errorbar(xv[alone], mean[alone], yerr=span[:, alone], ls="", capsize=3,
                            color=line.get_color())
            if (have & cut).any():
                ax.plot(xv[have & cut], mean[have & cut], ls="", marker="o", ms=7,
                        mfc="white", mec=line.get_color(), mew=1.5, zorder=3)
        else:
            pos = (np.arange(len(xs)) + (i - (len(hues) - 1) / 2) * width)[have]
            bars = ax.bar(pos, mean[have], width * 0.95, label=label)
            whisker = interval[have]
            if whisker.any():
                ax.errorbar(pos[whisker], mean[have][whisker], yerr=span[:, have][:, whisker],
                            ls="", capsize=3, color="black", lw=1)
            for bar, hatched in zip(bars, cut[have], strict=True):
                if hatched:
                    bar.set_hatch("//")
    if kind == "bar":
        ax.set_xticks(np.arange(len(xs)), [_label(v) for v in xs])
    elif len(xs) <= 12:  # the swept values themselves (no "2.25 agents" between them)
        ax.set_xticks([float(v) for v in xs], [_label(v) for v in xs])
    ax.set_xlabel(x)
    ax.set_ylabel(y_label(y, ok))
    runs_per = len(ok) / max(1, points)
    # the filters belong in the title: a plot of part of a sweep looked like the whole of it
    only = f"\n{', '.join(where)}" if where else ""
    if fraction:
        ax.set_ylim(-0.03, 1.03)
    ci = "95 % Wilson interval" if fraction else "95 % CI"
    what = (f"mean ± {ci}" if with_ci == points
            else "mean (one run a point: no interval)" if with_ci == 0
            else f"mean ± {ci} where a point has two runs or more")
    ax.set_title(
        f"{meta.get('mission', 'sweep')}: {y} vs {x} · {what} (≈{runs_per:.0f} runs/point)"
        + only,
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    ax.set_axisbelow(True)
    if hue is not None:
        ax.legend(title=hue, fontsize=8, title_fontsize=8, frameon=False)
    if unfinished:
        mark = "hollow markers" if kind == "line" else "hatched bars"
        fig.text(0.01, 0.01, f"{mark}: some runs did not finish; their {y} is where they"
                 " stopped", fontsize=7, color="dimgray")
    fig.tight_layout(rect=(0, 0.03 if unfinished else 0, 1, 1))
    pooled = [
        p
        for p in meta.get("axes", [])
        if p not in (x, hue, "seed") and p in columns and len(_levels([r[p] for r in ok])) > 1
    ]
    notes = []
    if pooled:
        notes.append(f"note: pooled over {', '.join(pooled)} (use --hue or --where to separate)")
    if unfinished:
        notes.append(f"note: {len(unfinished)} of the {len(ok)} runs plotted did not finish; their"
                     f" {y} is where they stopped, not a finish time (--where complete=true"
                     " keeps the finished ones)")
    if failed:
        empty = sorted({_where(r, x, hue) for r in failed} - {_where(r, x, hue) for r in ok})
        notes.append(f"note: {len(failed)} failed run(s) left out (the table's error column)"
                     + (f"; no finished run, so no point, at {'; '.join(empty)}" if empty
                        else ""))
    return fig, "\n".join(notes) or None


def y_label(y: str, rows: list[dict[str, Any]]) -> str:
    """The y axis's label: the column, with the runs' time unit when it is a time.

    Why: only ``makespan`` had its unit, so a traversal sweep's ``total_time_all`` (seconds)
    or a foraging sweep's ``exploration_time`` (steps) was drawn without one. A time is a
    metric named ``*_time*`` (``total_time_all``, ``max_total_time``, ``transport_time``) or
    ``mission_end``; it is in the record's ``time_unit`` (the makespan's unit).
    """
    if y == "complete":
        return "fraction complete"
    if _words(y)[-1] == "seconds":
        return f"{y} (s)"
    units = {r.get("time_unit") for r in rows} - {None}
    return f"{y} ({units.pop()})" if is_time(y) and len(units) == 1 else y


def is_time(y: str) -> bool:
    """Whether the column is a time of the run: a metric named ``*_time*``
    (``total_time_all``, ``transport_time``), ``makespan*`` (``makespan_seconds``) or
    ``mission_end``."""
    words = _words(y)
    return y == "mission_end" or words[0] == "makespan" or (
        "time" in words and y != "time_unit")


def _words(y: str) -> list[str]:
    return y.rsplit(".", 1)[-1].split("_")


def _where(row: dict[str, Any], x: str, hue: str | None) -> str:
    """``x=V`` (and ``hue=H``) of a row, for a note."""
    return f"{x}={_label(row.get(x))}" + ("" if hue is None else f" {hue}={row.get(hue)}")


def interval_ends(stats: list[Summary], fraction: bool) -> tuple[np.ndarray, np.ndarray]:
    """Each point's 95 % interval, lower and upper ends (NaN where it has none).

    A fraction (a yes/no column: ``complete``) gets Wilson's score interval, which stays
    within 0 and 1: the t interval of 0/1 values does not (two runs, one complete: −5.9 to
    6.9), and it drew a share of the runs above 100 %."""
    if not fraction:
        return (np.array([s.ci_low for s in stats], dtype=float),
                np.array([s.ci_high for s in stats], dtype=float))
    # a point with no finished run (n = 0, mean NaN) has no count of successes to round
    ends = [wilson_ci(round(s.mean * s.n), s.n) if s.n else (math.nan, math.nan)
            for s in stats]
    return np.array([e[0] for e in ends]), np.array([e[1] for e in ends])


def series(
    rows: list[dict[str, Any]],
    x: str,
    y: str,
    hue: str | None,
    xs: list[Any] | None = None,
    hues: list[Any] | None = None,
) -> dict[Any, list[Summary]]:
    """Per hue value (None without hue), the mean and CI of ``y`` at each x level."""
    xs = xs if xs is not None else _levels([r[x] for r in rows])
    hues = hues if hues is not None else (_levels([r[hue] for r in rows]) if hue else [None])
    out = {}
    for h in hues:
        sel = [r for r in rows if hue is None or r[hue] == h]
        out[h] = [summarize([_num(r[y]) for r in sel if r[x] == v]) for v in xs]
    return out


def _filter(rows: list[dict[str, Any]], where: list[str], columns: list[str],
            mission: str | None = None) -> list[dict]:
    from swarmex.missions.registry import same_value

    for cond in where:
        key, sep, value = cond.partition("=")
        key = column_name(columns, key.strip())
        if not sep or key not in columns:
            raise InputError(f"--where: expected PARAM=VALUE with a known PARAM, got {cond!r}")
        text = value.strip()
        # the table's spelling, else the option's parser: "5x5" finds a grid the table
        # holds as "5,5" (a sweep of grid=(5, 5))
        rows = [r for r in rows if _matches(r.get(key), text)
                or same_value(mission, key, r.get(key), text)]
    if not rows:
        raise InputError(f"--where {' '.join(where)}: no run matches")
    return rows


def _matches(v: Any, text: str) -> bool:
    if _is_number(v):
        try:
            return float(v) == float(text)
        except ValueError:
            return False
    if isinstance(v, bool):
        return str(v).lower() == text.lower()
    return str(v) == text


def _levels(values: list[Any]) -> list[Any]:
    """Distinct values: numbers sorted, anything else in first-seen order."""
    distinct = list(dict.fromkeys(values))
    if all(_is_number(v) for v in distinct):
        return sorted(distinct)
    return distinct


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _num(v: Any) -> float | None:
    if isinstance(v, bool):
        return float(v)
    return float(v) if _is_number(v) and np.isfinite(v) else None


def _label(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)
