"""Whole runs: completion for every strategy, blacklisting, trajectory replay, determinism."""

from __future__ import annotations

import json

import numpy as np
import pytest

from swarmex.engine.record import write_record
from swarmex.missions.exploration import STRATEGIES, ExplorationParams, run_exploration
from swarmex.missions.exploration.record import exploration_record
from swarmex.worlds.grid import GridWorld
from swarmex.worlds.metric import MetricGrid, empty_metric


def two_rooms(door_cells: int) -> MetricGrid:
    """3 × 4 m at 5 cm: two rooms split by a wall with one door, and a pillar in each room."""
    free = np.zeros((60, 80), dtype=bool)
    free[1:-1, 1:-1] = True
    free[1:-1, 40] = False
    free[25 : 25 + door_cells, 40] = True
    free[10:16, 15:22] = False
    free[40:48, 60:64] = False
    return MetricGrid(GridWorld(free, source=f"two rooms, door {door_cells}"), 0.05)


def replay(run) -> None:
    """Every recorded move is to an adjacent, truly free cell, without corner cutting."""
    free = run.grid.free
    for tr in run.trajectories:
        assert free[tr[0][2], tr[0][1]]
        for (t0, x0, y0), (t1, x1, y1) in zip(tr, tr[1:], strict=False):
            assert t1 > t0
            assert max(abs(x1 - x0), abs(y1 - y0)) == 1
            assert free[y1, x1]
            if x1 != x0 and y1 != y0:
                assert free[y0, x1] and free[y1, x0]


@pytest.mark.parametrize("strategy", sorted(STRATEGIES))
def test_every_strategy_completes_small_maps(strategy):
    for grid, n in ((empty_metric(3, 3), 3), (two_rooms(door_cells=12), 2)):
        run = run_exploration(grid, ExplorationParams(
            robots=n, laser_range=1.0, comm_range=2.0, strategy=strategy, seed=1))
        assert run.complete, (strategy, grid.world.source)
        assert run.explored_fraction() >= 0.99, (strategy, run.explored_fraction())
        replay(run)


def test_frontier_behind_a_gap_narrower_than_the_robot_is_blacklisted():
    grid = two_rooms(door_cells=3)  # 15 cm gap, robot 20 cm wide
    run = run_exploration(grid, ExplorationParams(
        robots=1, laser_range=1.0, comm_range=2.0, starts=((30, 28),), seed=0))
    assert run.complete and run.makespan < 2000  # no endless loop towards the gap
    r = run.robots[0]
    assert r.stats.blacklisted_regions >= 1  # the room seen through the gap
    left = np.zeros(grid.shape, bool)
    left[:, :40] = True
    mine = r.belief.grid.logodds < 0
    assert (mine & left & run.reachable).sum() >= 0.99 * (left & run.reachable).sum()
    assert run.explored_fraction() < 0.9  # the far room stays (honestly) unexplored
    replay(run)


def test_out_of_range_robots_explore_alone():
    grid = empty_metric(4, 4)
    run = run_exploration(grid, ExplorationParams(
        robots=2, laser_range=1.0, comm_range=0.2, starts=((10, 10), (70, 70)), seed=0))
    assert run.complete and run.explored_fraction() >= 0.99
    # each robot mapped (nearly) everything itself: scans only travel within 20 cm
    for r in run.robots:
        assert ((r.belief.grid.logodds < 0) & run.reachable).sum() >= 0.97 * run.reachable.sum()


def test_same_seed_same_record(tmp_path):
    grid = two_rooms(door_cells=12)
    params = ExplorationParams(robots=3, laser_range=1.0, comm_range=1.5, seed=4)
    a = exploration_record(run_exploration(grid, params)).to_dict()
    b = exploration_record(run_exploration(grid, params)).to_dict()
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
    rec = exploration_record(run_exploration(grid, params))
    path = write_record(rec, tmp_path / "r.json")
    d = json.loads(path.read_text())
    assert d["mission"] == "exploration" and d["time_unit"] == "step"
    assert d["algorithm"] == "greedy-exclusion" and d["complete"] is True
    assert d["makespan"] == a["makespan"] and len(d["agents"]) == 3
    m = d["metrics"]
    for key in ("explored_fraction", "steps", "mean_steps", "replans", "messages_sent",
                "bytes_sent", "plan_intervals_avg"):
        assert key in m
    assert m["mean_steps"] == pytest.approx(np.mean(m["steps"]))
    assert all(len(p) == 3 for a_ in d["agents"] for p in a_["trajectory"])


def test_run_collects_garbage_less_often_and_restores_the_thresholds():
    import gc

    import swarmex
    from swarmex.engine.collector import GC_YOUNG

    before = gc.get_threshold()
    during = []
    swarmex.run("exploration", empty="3x3", robots=2, laser_range=0.8, max_ticks=5,
                on_frame=lambda frame: during.append(gc.get_threshold()))
    assert during and all(th[0] >= GC_YOUNG for th in during)
    assert gc.get_threshold() == before

