"""The bounded planner search (issue 14 item 2) against the full distance field.

A nearest-candidate strategy's plan searches only up to its nearest candidate
(:func:`distance_until`) and finds reachable frontier cells from the map's 4-connected
pieces (:func:`labels4`); both must agree with :func:`distance_steps` wherever the plan
reads them, on random maps with walls, gaps and an untraversable start.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.exploration.paths import (
    distance_steps,
    distance_toward,
    distance_until,
    field_padded,
    labels4,
    padded,
    path_to,
    path_to_padded,
    reachable_pieces,
    steps_via_field,
)


def _maps() -> list[tuple[np.ndarray, int, int]]:
    out = []
    for seed in range(12):
        rng = np.random.default_rng(seed)
        h, w = int(rng.integers(5, 40)), int(rng.integers(5, 40))
        trav = rng.random((h, w)) > float(rng.uniform(0.1, 0.5))
        x, y = int(rng.integers(0, w)), int(rng.integers(0, h))
        if seed % 3 == 0:
            trav[y, x] = False  # a robot inside a freshly inflated zone still leaves it
        out.append((trav, x, y))
    return out


def _python_bfs(trav: np.ndarray, x: int, y: int) -> np.ndarray:
    """The rule written out: 8-connected steps, a diagonal only between two traversable
    cells, the start left even when it is not traversable; -1 unreachable."""
    h, w = trav.shape
    out = np.full((h, w), -1, dtype=np.int64)
    out[y, x] = 0
    frontier = [(x, y)]
    while frontier:
        nxt = []
        for cx, cy in frontier:
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    nx, ny = cx + dx, cy + dy
                    if (dx, dy) == (0, 0) or not (0 <= nx < w and 0 <= ny < h):
                        continue
                    if not trav[ny, nx] or out[ny, nx] >= 0:
                        continue
                    if dx and dy and not (trav[cy, nx] and trav[ny, cx]):
                        continue
                    out[ny, nx] = out[cy, cx] + 1
                    nxt.append((nx, ny))
        frontier = nxt
    return out


@pytest.mark.parametrize("case", range(12))
def test_full_field_is_the_rule_written_out(case):
    """The reference the bounded searches below are checked against (they share its
    kernel) is itself checked against a plain Python breadth-first search."""
    trav, x, y = _maps()[case]
    assert np.array_equal(distance_steps(trav, x, y), _python_bfs(trav, x, y))


@pytest.mark.parametrize("case", range(12))
def test_reachable_pieces_are_what_the_search_reaches(case):
    trav, x, y = _maps()[case]
    full = distance_steps(trav, x, y)
    lab = labels4(trav)
    pieces = reachable_pieces(trav, lab, x, y)
    reached = trav & np.isin(lab, pieces)
    expect = (full >= 0) & trav
    assert np.array_equal(reached, expect)


@pytest.mark.parametrize("case", range(12))
def test_bounded_search_is_exact_up_to_the_nearest_stop_cell(case):
    trav, x, y = _maps()[case]
    full = distance_steps(trav, x, y)
    rng = np.random.default_rng(100 + case)
    ys, xs = np.nonzero((full > 0) & trav)
    if ys.size == 0:
        pytest.skip("nothing reachable")
    pick = rng.choice(ys.size, size=min(ys.size, 4), replace=False)
    sx, sy = xs[pick], ys[pick]
    tp = padded(trav)
    dist_p = distance_until(tp, x, y, sx, sy)
    dist = dist_p[1:-1, 1:-1]
    near = int(full[sy, sx].min())
    within = (full >= 0) & (full <= near)
    assert np.array_equal(dist[within], full[within])
    other = ~within
    assert np.all((dist[other] == -1) | (dist[other] == full[other]))
    for gx, gy in zip(sx, sy, strict=True):
        if full[gy, gx] == near:
            a = path_to(full, trav, int(gx), int(gy), x, y)
            b = path_to_padded(dist_p, tp, int(gx), int(gy), x, y)
            assert np.array_equal(a, b)


@pytest.mark.parametrize("case", range(12))
def test_fields_from_candidates_give_the_same_steps_and_path(case):
    """Few candidates: steps read from fields taken at the candidates, and a search along
    the shortest paths to the goal only, give the full field's steps and path."""
    trav, x, y = _maps()[case]
    full = distance_steps(trav, x, y)
    ys, xs = np.nonzero((full > 0) & trav)
    if ys.size == 0:
        pytest.skip("nothing reachable")
    tp = padded(trav)
    rng = np.random.default_rng(200 + case)
    for i in rng.choice(ys.size, size=min(ys.size, 5), replace=False):
        gx, gy = int(xs[i]), int(ys[i])
        f = field_padded(tp, gx, gy)
        steps = steps_via_field(tp, f, x, y)
        assert steps == full[gy, gx]
        toward = distance_toward(tp, x, y, f, steps)
        a = path_to(full, trav, gx, gy, x, y)
        b = path_to_padded(toward, tp, gx, gy, x, y)
        assert np.array_equal(a, b)


def test_sharers_counts_the_grids_in_one_state():
    """Fields from candidates are cached on a map state only when at least as many robots
    share it (``OccupancyGrid.sharers``): grids of a pool that merged the same local maps
    are one state, a grid with another map is its own."""
    from swarmex.sensing.occupancy import GridPool, LocalMap, OccupancyGrid

    pool = GridPool()
    grids = [OccupancyGrid((8, 8), pool) for _ in range(3)]
    local = LocalMap(0, 0, np.ones((2, 2), dtype=bool), np.zeros((2, 2), dtype=bool))
    other = LocalMap(4, 4, np.ones((2, 2), dtype=bool), np.zeros((2, 2), dtype=bool))
    for g in grids:
        g.apply(local)
    grids[2].apply(other)
    for g in grids:  # grids merge lazily: a state counts the grids that reached it
        g.logodds  # noqa: B018
    assert [g.sharers for g in grids] == [2, 2, 1]
    assert OccupancyGrid((8, 8)).sharers == 1
