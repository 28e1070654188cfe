"""OMPL's PRM as the roadmap mission's standard baseline (``--planner ompl-prm``).

The roadmap is checked against an independent construction of the textbook PRM: milestones
are exactly the run generator's free draws, and milestone i is joined to each of its 10
nearest earlier milestones whose segment is free (tested through the world's STRtree route,
not the union OMPL was given). Without the ``ompl`` extra: one line naming it, exit 2.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.roadmap import build_record, replay_problems, run_roadmap

from .conftest import cluster

ompl_planning = pytest.importorskip("swarmex.planning.ompl")
pytest.importorskip("ompl.base")


def test_prm_is_k_nearest_on_the_run_generators_milestones(clutter):
    k_nodes = 120
    rm = ompl_planning.build_ompl_prm(clutter, cluster(3), k_nodes, np.random.default_rng(4))
    want = clutter.sample_free(np.random.default_rng(4), k_nodes)
    assert rm.n_nodes == k_nodes and np.array_equal(rm.pos, want)
    expect = set()
    for i in range(1, k_nodes):
        d = np.hypot(*(want[:i] - want[i]).T)
        near = np.argsort(d, kind="stable")[:ompl_planning.K_NEIGHBOURS]
        free = clutter.segments_free_by_tree(want[near], np.repeat(want[i][None], len(near), 0))
        expect |= {(int(j), i) for j in near[free]}
    assert {tuple(e) for e in rm.edges.tolist()} == expect
    assert rm.info["neighbours"] == ompl_planning.K_NEIGHBOURS
    assert rm.n_edges <= ompl_planning.K_NEIGHBOURS * k_nodes
    # the same seed gives the same roadmap, another seed another
    again = ompl_planning.build_ompl_prm(clutter, cluster(3), k_nodes, np.random.default_rng(4))
    other = ompl_planning.build_ompl_prm(clutter, cluster(3), k_nodes, np.random.default_rng(5))
    assert np.array_equal(again.edges, rm.edges) and not np.array_equal(other.pos, rm.pos)


def test_rrt_grows_a_tree_of_the_budget_with_steps_of_range(clutter):
    rm = ompl_planning.build_ompl_rrt(clutter, np.array([12.0, 12.0]), 80, 10.0,
                                      np.random.default_rng(0))
    assert rm.n_nodes == 80 and rm.n_edges == 79 and rm.components == 1
    lengths = rm.edge_length
    assert lengths.max() <= 10.0 + 1e-6
    assert clutter.segments_free_by_tree(rm.pos[rm.edges[:, 0]], rm.pos[rm.edges[:, 1]]).all()


@pytest.mark.parametrize("task", ["coverage", "search"])
def test_walkers_on_ompls_roadmap_replay_cleanly(clutter, task):
    goal = np.array(clutter.goal) if task == "search" else None
    run = run_roadmap(clutter, cluster(3), task=task, planner="ompl-prm", nodes=150, step=10,
                      sensor_range=20, goal=goal, seed=3)
    rec = build_record(run, {"task": task, "starts": cluster(3).tolist()}, 3, 0.0).to_dict()
    assert rec["algorithm"] == "ompl-prm" and rec["roadmap"]["kind"] == "ompl-prm"
    assert run.step_budget == 2 * 150  # the project's PRM budget
    assert replay_problems(rec, clutter) == []
    if task == "coverage":  # PRM walkers never know they are done
        assert not rec["complete"] and rec["metrics"]["budget_exhausted"]
        assert rec["metrics"]["coverage"] > 0.9
    else:
        assert rec["metrics"]["goal_found"] and rec["complete"]


def test_missing_ompl_is_one_line_naming_the_extra(monkeypatch, capsys):
    from swarmex.cli import main

    monkeypatch.setitem(sys.modules, "ompl", None)  # import ompl now raises ImportError
    monkeypatch.setitem(sys.modules, "ompl.base", None)
    code = main(["roadmap", "--env", "examples/roadmap_fig8.json", "--planner", "ompl-prm",
                 "--agents", "2", "--nodes", "40", "--step", "20", "--sensor-range", "25"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "swarmex[ompl]" in err[0] and "--planner ompl-prm" in err[0]
    with pytest.raises(InputError, match=r"swarmex\[ompl\]"):
        ompl_planning.ompl_modules()
