"""The PRM baseline: its loops end at the step budget, and they show in the record."""

from __future__ import annotations

import numpy as np

from swarmex.missions.roadmap import build_record, replay_problems, run_roadmap
from swarmex.planning.prm import build_prm

from .conftest import cluster


def test_step_budget_ends_the_walk(clutter):
    run = run_roadmap(clutter, cluster(3), planner="prm", nodes=150, step=10, sensor_range=15,
                      seed=0, step_budget=40)
    assert run.steps == 40 and run.budget_exhausted and not run.complete
    assert all(m <= 40 for m in run.moves)


def test_loops_and_revisits_are_recorded(enclosed):
    """Walled in with the goal outside (Fig. 15): the walkers never learn it is unreachable;
    they loop until the budget and revisit edges."""
    starts = cluster(3)
    rng = np.random.default_rng(2)
    # a PRM whose trees start inside the walls, so the team can join it
    rm = build_prm(enclosed, starts, 120, 8, rng)
    while rm.entry_node.min() < 0:
        rm = build_prm(enclosed, starts, 120, 8, rng)
    run = run_roadmap(enclosed, starts, task="search", planner="prm", nodes=120, step=8,
                      sensor_range=30, goal=np.array(enclosed.goal), seed=2, roadmap=rm,
                      step_budget=600)
    rec = build_record(run, {"task": "search", "starts": starts.tolist()}, 2, 0.0).to_dict()
    m = rec["metrics"]
    assert not rec["complete"] and not m["goal_found"] and not m["goal_unreachable"]
    assert m["budget_exhausted"] and m["steps"] == 600
    assert m["edge_revisits"] > 0 and m["cycles"] > 0
    assert m["components"] == rm.components >= 1
    assert replay_problems(rec, enclosed) == []


def test_prm_search_finds_and_follows(clutter):
    goal = np.array(clutter.goal)
    run = run_roadmap(clutter, cluster(3), task="search", planner="prm", nodes=300, step=10,
                      sensor_range=25, goal=goal, seed=1, step_budget=3000)
    assert run.goal_found
    rec = build_record(run, {"task": "search", "starts": cluster(3).tolist()}, 1, 0.0).to_dict()
    assert replay_problems(rec, clutter) == []
