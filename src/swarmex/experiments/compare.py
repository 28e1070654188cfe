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
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from swarmex.engine.stats import PairedComparison, paired_comparisons
from swarmex.errors import InputError

#: the columns of the comparison table, in order (after the group's parameter columns)
COLUMNS = ("metric", "pairs", "baseline_mean", "mean", "diff", "diff_low", "diff_high",
           "relative", "relative_low", "relative_high", "lower_in", "higher_in")


def parse_baseline(text: str) -> tuple[str, str]:
    """``PARAM=VALUE`` (the command line's ``--baseline``) as its two parts."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise InputError(f"--baseline: expected PARAM=VALUE (algorithm=madgta), got {text!r}")
    return name.strip().replace("-", "_"), value.strip()


def check_baseline(axes: Mapping[str, Sequence[Any]], name: str, value: Any,
                   option: str = "--baseline") -> None:
    """The compared parameter must be an axis of the sweep with at least two values, one of
    them the baseline's (an InputError naming what is wrong, before any run)."""
    varying = {k: v for k, v in axes.items() if len(v) > 1}
    if name not in varying:
        have = ", ".join(varying) or "none"
        raise InputError(f"{option}: {name!r} is not a parameter the sweep varies (it varies:"
                         f" {have})")
    values = [str(v) for v in varying[name]]
    if str(value) not in values:
        raise InputError(f"{option}: {name} has no value {value!r} in this sweep (its values:"
                         f" {', '.join(values)})")


def comparisons(table: Any, meta: Mapping[str, Any], name: str, value: Any,
                metrics: Sequence[str]) -> list[PairedComparison]:
    """The paired comparisons of a sweep ``table`` (its metadata names the axes)."""
    axes = [a for a in meta.get("axes", []) if a in table.column_names]
    if name not in axes:
        raise InputError(f"baseline: {name!r} is not a parameter the sweep varies (it varies:"
                         f" {', '.join(axes) or 'none'})")
    present = {str(v) for v in table.column(name).to_pylist()}
    if str(value) not in present:
        raise InputError(f"baseline: {name} has no value {value!r} in this sweep (its values:"
                         f" {', '.join(sorted(present))})")
    missing = [m for m in metrics if m not in table.column_names]
    if missing:
        raise InputError(f"metric {missing[0]!r}: no such column (have:"
                         f" {', '.join(table.column_names)})")
    return paired_comparisons(table.to_pylist(), name, value, axes, list(metrics))


def as_table(results: list[PairedComparison], name: str, axes: Sequence[str]) -> Any:
    """The comparisons as a ``pyarrow.Table``: the compared parameter and the group's other
    axes (null in a pooled row), then :data:`COLUMNS`; ``relative`` is a fraction."""
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
            lower_in=r.lower, higher_in=r.higher,
        )
        rows.append(row)
    return pa.Table.from_pylist(rows) if rows else pa.table({c: [] for c in (*params, *COLUMNS)})


def load(results: Any) -> tuple[Any, dict[str, Any]]:
    """A sweep's table and metadata from its folder (or results file), or from the table
    ``swarmex.sweep`` returned (its schema metadata names the axes)."""
    import json

    from swarmex.experiments.sweep import METADATA_KEY, read_results

    if isinstance(results, str | Path):
        return read_results(results)
    schema = getattr(results, "schema", None)
    if schema is None:
        raise InputError(f"expected a sweep folder or the table swarmex.sweep returned, got"
                         f" {type(results).__name__}")
    raw = (schema.metadata or {}).get(METADATA_KEY)
    return results, (json.loads(raw) if raw else {})


def _plain(value: Any) -> Any:
    return None if isinstance(value, float) and math.isnan(value) else value
