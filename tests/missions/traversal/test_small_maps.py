"""Tiny maps where an agent can run out of vacant steps: the online policies must still finish.

The map below (instance 30 of bench/gap_traversal_optimal.py, a 6-cell 3x4 grid) once made
MADGTA and nearest-vacant raise ``ValueError: high <= 0`` inside ``policies._pick`` (branch 3
found no step). The check is independent of the simulator's own ``complete`` flag: the
vertices that got a job are read from the agents' paths and compared with the free cells,
counted by hand from the map.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.traversal import run_traversal
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.worlds.grid import GridWorld

MAP = [[1, 0, 1],
       [1, 1, 1],
       [1, 0, 0],
       [0, 0, 0]]
# row-major vertex ids of the free cells (all one 4-connected component)
FREE = {r * 3 + c for r, row in enumerate(MAP) for c, v in enumerate(row) if v}


@pytest.mark.parametrize("nests", [(2, 6, 0), (2, 0)])
@pytest.mark.parametrize("algorithm", ["madgta", "nearest"])
def test_the_six_cell_map_is_traversed_without_a_crash(nests, algorithm):
    world = GridWorld(np.array(MAP, dtype=bool))
    assert {0, 2, 3, 4, 5, 6} == FREE
    for seed in range(20):
        run = run_traversal(world, [AgentSpec(nest=n) for n in nests], algorithm, seed=seed)
        jobs = {v for a in run.agents for v, job in a.path if job}
        assert jobs == FREE, (seed, sorted(jobs))
        visited = {v for a in run.agents for v, _ in a.path}
        assert visited <= FREE  # never on an obstacle
        assert run.complete
