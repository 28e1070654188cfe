"""Seed 000 §3.2.4: the 5×5 worked example must come out exactly as printed."""

from __future__ import annotations

import pytest

from swarmex.missions.traversal import run_traversal, uniform_agents

from .thesis_grid import node_to_tid, thesis_grid, tid_to_node

PRINTED = [
    "1-1*-2-2*-7-7*-6-6*-7-8-8*-9-9*-4-4*",
    "11-11*-12-12*-17-17*-16-16*-21-21*-22-22*-23-18-18*",
    "23-23*-24-24*-25-25*-20-20*-15-15*-10-10*-5-5*",
]


def example_run(seed: int):
    world = thesis_grid(5, 5, obstacles=(3, 13, 14, 19))
    nests = [tid_to_node(k, 5, 5) for k in (1, 11, 23)]
    run = run_traversal(world, uniform_agents(nests, travel_time=2.0, job_time=9.0), seed=seed)
    return run, run.path_strings(lambda v: str(node_to_tid(v, 5, 5)))


def test_printed_paths_for_a_tie_break_seed():
    # Seed 2 draws 12 over 16 at blue's step 2 and 23 over 17 at its step 7.
    _, paths = example_run(2)
    assert paths == PRINTED


@pytest.mark.parametrize("seed", range(30))
def test_every_seed_completes_with_each_job_once(seed):
    run, _ = example_run(seed)
    assert run.complete
    # independent check: 21 free vertices, each job started exactly once
    assert int(run.reachable.sum()) == 21
    assert (run.job_count[run.reachable] == 1).all()
    assert (run.job_count[~run.reachable] == 0).all()
    # replay: each consecutive trajectory pair is an edge of the grid between free cells
    world = run.world
    for agent in run.agents:
        nodes = [v for _, v in agent.trajectory]
        for u, v in zip(nodes, nodes[1:], strict=False):
            assert v in set(world.graph.neighbors(u).tolist())
            assert not world.blocked[v]


def test_the_example_is_found_in_a_fraction_of_seeds():
    hits = [s for s in range(40) if example_run(s)[1] == PRINTED]
    # two independent fair binary draws decide the printed run: about a quarter of seeds
    assert 4 <= len(hits) <= 20
