"""The resolved reading of seed 004's coverage, step and node count (docs/roadmap.md).

* Coverage = free raster cells (centre free) whose centre some point of the agents' walk saw:
  within range R and with a free sight line. Checked against a brute-force raster built from
  the recorded trajectories with shapely alone (not the compiled sweep, not the planners'
  prepared union).
* A complete run walks every edge, so its coverage is the tree's: the reproduction's study
  (``complete_coverage``) relies on that.
* ε is the exact length of every grown edge; ``--nodes K`` counts accepted nodes; the other
  readings exist only as explicit options. ``--sensor-range 2eps`` means 2ε.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from swarmex.errors import InputError
from swarmex.missions.roadmap.scenario import make_scenario, parse_range
from swarmex.missions.roadmap.sim import run_roadmap
from swarmex.planning.rrt_wma import build_wma_rrt
from swarmex.studies.roadmap import design as rr
from swarmex.studies.roadmap.readings import complete_coverage

from .conftest import cluster


def brute_force_seen(world, raster, walks: list[np.ndarray],
                     rng_r: float) -> tuple[np.ndarray, np.ndarray]:
    """(free, seen) cell masks of ``raster``'s grid, by shapely: a cell is free when its centre
    is, and seen from a walk's viewpoints, at most one cell apart along each segment."""
    obstacles = shapely.union_all(list(world.obstacles))
    h = raster.h
    xs = raster.x0 + (np.arange(raster.nx) + 0.5) * h
    ys = raster.y0 + (np.arange(raster.ny) + 0.5) * h
    gx, gy = np.meshgrid(xs, ys)
    centres = np.column_stack([gx.ravel(), gy.ravel()])
    xmin, ymin, xmax, ymax = world.bounds
    inside = (centres[:, 0] > xmin) & (centres[:, 0] < xmax) & (centres[:, 1] > ymin) & (
        centres[:, 1] < ymax)
    free = inside & ~shapely.intersects(obstacles, shapely.points(centres))
    seen = np.zeros(len(centres), dtype=bool)
    for walk in walks:
        for a, b in zip(walk[:-1], walk[1:], strict=True):
            m = max(1, math.ceil(float(np.hypot(*(b - a))) / h))
            for s in range(m + 1):
                p = a + s / m * (b - a)
                idx = np.flatnonzero(free & ~seen & (np.hypot(*(centres - p).T) <= rng_r))
                if len(idx):
                    lines = shapely.linestrings(
                        np.stack([np.repeat(p[None], len(idx), 0), centres[idx]], axis=1))
                    seen[idx[~shapely.intersects(obstacles, lines)]] = True
    return free.reshape(raster.ny, raster.nx), seen.reshape(raster.ny, raster.nx)


@pytest.mark.parametrize("rng_r", [9.0, 30.0])
def test_coverage_is_what_the_agents_walk_saw(clutter, rng_r):
    run = run_roadmap(clutter, cluster(3), task="coverage", nodes=45, step=15.0,
                      sensor_range=rng_r, seed=4, raster_cells=64)
    assert run.complete  # every branch COMPLETE: the coverage of a finished behaviour
    walks = [np.asarray(tr)[:, 1:] for tr in run.trajectories]
    free, seen = brute_force_seen(clutter, run.raster, walks, rng_r)
    assert np.array_equal(run.raster.free, free)
    assert np.array_equal(run.raster.seen_mask(), seen)
    assert run.raster.coverage() == pytest.approx(seen.sum() / free.sum())
    assert 0.2 < run.raster.coverage() < 1.0  # a case where the range matters
    # the walk traversed every edge, so the tree's own sweep gives the same number
    assert complete_coverage(clutter, run.roadmap, rng_r, cells=64) == pytest.approx(
        run.raster.coverage())


def test_a_larger_step_helps_at_equal_nodes_not_at_equal_length(clutter):
    """The mechanism behind Table 1, on a small world: at a fixed range, coverage follows the
    tree's total length; at equal nodes the larger step wins only through its longer tree."""
    starts = cluster(3)

    def cov(nodes: int, step: float) -> float:
        return float(np.mean([complete_coverage(
            clutter, build_wma_rrt(clutter, starts, nodes, step, np.random.default_rng(s)),
            8.0, cells=64) for s in range(4)]))

    assert cov(40, 16.0) > cov(40, 8.0) + 0.05  # equal nodes: ε = 16 wins clearly
    assert abs(cov(40, 16.0) - cov(80, 8.0)) < 0.06  # equal length: about level
    assert cov(160, 8.0) > cov(40, 16.0) + 0.05  # 4× the nodes at ε/2 wins


def test_step_is_exact_and_nodes_count_accepted_nodes(clutter):
    rm = build_wma_rrt(clutter, cluster(3), 60, 12.0, np.random.default_rng(1))
    assert rm.n_nodes == 61 and rm.n_edges == 60  # K accepted nodes + the Main Root
    assert np.allclose(rm.edge_length[3:], 12.0)  # every grown edge is exactly ε
    assert np.all(rm.edge_length[:3] <= 12.0 + 1e-9)  # M → Secondary Roots: at most ε
    assert rm.samples >= 57

    # the other readings, options only: EXTEND stops at q_rand, N counts draws
    ext = build_wma_rrt(clutter, cluster(3), 200, 12.0, np.random.default_rng(1),
                        exact_step=False)
    assert ext.n_nodes == 201 and np.all(ext.edge_length <= 12.0 + 1e-9)
    assert (ext.edge_length[3:] < 12.0 - 1e-9).any()
    drawn = build_wma_rrt(clutter, cluster(3), 60, 12.0, np.random.default_rng(1),
                          count_samples=True)
    assert drawn.samples == 60 and drawn.n_nodes <= 1 + 3 + 60
    assert drawn.n_nodes < rm.n_nodes  # some samples were rejected (clutter)


def test_sensor_range_as_a_multiple_of_the_step(clutter):
    assert parse_range("2eps", 20.0) == 40.0
    assert parse_range("ε", 40.0) == 40.0
    assert parse_range("0.5*eps", 30.0) == 15.0
    assert parse_range("inf", 20.0) == math.inf and parse_range("25", 20.0) == 25.0
    for bad in ("0eps", "xeps", "-2ε"):
        with pytest.raises(InputError, match="multiple of ε"):
            parse_range(bad, 20.0)
    sc = make_scenario(clutter, agents=3, nodes=30, step=15.0, sensor_range="1.5eps")
    assert sc.sensor_range == pytest.approx(22.5)
    job = rr.Job("t1eps", "fig8", "coverage", "wma-rrt", 200, 40.0, "2r", 0)
    assert job.sensor_range == pytest.approx(2 * rr.C_EPS * 40.0)
    assert rr.Job("t1", "fig8", "coverage", "wma-rrt", 200, 40.0, "2r", 0).sensor_range == \
        pytest.approx(2 * rr.R_BASE)


def test_a_step_no_tree_can_take_in_this_world_is_refused():
    # every exact step of ε leaves the 640 × 480 world: growth gave up after 200 draws per
    # node with 2 of 100 nodes, and the run covered that stub and said "complete"
    import swarmex

    fig11 = "examples/roadmap_fig11.json"
    with pytest.raises(InputError, match=r"^step 700: the WMA-RRT grew 0 of the 98 nodes it"
                                         r" needed beyond the 2 roots .* 640 × 480 world"):
        swarmex.run("roadmap", env=fig11, agents=2, nodes=100, step=700, sensor_range="2eps")
    ok = swarmex.run("roadmap", env=fig11, agents=2, nodes=100, step=600, sensor_range="2eps")
    assert ok.metrics["tree_nodes"] == 101
