"""The strategy comparison's map scenarios when the MovingAI maps are not at hand (a wheel
install run away from the repository): left out, and said so, never silently."""

from __future__ import annotations

from swarmex.studies.exploration.design import (
    QUICK_SCENARIOS,
    missing_maps,
    skipped_note,
    strategy_jobs,
)


def test_missing_maps_are_named_and_their_jobs_skipped(tmp_path, monkeypatch):
    monkeypatch.setenv("SWARMEX_MAPS", str(tmp_path))
    assert missing_maps(QUICK_SCENARIOS) == ["room-32-32-4.map"]
    assert {j["scenario"] for j in strategy_jobs(QUICK_SCENARIOS, 1)} == {QUICK_SCENARIOS[0][0]}
    note = skipped_note(["room-32-32-4.map"])
    assert "room-32-32-4.map" in note and str(tmp_path) in note and "SWARMEX_MAPS" in note

    (tmp_path / "room-32-32-4.map").write_text("type octile\n", encoding="ascii")
    assert missing_maps(QUICK_SCENARIOS) == []
    assert len({j["scenario"] for j in strategy_jobs(QUICK_SCENARIOS, 1)}) == 2
