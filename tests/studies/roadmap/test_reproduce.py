"""The reproduction: shipped environments, the plan of runs, and the report pipeline."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from swarmex.studies import roadmap
from swarmex.studies.roadmap import design as rr

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


@pytest.mark.parametrize("name", ["fig8", "fig11", "fig14", "fig17"])
def test_embedded_environments_match_examples(name):
    shipped = json.loads((EXAMPLES / f"roadmap_{name}.json").read_text())
    shipped.pop("description", None)
    assert shipped == rr.ENVIRONMENTS[name]


def test_plan_covers_both_tables():
    full = rr.plan(quick=False)
    t1 = [j for j in full if j.exp == "t1"]
    t2 = [j for j in full if j.exp == "t2"]
    assert len(t1) == 20 * 10 * 3 and len(t2) == 16 * 30 * 3
    assert {j.mult for j in t1} == {"r", "2r", "4r", "inf"}
    # the second reading of r (r = ε): finite rows only, WMA-RRT and PRM
    t1e = [j for j in full if j.exp == "t1eps"]
    t2e = [j for j in full if j.exp == "t2eps"]
    assert len(t1e) == 15 * 10 * 2 and len(t2e) == 12 * 30 * 2
    assert {j.mult for j in t1e} == {"r", "2r", "4r"}
    assert {j.planner for j in t1e + t2e} == {"wma-rrt", "prm"}
    assert len({j.key for j in full}) == len(full)
    quick = rr.plan(quick=True)
    assert len(quick) < 120
    assert {j.exp for j in quick} == {"t1", "t2", "t1eps", "t2eps", "unreach"}


def test_report_from_a_tiny_sweep(tmp_path, monkeypatch):
    jobs = [rr.Job("t1", "fig8", "coverage", p, 100, 40.0, "r", 0)
            for p in ("wma-rrt", "prm", "wma-rrt-takeover")]
    jobs += [rr.Job("t2", "fig11", "search", p, 100, 40.0, "r", 0)
             for p in ("wma-rrt", "prm", "wma-rrt-takeover")]
    jobs += [rr.Job("unreach", "fig14", "search", p, 60, 20.0, "r", 0)
             for p in ("wma-rrt", "prm")]
    monkeypatch.setattr("swarmex.studies.roadmap.pipeline.plan", lambda quick: jobs)
    monkeypatch.setattr("swarmex.studies.roadmap.report.draw_examples", lambda out, res: {})
    report = roadmap.reproduce(tmp_path, quick=True)
    text = report.read_text()
    assert "Table 1" in text and "Table 2" in text and "| 400 | 20 | r | 74 |" in text
    assert "The unreproduced claim" in text and "r = c·ε (c): RMSE" in text
    assert (tmp_path / "roadmap_readings.json").exists()
    assert (tmp_path / "fig6_coverage_vs_samples.png").stat().st_size > 1000
    lines = (tmp_path / "roadmap_runs.jsonl").read_text().splitlines()
    assert len(lines) == len(jobs)
    # a rerun resumes: nothing new is appended
    roadmap.reproduce(tmp_path, quick=True)
    assert len((tmp_path / "roadmap_runs.jsonl").read_text().splitlines()) == len(jobs)
