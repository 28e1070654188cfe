"""Small builders shared by the traversal policy tests."""

from __future__ import annotations

import numpy as np

from swarmex.missions.traversal import AgentSpec
from swarmex.worlds import GridWorld
from swarmex.worlds.nodegraph import NodeGraph


def mixed_agents(world: GridWorld, m: int, seed: int) -> list[AgentSpec]:
    """``m`` agents on distinct free cells of ``world``, each with its own speed (0.5-1 s per
    unit) and job time (5-10 s), drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    free = np.nonzero(~world.blocked)[0]
    return [AgentSpec(int(v), float(rng.uniform(0.5, 1.0)), float(rng.uniform(5, 10)))
            for v in rng.choice(free, m, replace=False)]


def corridor(n: int) -> NodeGraph:
    """The corridor 0-1-...-(n-1) with unit edges, along the x axis."""
    u = np.arange(n - 1)
    return NodeGraph.from_edges(n, u, u + 1, np.ones(n - 1), np.c_[np.arange(n), np.zeros(n)])
