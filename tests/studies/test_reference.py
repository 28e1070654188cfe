"""The seeds' reference numbers ship in the package and match the shared copies."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from swarmex.studies import reference_file

NAMES = (
    "foraging_fig78_79.csv",
    "roadmap_table1.csv",
    "roadmap_table2.csv",
    "traversal_tables_5_1_5_2.csv",
)


@pytest.mark.parametrize("name", NAMES)
def test_reference_is_packaged_and_matches_the_shared_copy(name):
    ours = list(csv.reader(reference_file(name).read_text(encoding="utf-8").splitlines()))
    assert len(ours) > 1
    shared = Path(__file__).resolve().parents[3] / "shared/reference" / name
    if not shared.exists():
        pytest.skip("../shared/reference not present")
    with open(shared, encoding="utf-8") as fh:
        assert list(csv.reader(fh)) == ours
