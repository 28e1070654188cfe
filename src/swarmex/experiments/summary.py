"""Means and 95 % confidence intervals of a sweep's metrics, per configuration.

A configuration is one combination of the parameters other than the seed; its runs are the
seeds. The interval is Student's t: ``mean ± t(0.975, n-1) · s / √n`` with ``s`` the sample
standard deviation (``ddof = 1``), the usual choice for a handful of seeds whose spread is
unknown; it is undefined (NaN) for a single run. Failed runs (with an ``error``) are counted
apart and left out of the statistics, since they have no metrics.

Plain Python and numpy over the rows: a sweep table has thousands of rows at most, and this
keeps pandas out of the dependencies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

CONFIDENCE = 0.95


@dataclass(frozen=True)
class Stat:
    mean: float
    half_width: float  # the CI is mean ± half_width; NaN when n < 2
    n: int

    @property
    def low(self) -> float:
        return self.mean - self.half_width

    @property
    def high(self) -> float:
        return self.mean + self.half_width


@dataclass
class ConfigSummary:
    config: dict[str, Any]  # parameter -> value
    runs: int
    failed: int
    stats: dict[str, Stat] = field(default_factory=dict)


def mean_ci(values: list[float] | np.ndarray, confidence: float = CONFIDENCE) -> Stat:
    """Mean and Student-t half width of the finite values (None/NaN are left out)."""
    from scipy.special import stdtrit  # Student t quantile; far lighter to import than stats

    x = np.asarray([v for v in values if v is not None], dtype=float)
    x = x[np.isfinite(x)]
    n = int(x.size)
    if n == 0:
        return Stat(math.nan, math.nan, 0)
    mean = float(x.mean())
    if n < 2:
        return Stat(mean, math.nan, n)
    half = float(stdtrit(n - 1, 0.5 + confidence / 2) * x.std(ddof=1) / math.sqrt(n))
    return Stat(mean, half, n)


def summarize(
    rows: list[dict[str, Any]],
    by: list[str],
    metrics: list[str],
    confidence: float = CONFIDENCE,
) -> list[ConfigSummary]:
    """Group ``rows`` by the ``by`` columns (first-seen order) and summarise ``metrics``.

    Booleans (``complete``) average to the fraction of runs where they hold.
    """
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for row in rows:
        groups.setdefault(tuple(row.get(k) for k in by), []).append(row)
    out = []
    for key, members in groups.items():
        ok = [r for r in members if not r.get("error")]
        stats = {m: mean_ci([_number(r.get(m)) for r in ok], confidence) for m in metrics}
        out.append(
            ConfigSummary(
                dict(zip(by, key, strict=True)), len(members), len(members) - len(ok), stats
            )
        )
    return out


def _number(v: Any) -> float | None:
    if v is None:
        return None
    if isinstance(v, bool):
        return float(v)
    if isinstance(v, int | float):
        return float(v)
    return None
