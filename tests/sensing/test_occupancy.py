"""The log-odds Bayesian update on hand-computed values, and local maps on the wire."""

from __future__ import annotations

import msgpack
import numpy as np
import pytest

from swarmex.sensing.occupancy import (
    L_HIT,
    L_MISS,
    P_MAX,
    P_MIN,
    LocalMap,
    OccupancyGrid,
)


def local(free_cells=(), occ_cells=(), shape=(3, 3), x0=0, y0=0) -> LocalMap:
    f = np.zeros(shape, dtype=bool)
    o = np.zeros(shape, dtype=bool)
    for y, x in free_cells:
        f[y, x] = True
    for y, x in occ_cells:
        o[y, x] = True
    return LocalMap(x0, y0, f, o)


def bayes(p: float, s: float) -> float:
    """The thesis's rule: p' = η · p · s, η normalising over {occupied, free}."""
    return p * s / (p * s + (1 - p) * (1 - s))


def test_hand_computed_probabilities():
    g = OccupancyGrid((3, 3))
    assert (g.probability() == 0.5).all() and g.unknown().all()
    lm = local(free_cells=[(0, 0)], occ_cells=[(1, 1)])
    g.apply(lm)
    p = g.probability()
    assert p[0, 0] == pytest.approx(0.4, abs=1e-6)
    assert p[1, 1] == pytest.approx(0.7, abs=1e-6)
    assert p[2, 2] == 0.5 and g.logodds[2, 2] == 0.0  # unseen stays exactly unknown
    g.apply(lm)
    p = g.probability()
    assert p[0, 0] == pytest.approx(0.16 / 0.52, abs=1e-6)  # 0.3077
    assert p[1, 1] == pytest.approx(0.49 / 0.58, abs=1e-6)  # 0.8448
    assert p[0, 0] == pytest.approx(bayes(bayes(0.5, 0.4), 0.4), abs=1e-6)
    assert g.free()[0, 0] and g.occupied()[1, 1] and g.unknown()[2, 2]


def test_clamping_lets_a_cell_change_its_mind():
    g = OccupancyGrid((1, 1))
    hit = local(occ_cells=[(0, 0)], shape=(1, 1))
    miss = local(free_cells=[(0, 0)], shape=(1, 1))
    for _ in range(50):
        g.apply(hit)
    assert g.probability()[0, 0] == pytest.approx(P_MAX, abs=1e-6)
    for _ in range(3):
        g.apply(miss)
    # from the clamp 0.97, three misses: log-odds 3.476 - 3 * 0.405 = 2.26 -> p = 0.906
    want = P_MAX
    for _ in range(3):
        want = bayes(want, 0.4)
    assert g.probability()[0, 0] == pytest.approx(want, abs=1e-5)
    for _ in range(50):
        g.apply(miss)
    assert g.probability()[0, 0] == pytest.approx(P_MIN, abs=1e-6)


def test_a_local_map_updates_only_its_box():
    g = OccupancyGrid((5, 6))
    g.apply(local(free_cells=[(0, 0), (1, 2)], occ_cells=[(2, 2)], x0=3, y0=2))
    assert g.logodds[2, 3] == L_MISS and g.logodds[3, 5] == L_MISS and g.logodds[4, 5] == L_HIT
    assert int(g.known().sum()) == 3


def test_wire_round_trip_through_msgpack():
    rng = np.random.default_rng(0)
    f = rng.random((7, 13)) < 0.5
    o = ~f & (rng.random((7, 13)) < 0.3)
    lm = LocalMap(4, 9, f, o)
    back = LocalMap.from_wire(msgpack.unpackb(msgpack.packb(lm.to_wire())))
    assert (back.x0, back.y0) == (4, 9)
    assert (back.free == f).all() and (back.occ == o).all()


@pytest.mark.parametrize("pooled", [False, True])
def test_a_derived_value_follows_the_grid_with_or_without_a_pool(pooled):
    """``derived()`` is computed once per grid state: a grid without a pool (a library
    user's) must drop it when a scan is merged, as a pooled one moves to a new state."""
    from swarmex.sensing.occupancy import GridPool

    grid = OccupancyGrid((4, 4), GridPool() if pooled else None)

    def passed(lo):
        return int((lo < 0).sum())

    assert grid.derived("passed", passed) == 0
    grid.apply(local(free_cells=[(1, 1)], shape=(4, 4)))
    assert grid.derived("passed", passed) == int(grid.free().sum()) == 1


def test_a_cell_one_beam_hits_and_another_passes_is_hit():
    """Hits win over passes (the module's rule): two beams along nearly one line, one ending
    in a cell the other goes through. With the noise-free laser this never happens in a run,
    but ``rasterise`` is public and takes any ranges."""
    from swarmex.sensing.occupancy import rasterise

    short = rasterise(5, 5, np.array([3.0]), np.array([0.0]), 8.0, (12, 12))
    long = rasterise(5, 5, np.array([5.0]), np.array([1e-6]), 8.0, (12, 12))
    end = tuple(np.argwhere(short.occ)[0])  # the cell the short beam ends in ...
    assert long.free[end]  # ... which the long one passes
    both = rasterise(5, 5, np.array([3.0, 5.0]), np.array([0.0, 1e-6]), 8.0, (12, 12))
    assert both.occ[end] and not both.free[end]
    assert not (both.free & both.occ).any()
