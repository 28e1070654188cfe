"""Summary statistics and 95 % confidence intervals: the one implementation swarmex uses.

Every table of results, from a sweep's summary to a seed's reproduced Table 5.1, reports a
sample the same way: :func:`summarize` gives n, min, max, median, mean, standard deviation
and a confidence interval of the mean, as a :class:`Summary`. Two intervals are offered,
because the two uses need different ones:

* **Student's t** (the default): ``mean ± t(0.975, n-1) · s / √n`` with ``s`` the sample
  standard deviation (``ddof = 1``). The usual choice for a handful of seeds whose spread is
  unknown; it is undefined (NaN half width) for a single run. Sweeps and plots use it.
* **Normal approximation**, ``z`` given: ``mean ± z · s / √n``. Seed 000 never says how its
  intervals are computed, but its half-widths match this with z = 1.96 (:data:`Z95`, spec §4.1
  [derived]), so its reproduction uses it to compare like with like. A single sample has no
  spread estimate either: its STD and both bounds are NaN, and reports print them as
  "n/a" with no overlap verdict (a zero-width interval would claim a precision one run
  cannot give).

Missing values (None, NaN, ±inf) are left out, so a failed run's empty metric does not poison
the others; an empty sample gives ``n = 0`` and NaN everywhere. :func:`summarize_groups`
applies the same to the rows of a sweep, one :class:`Summary` per configuration and metric.
The remaining helpers compare our intervals with a seed's published ones. Plain functions of
plain data (numpy, plus SciPy's t quantile), so tests check them against hand-computed values.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from swarmex.errors import InputError

CONFIDENCE = 0.95
Z95 = 1.96  # two-sided 95 % quantile of the standard normal, as the seeds use it


@dataclass(frozen=True)
class Summary:
    """The columns of a results table for one sample (NaN where undefined)."""

    n: int
    min: float
    max: float
    median: float
    mean: float
    std: float
    ci_low: float
    ci_high: float

    @property
    def half_width(self) -> float:
        return (self.ci_high - self.ci_low) / 2.0

    @property
    def ci(self) -> tuple[float, float]:
        return (self.ci_low, self.ci_high)

    @property
    def has_ci(self) -> bool:
        """Whether the sample has a confidence interval (not with fewer than two runs): a
        body to draw, an overlap to judge."""
        return not (math.isnan(self.ci_low) or math.isnan(self.ci_high))

    def to_dict(self) -> dict[str, float | int]:
        return asdict(self)


def normal_ci(mean: float, std: float, n: int, z: float = Z95) -> tuple[float, float]:
    """``mean ± z·std/√n``: the interval seed 000's tables are consistent with.

    A single sample has no spread estimate, so its interval is undefined: NaN bounds, as
    :func:`t_ci` gives.
    """
    if n < 1:
        raise ValueError("a confidence interval needs at least one sample")
    if n == 1 or not math.isfinite(std):
        return (math.nan, math.nan)
    half = z * std / math.sqrt(n)
    return (mean - half, mean + half)


def t_ci(mean: float, std: float, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """``mean ± t(½ + confidence/2, n-1)·std/√n``; NaN bounds for fewer than two samples."""
    if n < 2:
        return (math.nan, math.nan)
    from scipy.special import stdtrit  # Student t quantile; far lighter to import than stats

    half = float(stdtrit(n - 1, 0.5 + confidence / 2) * std / math.sqrt(n))
    return (mean - half, mean + half)


def summarize(
    values: Iterable[float | None],
    confidence: float = CONFIDENCE,
    z: float | None = None,
    ddof: int = 1,
) -> Summary:
    """Min, max, median, mean, STD and a confidence interval of the finite ``values``.

    The interval is Student's t at ``confidence``, or the normal ``mean ± z·STD/√n`` when
    ``z`` is given (then ``confidence`` is not used). ``ddof`` defaults to 1 because the samples
    are runs drawn from a population of seeds; with the ~100 runs of the seeds' tables the
    choice moves the STD by 0.5 % and no reported digit. With ``n <= ddof`` values (one run,
    for the sample STD) the STD is undefined: NaN, and so are the interval's bounds.
    """
    arr = np.asarray([v for v in values if v is not None], dtype=float)
    arr = arr[np.isfinite(arr)]
    n = int(arr.size)
    if n == 0:
        nan = math.nan
        return Summary(0, nan, nan, nan, nan, nan, nan, nan)
    mean = float(arr.mean())
    std = float(arr.std(ddof=ddof)) if n > ddof else math.nan
    if z is None:
        low, high = t_ci(mean, std, n, confidence)
    else:
        low, high = normal_ci(mean, std, n, z)
    return Summary(
        n=n,
        min=float(arr.min()),
        max=float(arr.max()),
        median=float(np.median(arr)),
        mean=mean,
        std=std,
        ci_low=low,
        ci_high=high,
    )


def wilson_ci(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson's score interval of a proportion ``k / n`` (NaN for n = 0).

    For success rates over a few dozen runs: unlike ``p ± z·√(p(1-p)/n)`` it stays inside
    [0, 1] and does not collapse to a point at 0 or n successes.
    """
    if n < 1:
        return (math.nan, math.nan)
    p = k / n
    den = 1.0 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return (max(0.0, mid - half), min(1.0, mid + half))


def proportion_difference_ci(k1: int, n1: int, k2: int, n2: int,
                             z: float = Z95) -> tuple[float, float, float]:
    """``(p1 − p2, low, high)``: Newcombe's hybrid score interval (1998, method 10), built
    from the two Wilson intervals — the difference of two success rates over runs."""
    if n1 < 1 or n2 < 1:
        return (math.nan, math.nan, math.nan)
    p1, p2 = k1 / n1, k2 / n2
    l1, u1 = wilson_ci(k1, n1, z)
    l2, u2 = wilson_ci(k2, n2, z)
    d = p1 - p2
    return (d, d - math.sqrt((p1 - l1) ** 2 + (u2 - p2) ** 2),
            d + math.sqrt((u1 - p1) ** 2 + (p2 - l2) ** 2))


def mean_difference_ci(a: Sequence[float], b: Sequence[float],
                       confidence: float = CONFIDENCE) -> tuple[float, float, float]:
    """``(mean(a) − mean(b), low, high)``: Welch's interval (unequal variances,
    Welch–Satterthwaite degrees of freedom); NaN bounds when either sample has fewer than
    two values. Equal samples of zero spread give a zero-width interval at the difference."""
    x = np.asarray(a, dtype=float)
    y = np.asarray(b, dtype=float)
    if len(x) == 0 or len(y) == 0:
        return (math.nan, math.nan, math.nan)
    d = float(x.mean() - y.mean())
    if len(x) < 2 or len(y) < 2:
        return (d, math.nan, math.nan)
    vx, vy = x.var(ddof=1) / len(x), y.var(ddof=1) / len(y)
    se2 = vx + vy
    if se2 == 0:
        return (d, d, d)
    df = se2 * se2 / (vx * vx / (len(x) - 1) + vy * vy / (len(y) - 1))
    from scipy.special import stdtrit

    half = float(stdtrit(df, 0.5 + confidence / 2) * math.sqrt(se2))
    return (d, d - half, d + half)


@dataclass
class ConfigSummary:
    """One configuration of a sweep (the parameters other than the seed) and its runs."""

    config: dict[str, Any]  # parameter -> value
    runs: int
    failed: int
    stats: dict[str, Summary] = field(default_factory=dict)


def summarize_groups(
    rows: list[dict[str, Any]],
    by: list[str],
    metrics: list[str],
    confidence: float = CONFIDENCE,
) -> list[ConfigSummary]:
    """Group ``rows`` by the ``by`` columns (first-seen order) and summarise ``metrics``.

    Failed runs (with an ``error``) are counted apart and left out of the statistics, since
    they have no metrics. Booleans (``complete``) average to the fraction of runs where they
    hold; values that are not numbers count as missing.
    """
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for row in rows:
        groups.setdefault(tuple(row.get(k) for k in by), []).append(row)
    out = []
    for key, members in groups.items():
        ok = [r for r in members if not r.get("error")]
        stats = {
            m: summarize([_number(r.get(m)) for r in ok], confidence) for m in metrics
        }
        out.append(
            ConfigSummary(
                dict(zip(by, key, strict=True)), len(members), len(members) - len(ok), stats
            )
        )
    return out


@dataclass
class PairedComparison:
    """One variant against the baseline on one metric, paired run by run: the same
    configuration otherwise and the same seed (so the same world, starts and draws).

    ``config`` is the variant's value of the compared parameter and the group's other
    parameters (empty of them for the pooled row); ``pairs`` the runs with both sides'
    values; ``diff`` summarises variant − baseline per pair, ``relative`` variant / baseline
    − 1 (a pair whose baseline is 0 is left out of it: :attr:`relative_pairs` counts the
    pairs it is over, fewer than ``pairs`` then); ``lower`` and ``higher`` count the
    pairs where the variant's value is below or above the baseline's (which is better
    depends on the metric: makespan lower, coverage higher)."""

    config: dict[str, Any]
    metric: str
    pairs: int
    baseline_mean: float
    variant_mean: float
    diff: Summary
    relative: Summary
    lower: int
    higher: int

    @property
    def relative_pairs(self) -> int:
        """The pairs the relative difference is over: those with a nonzero baseline."""
        return self.relative.n


def paired_comparisons(
    rows: list[dict[str, Any]],
    axis: str,
    baseline: Any,
    by: list[str],
    metrics: list[str],
    confidence: float = CONFIDENCE,
) -> list[PairedComparison]:
    """Every other value of the ``axis`` column against ``baseline``, per group of the ``by``
    columns (without ``axis``) and pooled over the groups when there are several.

    A pair is two runs that differ only in ``axis``: equal ``by`` columns and ``seed``.
    Failed runs (an ``error``) and missing values leave their pair out. The intervals are
    Student's t over the pairs, the comparisons the docs' tables make by hand (a paired
    interval cancels the spread between seeds, which an unpaired one keeps). Values compare
    as text, so ``agents=4`` finds the integer 4 of a table."""
    key_cols = [c for c in by if c != axis]
    base: dict[tuple, dict[str, Any]] = {}
    variants: dict[Any, list[dict[str, Any]]] = {}
    seen: set[tuple] = set()
    for row in rows:
        if row.get("error"):
            continue
        key = (*(row.get(c) for c in key_cols), row.get("seed"))
        # two runs with one key: the table varies a column the axes do not name (two sweeps
        # concatenated), and pairing them anyway compared runs of different configurations
        if (str(row.get(axis)), key) in seen:
            named = ", ".join(f"{c}={v}" for c, v in zip([*key_cols, "seed"], key, strict=True))
            raise InputError(
                f"two runs of {axis}={row.get(axis)} share {named}: the table varies a"
                " parameter its axes do not name (two sweeps put together?), so runs cannot"
                " be paired; compare each sweep alone"
            )
        seen.add((str(row.get(axis)), key))
        if str(row.get(axis)) == str(baseline):
            base[key] = row
        else:
            variants.setdefault(row.get(axis), []).append(row)
    out: list[PairedComparison] = []
    for value, members in variants.items():
        for metric in metrics:
            groups: dict[tuple, list[tuple[float, float]]] = {}
            for row in members:
                group = tuple(row.get(c) for c in key_cols)
                other = base.get((*group, row.get("seed")))
                a = _number(other.get(metric)) if other is not None else None
                b = _number(row.get(metric))
                if a is not None and b is not None and math.isfinite(a) and math.isfinite(b):
                    groups.setdefault(group, []).append((a, b))
            pooled = [p for pairs in groups.values() for p in pairs]
            cases = [(dict(zip(key_cols, g, strict=True)), pairs) for g, pairs in groups.items()]
            if len(groups) > 1:
                cases.append(({}, pooled))
            for config, pairs in cases:
                out.append(_paired({axis: value, **config}, metric, pairs, confidence))
    return out


def _paired(config: dict[str, Any], metric: str, pairs: list[tuple[float, float]],
            confidence: float) -> PairedComparison:
    a = np.array([p[0] for p in pairs], dtype=float)
    b = np.array([p[1] for p in pairs], dtype=float)
    nonzero = a != 0
    return PairedComparison(
        config=config,
        metric=metric,
        pairs=len(pairs),
        baseline_mean=float(a.mean()) if len(a) else math.nan,
        variant_mean=float(b.mean()) if len(b) else math.nan,
        diff=summarize(b - a, confidence),
        relative=summarize(b[nonzero] / a[nonzero] - 1.0, confidence),
        lower=int((b < a).sum()),
        higher=int((b > a).sum()),
    )


def _number(v: Any) -> float | None:
    if isinstance(v, bool | int | float):
        return float(v)
    return None


def intervals_overlap(a: Sequence[float], b: Sequence[float]) -> bool:
    """Whether the closed intervals ``a`` and ``b`` share at least one point (not when
    either is undefined, with a NaN bound: callers give no verdict then)."""
    if any(math.isnan(x) for x in (*a[:2], *b[:2])):
        return False
    return max(a[0], b[0]) <= min(a[1], b[1])


def implied_sample_size(std: float, ci_low: float, ci_high: float, z: float = Z95) -> float:
    """The n for which ``z·std/√n`` equals the half-width of a published interval.

    Seeds rarely state their run counts; inverting the CI formula recovers them (seed 000's
    rows all give n ≈ 108), which is how we choose our own run counts to compare like with like.
    """
    half = (ci_high - ci_low) / 2.0
    if half <= 0:
        return math.nan
    return (z * std / half) ** 2


def standard_errors_apart(ours: Summary, mean: float) -> float:
    """How many of our standard errors our mean lies from a reference mean (signed:
    negative when our mean is below it).

    NaN when the standard error is undefined (fewer than two runs); ±inf, with the sign of
    the difference, when our runs have no spread at all and the means differ.
    """
    if ours.n < 2 or not math.isfinite(ours.std):
        return math.nan
    if ours.std == 0:
        return math.copysign(math.inf, ours.mean - mean) if ours.mean != mean else 0.0
    return (ours.mean - mean) / (ours.std / math.sqrt(ours.n))


def position_in_interval(value: float, interval: Sequence[float]) -> str:
    """'below', 'inside' or 'above' the closed interval: a report's one-word verdict."""
    if value < interval[0]:
        return "below"
    if value > interval[1]:
        return "above"
    return "inside"
