"""Summary statistics and the resumable run store, checked against hand-computed values."""

from __future__ import annotations

import json
import math

import pytest

from swarmex.experiments.runstore import RunStore, stable_seed
from swarmex.experiments.stats import (
    implied_sample_size,
    intervals_overlap,
    normal_ci,
    position_in_interval,
    standard_errors_apart,
    summarize,
)


def test_summary_of_four_values_by_hand():
    s = summarize([4.0, 1.0, 3.0, 2.0])
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
    one = summarize([7.0])
    assert (one.std, one.ci_low, one.ci_high) == (0.0, 7.0, 7.0)
    const = summarize([3.0] * 5)
    assert const.ci == (3.0, 3.0)
    with pytest.raises(ValueError):
        summarize([])
    with pytest.raises(ValueError):
        normal_ci(0.0, 1.0, 0)


def test_overlap_position_and_distance():
    assert intervals_overlap((1, 2), (2, 3))  # touching counts
    assert intervals_overlap((1, 5), (2, 3))
    assert not intervals_overlap((1, 2), (2.01, 3))
    assert position_in_interval(450.0, (450.45, 453.07)) == "below"
    assert position_in_interval(451.0, (450.45, 453.07)) == "inside"
    assert position_in_interval(454.0, (450.45, 453.07)) == "above"
    s = summarize([1.0, 2.0, 3.0, 4.0])  # standard error sqrt(5/3)/2
    assert standard_errors_apart(s, 2.0) == pytest.approx(0.5 / (math.sqrt(5 / 3) / 2))


def test_stable_seed_is_a_fixed_function_of_its_parts():
    assert stable_seed("traversal", "k", 3) == stable_seed("traversal", "k", 3)
    assert stable_seed("traversal", "k", 3) != stable_seed("traversal", "k", 4)
    assert 0 <= stable_seed("x") < 2**32
    # sha256("a|1")[:4] little-endian: pinned so seeds never drift between versions
    assert stable_seed("a", 1) == int.from_bytes(
        __import__("hashlib").sha256(b"a|1").digest()[:4], "little"
    )


def test_run_store_keeps_runs_across_an_interruption(tmp_path):
    path = tmp_path / "runs.json"
    store = RunStore(path, {"study": "t"}, flush_every=1e9)
    store.add({"id": "a#0", "x": 1})
    store.add({"id": "a#1", "x": 2})
    # simulate a kill: no close(), and a torn last journal line
    store._journal.write('{"id": "a#2", "x"')
    store._journal.flush()
    again = RunStore(path, {"study": "t"})
    assert "a#0" in again and "a#1" in again and "a#2" not in again
    again.add_config("a", {"p": 1})
    again.close()
    data = json.loads(path.read_text())
    assert set(data["runs"]) == {"a#0", "a#1"}
    assert data["configs"] == {"a": {"p": 1}} and data["study"] == "t"
    assert not store.journal_path.exists()
