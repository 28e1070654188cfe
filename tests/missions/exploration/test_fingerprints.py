"""Exploration records at 5-20 robots are unchanged by the scale work (fingerprints.py)."""

from __future__ import annotations

import json

import pytest

from tests.missions.exploration.fingerprints import RECORDS, digest, run_one, scenarios

GOLDEN = json.loads(RECORDS.read_text())


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    return scenarios(tmp_path_factory.mktemp("maps"))


@pytest.mark.parametrize("name", sorted(GOLDEN))
def test_record_unchanged(name, cases):
    rec = run_one(cases[name])
    want = GOLDEN[name]
    assert (rec["makespan"], rec["complete"]) == (want["makespan"], want["complete"])
    assert digest(rec) == want["sha256"], f"{name}: record changed (see fingerprints.py)"


def test_every_scenario_is_recorded(tmp_path):
    assert sorted(GOLDEN) == sorted(scenarios(tmp_path))
