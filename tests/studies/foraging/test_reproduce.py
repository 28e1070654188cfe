"""The reproduction's bookkeeping: food cells, reference numbers, aggregation, report."""

from __future__ import annotations

from swarmex.studies.foraging import analysis as A
from swarmex.studies.foraging import design as R
from swarmex.studies.foraging.report import write_report


def test_reference_has_the_78_rows_of_figs_78_79():
    ref = R.reference()
    assert len(ref) == 78
    assert ref[("0-20", "strips", 4)]["exploration"] == 2108
    assert ref[("random", "spiral", 16)]["transportation"] == 504


def test_food_cells_are_shared_and_in_band():
    a, b = R.food_cells(7, 5), R.food_cells(7, 5)
    assert a == b
    for x, y in a["80-100"]:
        assert abs(x - 64) + abs(y - 64) >= 102


def test_aggregate_and_report(tmp_path):
    ref = R.reference()
    runs = {}
    for (band, pattern, n), row in ref.items():
        for i in range(2):
            key = R.run_key(pattern, n, band, i, "relay-food")
            m = {R.METRIC_OF[c]: row[c] + i for c in R.COLUMNS}
            m["total_time"] = sum(m.values())
            runs[key] = {
                "key": key, "pattern": pattern, "n": n, "band": band, "i": i,
                "transport": "relay-food", "cells_revisited": 0, "wall": 0.01, **m,
            }  # fmt: skip
    table = A.aggregate(runs)
    row = table[("random", "strips", 16, "relay-food")]
    assert row["exploration"] == 640.5 and row["runs"] == 2
    A.write_csv(table, tmp_path / "t.csv")
    path = write_report(tmp_path, table, {}, ref, {}, True, 1, 2, runs, {})
    text = path.read_text()
    assert text.count("| RANDOM |") >= 13
    assert "Why our numbers differ" in text
