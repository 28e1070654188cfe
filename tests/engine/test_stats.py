"""Summary statistics and confidence intervals, checked against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmex.engine.stats import (
    Z95,
    implied_sample_size,
    intervals_overlap,
    mean_difference_ci,
    normal_ci,
    paired_comparisons,
    position_in_interval,
    proportion_difference_ci,
    standard_errors_apart,
    summarize,
    summarize_groups,
    wilson_ci,
)


def test_summary_of_four_values_by_hand():
    s = summarize([4.0, 1.0, 3.0, 2.0], z=Z95)
    assert (s.n, s.min, s.max, s.median, s.mean) == (4, 1.0, 4.0, 2.5, 2.5)
    # sample STD: sqrt(((1.5² + 0.5²) * 2) / 3) = sqrt(5/3)
    assert s.std == pytest.approx(math.sqrt(5 / 3))
    half = 1.96 * math.sqrt(5 / 3) / 2  # 1.96 · STD / √4 = 1.265175
    assert s.ci_low == pytest.approx(2.5 - half)
    assert s.ci_high == pytest.approx(2.5 + half)
    assert s.half_width == pytest.approx(1.265175, abs=1e-6)


def test_population_std_and_other_z():
    s = summarize([1.0, 2.0, 3.0, 4.0], z=2.0, ddof=0)
    assert s.std == pytest.approx(math.sqrt(1.25))
    assert s.ci_high - s.mean == pytest.approx(2.0 * math.sqrt(1.25) / 2)


def test_normal_ci_reproduces_the_thesis_corner_row():
    # Table 5.1, corner nests, totalTimeAll: mean 451.76, STD 6.94 → CI [450.45, 453.07]
    low, high = normal_ci(451.76, 6.94, 108)
    assert round(low, 2) == 450.45 and round(high, 2) == 453.07


def test_implied_sample_size_inverts_the_ci():
    assert implied_sample_size(6.94, 450.45, 453.07) == pytest.approx(107.8, abs=0.1)
    low, high = normal_ci(10.0, 2.0, 50)
    assert implied_sample_size(2.0, low, high) == pytest.approx(50.0)
    assert math.isnan(implied_sample_size(1.0, 5.0, 5.0))


def test_degenerate_samples():
    # one run has no sample STD: it was 0.0, and the interval collapsed to [7, 7], which a
    # report printed as a zero-width CI that "overlaps" any interval holding 7
    one = summarize([7.0], z=Z95)
    assert one.mean == 7.0 and all(math.isnan(v) for v in (one.std, one.ci_low, one.ci_high))
    assert math.isnan(summarize([7.0]).std)
    assert summarize([7.0], ddof=0).std == 0.0  # the population SD of one value is defined
    const = summarize([3.0] * 5, z=Z95)
    assert const.ci == (3.0, 3.0)
    assert summarize([3.0] * 5).ci == (3.0, 3.0)  # Student t too: no spread, no width
    empty = summarize([])
    assert empty.n == 0 and math.isnan(empty.mean) and math.isnan(empty.half_width)
    with pytest.raises(ValueError):
        normal_ci(0.0, 1.0, 0)


def test_overlap_position_and_distance():
    assert intervals_overlap((1, 2), (2, 3))  # touching counts
    assert intervals_overlap((1, 5), (2, 3))
    assert not intervals_overlap((1, 2), (2.01, 3))
    assert position_in_interval(450.0, (450.45, 453.07)) == "below"
    assert position_in_interval(451.0, (450.45, 453.07)) == "inside"
    assert position_in_interval(454.0, (450.45, 453.07)) == "above"
    s = summarize([1.0, 2.0, 3.0, 4.0], z=Z95)  # standard error sqrt(5/3)/2
    assert standard_errors_apart(s, 2.0) == pytest.approx(0.5 / (math.sqrt(5 / 3) / 2))
    assert standard_errors_apart(s, 3.0) == pytest.approx(-0.5 / (math.sqrt(5 / 3) / 2))


def test_distance_is_signed_and_undefined_without_a_standard_error():
    # it was +inf whatever the sign: a mean 0.65 s below the reference read "+inf"
    const = summarize([5.0, 5.0, 5.0])
    assert standard_errors_apart(const, 6.0) == -math.inf
    assert standard_errors_apart(const, 4.0) == math.inf
    assert standard_errors_apart(const, 5.0) == 0.0
    assert math.isnan(standard_errors_apart(summarize([451.11], z=Z95), 451.76))
    # an undefined interval overlaps nothing (the caller gives no verdict)
    nan = math.nan
    assert not intervals_overlap((nan, nan), (0.0, 1000.0))
    assert not intervals_overlap((0.0, 1000.0), (nan, nan))


def test_t_interval_matches_a_hand_computation():
    s = summarize([1.0, 2.0, 3.0, 4.0])
    sd = math.sqrt(((1.5**2) * 2 + (0.5**2) * 2) / 3)  # sample sd of 1..4
    t_975_3 = 3.182446305284263  # Student t quantile, 3 degrees of freedom
    assert s.mean == 2.5 and s.n == 4
    assert s.half_width == pytest.approx(t_975_3 * sd / 2, rel=1e-12)
    assert math.isnan(summarize([7.0]).half_width) and summarize([7.0]).mean == 7.0
    assert summarize([None, float("nan")]).n == 0


def test_summarize_groups_and_skips_failures():
    rows = [
        {"a": 1, "seed": 0, "makespan": 10.0, "complete": True, "error": None},
        {"a": 1, "seed": 1, "makespan": 14.0, "complete": False, "error": None},
        {"a": 2, "seed": 0, "makespan": None, "complete": None, "error": "boom"},
        {"a": 2, "seed": 1, "makespan": 5.0, "complete": True, "error": None},
    ]
    g1, g2 = summarize_groups(rows, ["a"], ["makespan", "complete"])
    assert g1.config == {"a": 1} and (g1.runs, g1.failed) == (2, 0)
    assert g1.stats["makespan"].mean == 12.0
    t_975_1 = 12.706204736174698
    sd = math.sqrt(8)  # sample sd of 10 and 14
    assert g1.stats["makespan"].half_width == pytest.approx(t_975_1 * sd / math.sqrt(2))
    assert g1.stats["complete"].mean == 0.5
    assert (g2.runs, g2.failed, g2.stats["makespan"].n) == (2, 1, 1)


@pytest.mark.parametrize(("k", "n"), [(0, 30), (7, 30), (15, 30), (30, 30), (1, 3)])
def test_wilson_bounds_solve_the_score_equation(k, n):
    """Wilson's bounds are the p with |k/n − p| = z·√(p(1−p)/n) (and 0 / 1 at the ends)."""
    low, high = wilson_ci(k, n)
    ph = k / n
    for p in (low, high):
        if 0 < p < 1:
            assert abs(ph - p) == pytest.approx(Z95 * math.sqrt(p * (1 - p) / n), rel=1e-9)
    assert 0 <= low <= ph <= high <= 1 and (k > 0 or low == 0) and (k < n or high == 1)
    assert all(math.isnan(v) for v in wilson_ci(0, 0))


def test_newcombe_interval_matches_the_published_examples():
    # Newcombe (1998), Statistics in Medicine 17:873, method 10, examples (a) and (c)
    d, lo, hi = proportion_difference_ci(56, 70, 48, 80)
    assert d == pytest.approx(0.2) and (lo, hi) == pytest.approx((0.0524, 0.3339), abs=5e-5)
    _, lo, hi = proportion_difference_ci(9, 10, 3, 10)
    assert (lo, hi) == pytest.approx((0.1705, 0.8090), abs=5e-5)


def test_welch_interval_matches_scipy():
    from scipy import stats

    a, b = [76.1, 74.0, 79.2, 75.5, 77.7], [70.2, 73.9, 69.0, 72.4, 71.1, 68.8]
    d, lo, hi = mean_difference_ci(a, b)
    want = stats.ttest_ind(a, b, equal_var=False).confidence_interval()
    assert d == pytest.approx(np.mean(a) - np.mean(b))
    assert (lo, hi) == pytest.approx((want.low, want.high), rel=1e-9)
    assert mean_difference_ci([1.0, 1.0], [1.0, 1.0]) == (0.0, 0.0, 0.0)
    assert math.isnan(mean_difference_ci([1.0], [2.0, 3.0])[1])


def test_relative_difference_says_how_many_pairs_it_is_over():
    # a baseline of 0 has no ratio: the relative Δ was over 3 pairs while `pairs` said 4
    from swarmex.experiments.compare import as_table

    rows = [{"algorithm": a, "seed": s, "m": v}
            for s, (base, var) in enumerate([(0, 2), (1, 2), (2, 2), (4, 2)])
            for a, v in (("madgta", base), ("nearest", var))]
    (pc,) = paired_comparisons(rows, "algorithm", "madgta", ["algorithm"], ["m"])
    assert (pc.pairs, pc.relative_pairs) == (4, 3)
    assert pc.relative.mean == pytest.approx((1.0 + 0.0 - 0.5) / 3)
    (row,) = as_table([pc], "algorithm", ["algorithm"]).to_pylist()
    assert (row["pairs"], row["relative_pairs"]) == (4, 3)
