"""bench/exploration_bound.py: the makespan lower bound is exact on a corridor and below
every real run on small worlds (issue 17 item 2)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from swarmex.missions.exploration.mission import build_world
from swarmex.missions.exploration.params import default_starts
from swarmex.missions.exploration.sim import run_exploration
from swarmex.missions.registry import get
from swarmex.sensing.laser import Laser

BENCH = Path(__file__).resolve().parents[3] / "bench" / "exploration_bound.py"


def _bound_module():
    spec = importlib.util.spec_from_file_location("exploration_bound", BENCH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


eb = _bound_module()


def _corridor(length: int) -> np.ndarray:
    free = np.zeros((3, length + 2), dtype=bool)
    free[1, 1:-1] = True
    return free


@pytest.mark.parametrize(("start", "sight", "best"), [(1, 24, 24), (16, 10, 28)])
def test_corridor_bound_is_the_best_walk(start, sight, best):
    # a 1-cell corridor of 30 free cells (x = 1..30), laser 5 cells: a beam along the
    # corridor enters the k-th cell ahead at k - 0.5 < 5, so a robot sees 5 cells ahead.
    # From x = 1 the far end x = 30 is first seen from x = 25: 24 steps. From x = 16 either
    # end is seen after 9 or 10 steps (sight bound 10), but one robot must see both: to
    # x = 25 (9 steps), then back to x = 6 (19): 28, the pair bound, and the optimum
    free = _corridor(30)
    laser = Laser(5.0, 360, 1.0)
    b = eb.bound_for(free, ((start, 1),), laser.angles, laser.range_cells)
    assert b.cells == 30
    assert b.sight == sight
    assert b.steps == best


def test_corridor_sweep_gains_one_cell_per_step():
    free = np.zeros((3, 32), dtype=bool)
    free[1, 1:-1] = True
    free[0, 0] = True  # not a rectangle any more: Δ is searched over the map's moves
    laser = Laser(5.0, 360, 1.0)
    steps, cells, gain = eb.sweep_bound(free, ((1, 1),), laser.angles, laser.range_cells)
    assert (cells, gain) == (30, 1)
    assert steps == 30 - 6  # the start sees itself and 5 cells ahead


@pytest.mark.parametrize(
    ("world", "robots", "laser", "comm", "strategy"),
    [
        ({"empty": (3.0, 3.0), "cell": 0.1}, 3, 0.6, 3.0, "greedy-exclusion"),
        ({"empty": (3.0, 3.0), "cell": 0.1}, 2, 0.6, 1.0, "greedy"),
        ({"empty": (4.0, 2.0), "cell": 0.1}, 4, 0.5, 1.0, "hungarian-exclusion"),
    ],
)
def test_bound_is_below_real_runs(world, robots, laser, comm, strategy):
    m = get("exploration")
    for seed in range(3):
        params = m.params(**world, robots=robots, laser_range=laser, comm_range=comm,
                          strategy=strategy, seed=seed)
        grid = build_world(params)
        run = run_exploration(grid, params)
        assert run.complete and run.explored_fraction() == 1.0
        las = Laser(params.laser_range, params.beams, grid.cell)
        starts = default_starts(grid, params.robots, params.robot_radius)
        b = eb.bound_for(grid.free, tuple(starts), las.angles, las.range_cells)
        assert 0 < b.steps <= run.makespan, (b, run.makespan)
