"""Paired comparisons of a sweep's runs: each value of one parameter against a baseline value,
on the same configurations and seeds (``swarmex.compare``, ``swarmex sweep --baseline``).

Why: the question a sweep over algorithms answers is "is B better than A, and by how much?",
and the runs of a sweep are paired by construction (the same world, starts and draws for
every value of the compared parameter). A paired interval cancels the spread between seeds,
which the per-configuration means ± CI of ``--summary`` keep, so a 1 % difference that the
overlapping intervals of two means hide is resolved. The project's own comparison tables
(docs/traversal-variants.md) are of this kind; this makes them one call.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from os import PathLike, fspath
from pathlib import Path
from typing import Any

from swarmex.engine.stats import PairedComparison, paired_comparisons
from swarmex.errors import InputError
from swarmex.missions.registry import same_value

#: the columns of the comparison table, in order (after the group's parameter columns)
COLUMNS = ("metric", "pairs", "baseline_mean", "mean", "diff", "diff_low", "diff_high",
           "relative", "relative_low", "relative_high", "relative_pairs", "lower_in",
           "higher_in")


def parse_baseline(text: str) -> tuple[str, str]:
    """``PARAM=VALUE`` (the command line's ``--baseline``) as its two parts."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise InputError(f"--baseline: expected PARAM=VALUE (algorithm=madgta), got {text!r}")
    return name.strip().replace("-", "_"), value.strip()


def check_baseline(axes: Mapping[str, Sequence[Any]], name: str, value: Any,
                   option: str = "--baseline", mission: str | None = None) -> tuple[str, Any]:
    """The compared parameter must be an axis of the sweep with at least two values, one of
    them the baseline's (an InputError naming what is wrong, before any run). Returns the
    axis and the value as the sweep spells them (:func:`axis_name`, :func:`axis_value`)."""
    varying = {k: v for k, v in axes.items() if len(v) > 1}
    name = axis_name(varying, name)
    if name not in varying:
        have = ", ".join(varying) or "none"
        raise InputError(f"{option}: {name!r} is not a parameter the sweep varies (it varies:"
                         f" {have})")
    found = axis_value(varying[name], value)
    if found is None:  # another spelling of one of its values ("5x5" for a grid of "5,5")
        found = next((v for v in varying[name] if same_value(mission, name, v, value)), None)
    if found is None:
        values = [str(v) for v in varying[name]]
        raise InputError(f"{option}: {name} has no value {value!r} in this sweep (its values:"
                         f" {', '.join(values)})")
    return name, found


def axis_name(axes: Iterable[str], name: str) -> str:
    """The axis ``name`` means, as the sweep spells it: a spec key keeps its dashes
    (``travel-time``) while ``--baseline`` and Python write ``travel_time``; both name the
    same option. ``name`` itself when no axis matches."""
    wanted = name.replace("-", "_")
    return next((a for a in axes if a.replace("-", "_") == wanted), name)


def axis_value(values: Iterable[Any], value: Any) -> Any:
    """The sweep's own value that ``value`` names, or None: the same text, or the same
    number (``2`` for ``2.0``, ``"2"`` for the integer 2) or boolean (``"true"`` for a
    TOML ``true``), since a value typed on the command line is text and one from Python may
    be of another numeric type than the table's column."""
    values = list(values)
    for v in values:
        if str(v) == str(value):
            return v
    for v in values:
        if isinstance(v, bool) or isinstance(value, bool):
            if isinstance(v, bool) and _as_bool(value) is v:
                return v
            continue
        if isinstance(v, int | float) and _as_float(value) == v:
            return v
    return None


def _as_bool(value: Any) -> bool | None:
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    return True if text == "true" else False if text == "false" else None


def _as_float(value: Any) -> float | None:
    if isinstance(value, bool):
        return None
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def comparisons(table: Any, meta: Mapping[str, Any], name: str, value: Any,
                metrics: Sequence[str]) -> list[PairedComparison]:
    """The paired comparisons of a sweep ``table`` (its metadata names the axes)."""
    axes = [a for a in meta.get("axes", []) if a in table.column_names]
    values = {a: table.column(a).unique().to_pylist() for a in axes}
    stray = [p for p in meta.get("params", []) if p not in axes and p in table.column_names
             and len(table.column(p).unique()) > 1]
    if stray:  # its runs would be paired across the stray parameter's values
        raise InputError(f"the table varies {', '.join(stray)}, which its axes do not name"
                         " (two sweeps put together?); compare each sweep alone")
    name, found = check_baseline(values, name, value, option="baseline",
                                 mission=meta.get("mission"))
    metrics = [metric_name(table, m) for m in metrics]
    return paired_comparisons(table.to_pylist(), name, found, axes, metrics)


def metric_name(table: Any, metric: str) -> str:
    """The numeric column ``metric`` names: itself, or ``metrics.NAME``'s plain ``NAME``
    column (what ``--metric`` accepts); an InputError for a missing or non-numeric column,
    which would otherwise give no pairs at all rather than an error."""
    import pyarrow.types as pt

    columns = table.column_names
    name = metric
    if name not in columns and name.removeprefix("metrics.") in columns:
        name = name.removeprefix("metrics.")
    if name not in columns:
        raise InputError(f"metric {metric!r}: no such column (have: {', '.join(columns)})")
    kind = table.schema.field(name).type
    if not (pt.is_integer(kind) or pt.is_floating(kind) or pt.is_boolean(kind)
            or pt.is_null(kind)):
        raise InputError(f"metric {metric!r}: not a number (its column holds {kind})")
    return name


def as_table(results: list[PairedComparison], name: str, axes: Sequence[str]) -> Any:
    """The comparisons as a ``pyarrow.Table``: the compared parameter and the group's other
    axes (null in a pooled row), then :data:`COLUMNS`; ``relative`` is a fraction, over
    ``relative_pairs`` pairs (those whose baseline is not 0)."""
    import pyarrow as pa

    params = [name, *(a for a in axes if a != name)]
    rows = []
    for r in results:
        row: dict[str, Any] = {p: _plain(r.config.get(p)) for p in params}
        row.update(
            metric=r.metric, pairs=r.pairs, baseline_mean=r.baseline_mean,
            mean=r.variant_mean, diff=r.diff.mean, diff_low=r.diff.ci_low,
            diff_high=r.diff.ci_high, relative=r.relative.mean,
            relative_low=r.relative.ci_low, relative_high=r.relative.ci_high,
            relative_pairs=r.relative_pairs, lower_in=r.lower, higher_in=r.higher,
        )
        rows.append(row)
    return pa.Table.from_pylist(rows) if rows else pa.table({c: [] for c in (*params, *COLUMNS)})


def load(results: Any) -> tuple[Any, dict[str, Any]]:
    """A sweep's table and metadata from its folder (or results file), or from the table
    ``swarmex.sweep`` returned (its schema metadata names the axes)."""
    from swarmex.experiments.sweep import read_results, table_meta

    if isinstance(results, str | PathLike):  # a PurePath too
        return read_results(Path(fspath(results)))
    if getattr(results, "schema", None) is None:
        raise InputError(f"expected a sweep folder or the table swarmex.sweep returned, got"
                         f" {type(results).__name__}")
    return results, table_meta(results)


def _plain(value: Any) -> Any:
    return None if isinstance(value, float) and math.isnan(value) else value
