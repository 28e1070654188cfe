"""``bench/compare_foraging_patterns.py`` runs recall as a series of trips: trip i remembers
the band's cells of trips 0 … i - 1, and its table counts what recall chose."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))


def test_each_trip_remembers_the_bands_earlier_cells_and_only_recall_remembers():
    from compare_foraging_patterns import memory

    cells = [(1, 2), (3, 4), (5, 6)]
    assert memory("recall", cells, 0) == ()
    assert memory("recall", cells, 2) == ((1, 2), (3, 4))
    assert memory("strips", cells, 2) == ()


def test_the_choices_table_counts_patterns_and_averages_the_later_trips():
    from compare_foraging_patterns import choices

    rows = [
        (("recall", 8, "0-20", i, (0, 0), ()), 0.0,
         {"pattern": "annulus 3-9" if i % 3 else "sectors", "total_time": 100.0 + i})
        for i in range(10)
    ]  # fmt: skip
    rows.append((("strips", 8, "0-20", 0, (0, 0), ()), 0.0, {"total_time": 1.0}))
    table = choices(rows)
    assert table[2] == "| 8 | 0%-20% | annulus 6, sectors 4 | 108 |"  # trips 8, 9: 108.5
    assert len(table) == 3
