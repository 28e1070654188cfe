"""``nodes_traveled`` counts the nest only when the agent did its nest's job before moving.

docs/traversal.md, choice 10: "``nodes_traveled`` = edge moves + 1 if the agent did its own
nest's job". An agent whose first job comes after one move did not do its nest's job, and
its nest is not counted: a mutation run found this guarded only by the fingerprints.
"""

from __future__ import annotations

import numpy as np

from swarmex.missions.traversal import run_traversal, uniform_agents
from swarmex.missions.traversal.metrics import agent_metrics
from swarmex.worlds import GridWorld


def test_the_nest_counts_as_traveled_only_if_its_job_came_before_any_move():
    """Two agents share nest 0 of a 1 × 3 corridor (vertices 0, 1, 2). Agent 1 starts first
    and does the nest's job, then moves to 1 and 2 (taking 2's job, as agent 2 holds 1):
    2 moves + its nest = 3 vertices. Agent 2 finds the nest taken, moves to 1 and does that
    job: its first job follows one move, so no nest job, 1 vertex traveled."""
    world = GridWorld(np.ones((1, 3), dtype=bool))
    run = run_traversal(world, uniform_agents([0, 0], 1.0, 5.0), seed=0)
    first, second = run.agents
    assert first.path == [(0, True), (1, False), (2, True)]
    assert (first.moves, first.nest_job) == (2, True)
    assert agent_metrics(first, 1.0)["nodes_traveled"] == 3
    assert second.path == [(1, True)]
    assert (second.moves, second.nest_job) == (1, False)
    assert agent_metrics(second, 1.0)["nodes_traveled"] == 1
    assert agent_metrics(second, 1.0)["nodes_without_job"] == 0
