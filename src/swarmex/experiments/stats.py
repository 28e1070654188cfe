"""Summary statistics for reproduction reports: the seeds' table columns, computed one way.

Every study we reproduce reports samples the same way: min, max, median, mean, standard
deviation and a 95 % confidence interval of the mean. Seed 000 never says how its interval is
computed, but its half-widths match the normal approximation ``mean ± z·STD/√n`` with
z = 1.96 (spec §4.1 [derived]), so that is the default here; ``z`` and the degrees-of-freedom
correction are parameters because other seeds may differ. The helpers are plain functions of
plain data so that any reproduction (traversal, roadmap, foraging) can reuse them and tests can
check them against hand-computed values.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass

import numpy as np

Z95 = 1.96  # two-sided 95 % quantile of the standard normal, as the seeds use it


@dataclass(frozen=True)
class Summary:
    """The columns of a seed's results table for one sample."""

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

    def to_dict(self) -> dict[str, float | int]:
        return asdict(self)


def normal_ci(mean: float, std: float, n: int, z: float = Z95) -> tuple[float, float]:
    """``mean ± z·std/√n``: the interval seed 000's tables are consistent with.

    A single sample has no spread estimate, so its interval collapses to the mean rather than
    failing: reports then still render, and the n column says why the interval is empty.
    """
    if n < 1:
        raise ValueError("a confidence interval needs at least one sample")
    if n == 1 or not math.isfinite(std):
        return (mean, mean)
    half = z * std / math.sqrt(n)
    return (mean - half, mean + half)


def summarize(values: Iterable[float], z: float = Z95, ddof: int = 1) -> Summary:
    """Min, max, median, mean, STD (``ddof`` = 1: the sample STD) and the normal 95 % CI.

    ``ddof`` defaults to 1 because the samples are runs drawn from a population of seeds; with
    the ~100 runs of the seeds' tables the choice moves the STD by 0.5 % and no reported digit.
    """
    arr = np.asarray(list(values), dtype=float)
    if arr.size == 0:
        raise ValueError("cannot summarize an empty sample")
    n = int(arr.size)
    mean = float(arr.mean())
    std = float(arr.std(ddof=ddof)) if n > ddof else 0.0
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


def intervals_overlap(a: Sequence[float], b: Sequence[float]) -> bool:
    """Whether the closed intervals ``a`` and ``b`` share at least one point."""
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
    """How many of our standard errors our mean lies from a reference mean (signed)."""
    if ours.n < 2 or ours.std == 0:
        return math.inf if ours.mean != mean else 0.0
    return (ours.mean - mean) / (ours.std / math.sqrt(ours.n))


def position_in_interval(value: float, interval: Sequence[float]) -> str:
    """'below', 'inside' or 'above' the closed interval: a report's one-word verdict."""
    if value < interval[0]:
        return "below"
    if value > interval[1]:
        return "above"
    return "inside"
