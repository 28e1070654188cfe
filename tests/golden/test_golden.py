"""Golden records (issue 12): fixed-seed runs of every mission and algorithm, recorded before
the code moved behind the Mission contract, must stay byte-identical (``wall_seconds`` aside).

Regenerate only for a deliberate change of results: ``python tests/golden/make_golden.py``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from tests.golden.make_golden import digest, run_cli
from tests.golden.scenarios import SCENARIOS

REPO = Path(__file__).resolve().parents[2]
GOLDEN = json.loads(Path(__file__).with_name("records.json").read_text())


@pytest.fixture(autouse=True)
def _at_repo_root(monkeypatch):
    monkeypatch.chdir(REPO)  # the scenarios name files relative to the repository


@pytest.mark.parametrize(
    ("name", "mission", "command", "argv"), SCENARIOS, ids=[s[0] for s in SCENARIOS]
)
def test_cli_record_unchanged(name, mission, command, argv):
    rec = run_cli(command, argv)
    assert rec["mission"] == mission
    assert digest(rec) == GOLDEN[name]["sha256"], f"{name}: record changed (see make_golden.py)"


def test_every_scenario_has_a_golden_record():
    assert sorted(GOLDEN) == sorted(s[0] for s in SCENARIOS)
    assert os.path.exists(REPO / "tests" / "golden" / "tiny.map")
