"""Replay of records: every segment free and on a roadmap edge or leg; tampering is caught."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from swarmex.missions.roadmap import build_record, replay_problems, run_roadmap

from .conftest import cluster


@pytest.fixture(scope="module")
def record(clutter):
    run = run_roadmap(clutter, cluster(3), task="search", nodes=200, step=10, sensor_range=20,
                      goal=np.array(clutter.goal), seed=3)
    return build_record(run, {"task": "search", "starts": cluster(3).tolist()}, 3, 0.0).to_dict()


def test_record_shape(record):
    assert record["mission"] == "roadmap" and record["time_unit"] == "step"
    assert record["world"]["kind"] == "polygons" and record["world"]["free_cells"] > 0
    for key in ("coverage", "goal_found", "goal_unreachable", "steps", "path_length",
                "tree_nodes", "components", "edge_revisits"):
        assert key in record["metrics"]
    for ag in record["agents"]:
        assert all(len(p) == 3 for p in ag["trajectory"])
        assert ag["metrics"]["path_length"] > 0
    assert record["makespan"] == record["metrics"]["steps"]


def test_clean_record_replays(record, clutter):
    assert replay_problems(record, clutter) == []


def test_off_edge_step_is_caught(record, clutter):
    bad = copy.deepcopy(record)
    tr = bad["agents"][0]["trajectory"]
    tr[3][1] += 3.0  # nudge one position off its node
    assert any("neither an edge nor a leg" in p for p in replay_problems(bad, clutter))


def test_collision_is_caught(record, clutter):
    bad = copy.deepcopy(record)
    # pretend the roadmap had an edge straight through the square obstacle
    bad["roadmap"]["nodes"] += [[35.0, 45.0], [75.0, 45.0]]
    k = len(bad["roadmap"]["nodes"])
    bad["roadmap"]["edges"].append([k - 2, k - 1])
    last = bad["agents"][1]["trajectory"][-1][0]
    bad["agents"][1]["trajectory"] += [[last + 1, 35.0, 45.0], [last + 2, 75.0, 45.0]]
    problems = replay_problems(bad, clutter)
    assert any("collides" in p for p in problems)


def test_false_claims_are_caught(record, clutter):
    bad = copy.deepcopy(record)
    bad["agents"][2]["trajectory"] = bad["agents"][2]["trajectory"][:-2]
    assert any("every agent" in p for p in replay_problems(bad, clutter))
    cov = copy.deepcopy(record)
    cov["params"]["task"] = "coverage"  # a search that stopped early is no full coverage
    assert any("never traversed" in p for p in replay_problems(cov, clutter))
