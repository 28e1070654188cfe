"""The reproduction: shipped environments, the plan of runs, and the report pipeline."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
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
    full = rr.plan(quick=False, ompl=False)
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
    quick = rr.plan(quick=True, ompl=False)
    assert len(quick) < 120
    assert {j.exp for j in quick} == {"t1", "t2", "t1eps", "t2eps", "unreach"}
    # OMPL's PRM: every row of both tables and the unreachable-goal runs, not the r = ε rerun
    with_ompl = rr.plan(quick=False, ompl=True)
    added = [j for j in with_ompl if j.planner == "ompl-prm"]
    assert len(added) == 20 * 10 + 16 * 30 + 2 * 10
    assert {j.exp for j in added} == {"t1", "t2", "unreach"}
    assert [j for j in with_ompl if j.planner != "ompl-prm"] == full


def test_per_row_winner_needs_a_significant_lead():
    from swarmex.studies.roadmap.analysis import EQUAL, at_travel, versus

    ref = [{"nodes": "100", "step": "40", "sensor_range": "r"}]

    def runs(planner, covs, path=100.0):
        return [{"exp": "t1", "nodes": 100, "step": 40.0, "mult": "r", "planner": planner,
                 "coverage": c, "path_length": path, "goal_found": False,
                 "effort": [[0.0, 0.0], [2 * path, c]]} for c in covs]

    close = runs("wma-rrt", [0.80, 0.82, 0.81]) + runs("prm", [0.60, 0.61, 0.62]) + \
        runs("ompl-prm", [0.82, 0.80, 0.83], path=300.0)
    row = versus(close, ref, "t1")[0]
    assert row["winner"] == "tie: ompl-prm ≈ wma-rrt"
    far = runs("wma-rrt", [0.90, 0.91, 0.92]) + runs("prm", [0.60, 0.61, 0.62]) + \
        runs("ompl-prm", [0.70, 0.71, 0.69], path=300.0)
    row = versus(far, ref, "t1")[0]
    assert row["winner"] == "wma-rrt" and row["wma_minus_ompl"][1] > 0
    # at equal travel OMPL's runs are stopped at WMA-RRT's path (100 of their 600 units)
    assert row["cells"][EQUAL]["mean"] == pytest.approx(100 * np.mean([0.70, 0.71, 0.69]) / 6)
    assert at_travel([[0, 0], [10, 0.5], [20, 0.6]], 15) == pytest.approx(0.55)
    assert at_travel([[0, 0], [10, 0.5]], 99) == 0.5  # never walked that far: its final


def test_report_from_a_tiny_sweep(tmp_path, monkeypatch):
    jobs = [rr.Job("t1", "fig8", "coverage", p, 100, 40.0, "r", 0)
            for p in ("wma-rrt", "prm", "wma-rrt-takeover")]
    jobs += [rr.Job("t2", "fig11", "search", p, 100, 40.0, "r", 0)
             for p in ("wma-rrt", "prm", "wma-rrt-takeover")]
    jobs += [rr.Job("t1", "fig8", "coverage", p, 400, 20.0, "r", 0) for p in ("wma-rrt", "prm")]
    jobs += [rr.Job("unreach", "fig14", "search", p, 60, 20.0, "r", 0)
             for p in ("wma-rrt", "prm")]
    ompl = rr.ompl_available()
    if ompl:
        jobs += [rr.Job(t, env, task, "ompl-prm", 200, 40.0, "r", 0) for t, env, task in
                 (("t1", "fig8", "coverage"), ("t2", "fig11", "search"))]
    monkeypatch.setattr("swarmex.studies.roadmap.pipeline.plan", lambda quick: jobs)
    monkeypatch.setattr("swarmex.studies.roadmap.report.draw_examples", lambda out, res: {})
    report = roadmap.reproduce(tmp_path, quick=True)
    text = report.read_text()
    assert "Table 1" in text and "Table 2" in text and "| 400 | 20 | r | 74 |" in text
    assert "The unreproduced claim" in text and "r = c·ε (c): RMSE" in text
    # one run per row has no sample SD: the cells read "76.5 ± 0.0"
    assert " ± 0.0 " not in text and " ± n/a |" in text
    # a quick report said to regenerate it without --quick, and called a sum of the runs'
    # times "wall time" (it exceeded the invocation's)
    assert "Regenerate with `swarmex reproduce roadmap --quick --out DIR`" in text
    assert "s of wall time in all" not in text and "a sum over runs" in text
    assert (tmp_path / "roadmap_readings.json").exists()
    assert "## A standard PRM: OMPL's" in text and "**Build (pre-processing) time**" in text
    builds = json.loads((tmp_path / "roadmap_buildtimes.json").read_text())
    assert builds["builders"][:2] == ["wma-rrt", "prm"]
    if ompl:
        assert builds["builders"][2:] == ["ompl-prm", "ompl-rrt"]
        rows = [ln for ln in text.split("## A standard PRM")[1].splitlines()
                if ln.startswith("| 200 | 40 | r |")]
        assert len(rows) == 2 and all("**OMPL PRM**" in ln for ln in rows)  # alone there
        assert (tmp_path / "versus_ompl_prm.csv").exists()
    else:
        assert "OMPL's PRM was not run" in text
    assert (tmp_path / "fig6_coverage_vs_samples.png").stat().st_size > 1000
    lines = (tmp_path / "roadmap_runs.jsonl").read_text().splitlines()
    assert len(lines) == len(jobs)
    # a rerun resumes: nothing new is appended
    roadmap.reproduce(tmp_path, quick=True)
    assert len((tmp_path / "roadmap_runs.jsonl").read_text().splitlines()) == len(jobs)
