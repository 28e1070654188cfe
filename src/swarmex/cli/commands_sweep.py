"""``swarmex sweep SPEC.toml`` and ``swarmex plot DIR``: experiments at scale and their figures.

Thin: the spec is read by :mod:`swarmex.experiments.sweep_spec`, run by
:mod:`swarmex.experiments.sweep`, summarised by :mod:`swarmex.engine.stats` and drawn
by :mod:`swarmex.viz.plot`. What lives here is the progress bar and the tables.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import typer
from rich.console import Console
from rich.measure import Measurement
from rich.table import Table

from swarmex.cli.app import app, console, err_console, interrupted
from swarmex.errors import InputError
from swarmex.experiments.progress import SweepBar


def mission_shapes(mission: str, where: Path):
    """Option shapes of a mission's parameters (read off its Params)."""
    from swarmex.experiments.scenario import mission_shapes as shapes

    try:
        return shapes(mission)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


@app.command()
def sweep(
    spec_file: Path = typer.Argument(
        ..., help="TOML spec: mission, options (lists = axes), seeds."
    ),
    backend: str = typer.Option(
        "local", "--backend", help="local (process pool) | ray | serial (in this process)."
    ),
    workers: int | None = typer.Option(
        None, "--workers", help="Worker processes (default: all cores).", show_default=False
    ),
    out: Path | None = typer.Option(
        None, "--out", help="Sweep folder (default: ./<spec name>-sweep).", show_default=False
    ),
    ray_address: str | None = typer.Option(
        None,
        "--ray-address",
        help="Ray cluster to join (default: RAY_ADDRESS, else a local Ray).",
        show_default=False,
    ),
    retry_failed: bool = typer.Option(
        False, "--retry-failed", help="Run again the runs that failed before."
    ),
    summary: bool = typer.Option(
        False, "--summary", help="Print means and 95 % CIs per configuration."
    ),
    metric: list[str] = typer.Option(
        [], "--metric", help="A metric to add to the summary (repeatable; implies --summary)."
    ),
    baseline: str | None = typer.Option(
        None,
        "--baseline",
        help="PARAM=VALUE: compare every other value of PARAM with it, paired by"
        " configuration and seed (Δ and relative Δ with 95 % CIs).",
        show_default=False,
    ),
) -> None:
    """Run the product of a spec's parameter lists and seeds; resumable; one Parquet table."""
    from swarmex.experiments.sweep import run_sweep
    from swarmex.experiments.sweep_spec import always_ignored, listed_axes, load_sweep_spec

    spec = load_sweep_spec(spec_file)
    for key, count in listed_axes(spec):
        err_console.print(f"note: {key} is an axis of {count} values, one per run; for one"
                          f" list of {key} in every run, put it under [fixed] (docs/sweeps.md)",
                          soft_wrap=True, markup=False)
    for name, why in always_ignored(spec):
        err_console.print(f"note: {name.replace('_', '-')} is ignored in every run: {why}",
                          soft_wrap=True, markup=False, highlight=False)
    shapes = mission_shapes(spec.mission, spec_file)
    check_metrics(spec.mission, metric)  # a typo must stop the sweep before its runs
    compared = None
    if baseline is not None:
        from swarmex.experiments.compare import check_baseline, parse_baseline

        compared = check_baseline(spec.axes, *parse_baseline(baseline), mission=spec.mission)
    summary = summary or bool(metric)  # a metric asked for was silently never shown
    out_dir = out if out is not None else Path(f"{spec_file.stem}-sweep")

    def announce(total: int, finished: int) -> None:
        console.print(
            f"sweep: {total} runs of swarmex {spec.command} ({finished} finished before,"
            f" {total - finished} to run) → {out_dir}",
            soft_wrap=True,  # one line each, whatever the width: paths stay whole in logs
        )

    bar = SweepBar(err_console, announce=announce)

    try:
        try:
            result = run_sweep(
                spec,
                shapes,
                out_dir,
                backend=backend,
                workers=workers,
                ray_address=ray_address,
                retry_failed=retry_failed,
                on_start=bar.on_start,
                on_outcome=bar.on_outcome,
                on_warning=lambda text: err_console.print(
                    f"warning: {text}", highlight=False, soft_wrap=True, markup=False
                ),
            )
        finally:
            bar.stop()
    except KeyboardInterrupt:
        # Ctrl-C, or SIGTERM (a scheduler, `kill`: swarmex.cli.main makes it one)
        interrupted(
            f"finished runs are saved in {out_dir} (run the same command again to resume)"
        )
    console.print(
        f"{result.skipped + result.ran}/{result.total} runs finished ({result.ran} now),"
        f" {result.failed} failed → {result.table}",
        soft_wrap=True,
    )
    if result.failed:
        console.print(
            f"[yellow]failed runs are in the table's error column and in"
            f" {result.out_dir / 'runs'}/*.error.json[/]",
            soft_wrap=True,
        )
    if summary:
        print_summary(result.out_dir, metric)
    if compared is not None:
        print_paired(result.out_dir, *compared, metric)


def check_metrics(mission: str, names: list[str]) -> None:
    """Each ``--metric`` must name a number the mission's records hold (InputError if not)."""
    from swarmex.missions.registry import get

    m = get(mission)
    for name in names:
        m.check_metric(name)


def print_summary(out_dir: Path, extra_metrics: list[str]) -> None:
    """A Rich table: one row per configuration, means ± 95 % CI half widths."""
    from swarmex.engine.stats import summarize_groups
    from swarmex.experiments.sweep import read_results

    table, meta = read_results(out_dir)
    rows = table.to_pylist()
    columns = set(table.column_names)
    by = [p for p in meta.get("axes", []) if p in columns] or [
        p for p in meta.get("params", []) if p in columns
    ]
    extra = [metric_column(m, columns, meta.get("mission")) for m in extra_metrics]
    metrics = [
        "complete",
        "makespan",
        *[m for m in extra if m not in ("complete", "makespan")],
    ]
    groups = summarize_groups(rows, by, metrics)
    out = Table(
        title=f"{meta.get('mission', '')} sweep · mean ± 95 % CI (Student t over seeds)",
        title_justify="left",
    )
    for p in by:
        out.add_column(p)
    out.add_column("runs", justify="right")
    out.add_column("failed", justify="right")
    for m in metrics:
        out.add_column("complete %" if m == "complete" else m, justify="right")
    for g in groups:
        cells = [_value(g.config[p]) for p in by] + [str(g.runs), str(g.failed or "")]
        for m in metrics:
            s = g.stats[m]
            scale = 100.0 if m == "complete" else 1.0
            cells.append(_mean_ci(s.mean * scale, s.half_width * scale))
        out.add_row(*cells)
    print_wide(out)


def print_paired(out_dir: Path, name: str, value: Any, extra_metrics: list[str]) -> None:
    """A Rich table of ``--baseline``: each other value of ``name`` against ``value``, per
    configuration and pooled, on makespan and the ``--metric`` metrics."""
    from swarmex.experiments.compare import comparisons
    from swarmex.experiments.sweep import read_results

    table, meta = read_results(out_dir)
    columns = set(table.column_names)
    extra = [metric_column(m, columns, meta.get("mission")) for m in extra_metrics]
    metrics = ["makespan", *[m for m in extra if m != "makespan" and m in columns]]
    for asked, column in zip(extra_metrics, extra, strict=True):
        if column not in columns:  # dropped without a word: the summary at least shows "—"
            err_console.print(f"note: no run wrote {asked}, so it is not compared",
                          highlight=False, soft_wrap=True, markup=False)
    results = comparisons(table, meta, name, value, metrics)
    if not results:  # an empty table with headers only said nothing of why
        console.print(f"paired against {name} = {_value(value)}: no pairs (every run with"
                      f" that value, or every run it would pair with, failed: see the"
                      f" table's error column)", highlight=False, soft_wrap=True)
        return
    groups = [a for a in meta.get("axes", []) if a in columns and a != name]
    out = Table(
        title=f"paired against {name} = {_value(value)} · same configuration and seed · mean Δ and"
              " relative Δ with 95 % CIs (Student t over the pairs); lower/higher: pairs",
        title_justify="left",
    )
    for column in (name, *groups, "metric", "pairs", f"{_value(value)} mean", "mean", "Δ",
                   "relative Δ", "lower", "higher"):
        out.add_column(column, justify="left" if column in (name, *groups, "metric")
                       else "right")
    for r in results:
        pooled = not any(g in r.config for g in groups) and bool(groups)
        cells = [_value(r.config[name]),
                 *("all" if pooled else _value(r.config[g]) for g in groups),
                 r.metric, str(r.pairs), _num(r.baseline_mean), _num(r.variant_mean),
                 _mean_ci(r.diff.mean, r.diff.half_width),
                 _relative(r), str(r.lower), str(r.higher)]
        out.add_row(*cells)
    print_wide(out)


def _relative(r: Any) -> str:
    """The relative Δ cell, with the pairs it is over when a zero baseline left some out
    (a ratio to 0 is none; the cell read as if over every pair the row counts)."""
    cell = _mean_ci(100 * r.relative.mean, 100 * r.relative.half_width) + " %"
    return cell if r.relative_pairs == r.pairs else f"{cell} ({r.relative_pairs} pairs)"


def print_wide(out: Table) -> None:
    """Print a table at its natural width: "mean ± CI" cells are never wrapped, so a table
    wider than the terminal stays one line per row."""
    natural = Measurement.get(console, console.options.update_width(10_000), out).maximum
    Console(file=console.file, width=max(console.width, natural),
            force_terminal=console.is_terminal, no_color=console.no_color).print(out)


def _value(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def metric_column(name: str, columns: set[str], mission: Any) -> str:
    """The table column of ``--metric NAME``.

    ``metrics.NAME`` is accepted before the runs (the column of a metric whose name a
    parameter took) but is the plain ``NAME`` column when no parameter took it; and a metric
    the mission declares, or a declared entry of one of its tables (``unicasts.sent``), may
    be in no row (traversal's solver figures when no run was ``optimal``, a table written
    before its entries were columns): its column then shows no value rather than failing
    after the whole sweep has run. Anything else is an InputError listing the columns."""
    if name in columns:
        return name
    bare = name.removeprefix("metrics.")
    if bare != name and bare in columns:
        return bare
    if isinstance(mission, str) and _declared(mission, name):
        return name  # no row has it: shown as "—"
    raise InputError(f"--metric: no column {name!r} (have: {', '.join(sorted(columns))})")


def _declared(mission: str, name: str) -> bool:
    """Whether ``name`` is a metric the mission declares, or a declared entry of one of its
    tables: the names ``--metric`` lets through before the runs (Mission.check_metric)."""
    from swarmex.missions.registry import get

    try:
        m = get(mission)
        if not m.team_metrics():  # a mission that declares nothing: nothing is known
            return False
        m.check_metric(name)
    except InputError:  # not declared, or a plugin mission no longer installed
        return False
    return True


def _mean_ci(mean: float, half: float) -> str:
    if math.isnan(mean):
        return "—"
    if math.isnan(half):
        return _num(mean)
    return f"{_num(mean)} ± {_num(half)}"


def _num(v: float) -> str:
    """Fixed notation with a precision that follows the magnitude (no 1.2e+03 in tables)."""
    a = abs(v)
    if a >= 1000:
        return f"{v:,.0f}"
    if a >= 10:
        return f"{v:.1f}"
    if a >= 0.01 or a == 0:
        return f"{v:.3g}" if a < 1 else f"{v:.2f}"
    return f"{v:.1e}"


@app.command()
def plot(
    sweep_dir: Path = typer.Argument(..., help="A sweep folder (or its results.parquet)."),
    x: str = typer.Option(..., "--x", help="Parameter on the x axis."),
    y: str = typer.Option(..., "--y", help="Metric on the y axis (makespan, complete, …)."),
    hue: str | None = typer.Option(
        None, "--hue", help="Parameter that colours the series.", show_default=False
    ),
    where: list[str] = typer.Option(
        [], "--where", help="Keep only rows with PARAM=VALUE (repeatable)."
    ),
    kind: str = typer.Option(
        "auto", "--kind", help="line (CI bands) | bar (grouped, CI whiskers) | auto."
    ),
    out: Path | None = typer.Option(
        None,
        "--out",
        help="PNG or SVG file (default: DIR/<y>-vs-<x>.png).",
        show_default=False,
    ),
) -> None:
    """Draw a sweep's metric against a parameter: means with 95 % CI bands or bars."""
    from swarmex.experiments.sweep import read_results
    from swarmex.viz.plot import plot_sweep

    table, meta = read_results(sweep_dir)
    base = sweep_dir if sweep_dir.is_dir() else sweep_dir.parent
    path = out if out is not None else base / f"{y}-vs-{x}.png"
    written, note = plot_sweep(table.to_pylist(), meta, x, y, hue, where, kind, path)
    if note:
        err_console.print(note, soft_wrap=True, highlight=False)  # notes go to stderr
    console.print(f"wrote {written}", soft_wrap=True)
