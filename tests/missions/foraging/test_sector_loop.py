"""Sector Loop (issue 17.3): Sectors' timing near the nest, Loop Strips' lockstep far away."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.foraging import sector_loop
from swarmex.missions.foraging.grid import nest_of
from swarmex.missions.foraging.patterns import ALGORITHMS, build_plan
from swarmex.missions.foraging.timed import execute, timed_plan


def first_visit(pos: np.ndarray, g: int) -> np.ndarray:
    """Round at which each cell is first occupied (``first[x, y]``), from a timetable."""
    first = np.full((g, g), -1, dtype=np.int64)
    for t in range(len(pos) - 1, -1, -1):
        first[pos[t, :, 0], pos[t, :, 1]] = t
    return first


def distance(g: int) -> np.ndarray:
    nx, ny = nest_of(g)
    xs, ys = np.meshgrid(np.arange(g), np.arange(g), indexing="ij")
    return np.abs(xs - nx) + np.abs(ys - ny)


def test_registered_after_the_thesis_patterns():
    assert "sector-loop" in ALGORITHMS
    assert ALGORITHMS.index("sector-loop") > ALGORITHMS.index("modified-zigzag")


@pytest.mark.parametrize(("g", "n"), [(8, 4), (16, 12), (30, 8), (36, 8), (40, 16), (14, 8)])
def test_unsupported_team_sizes_are_input_errors(g, n):
    with pytest.raises(InputError, match="sector-loop supports"):
        build_plan("sector-loop", g, n)


@pytest.mark.parametrize(("g", "n"), [(40, 8), (48, 16)])
def test_near_cells_are_found_no_later_than_by_sectors(g, n):
    # phase A is Sectors' own order restricted to the diamond, so inside it the cells are
    # reached as early as Sectors reaches them (checked against Sectors' timetable): the
    # shortest-path bridges over the cut level ends may differ by a step, never more
    ours = first_visit(timed_plan("sector-loop", g, n).pos, g)
    theirs = first_visit(timed_plan("sectors", g, n).pos, g)
    near = (distance(g) < sector_loop.switch_radius(g, n)) & (distance(g) > 0)
    assert near.sum() > 0
    assert (ours[near] <= theirs[near] + 1).all()
    assert ours[near].mean() < theirs[near].mean()


@pytest.mark.parametrize(("g", "n"), [(32, 8), (64, 16), (96, 16)])
def test_far_phase_is_in_lockstep(g, n):
    # from the round the last robot enters its strip, all robots stand in the same column, or
    # the next one (the grid's parity can leave a robot one round off), until the sweep ends:
    # Loop Strips' property that keeps the communication short (strips of even height; with
    # odd heights the mirrored halves differ in size, as in Loop Strips)
    T = timed_plan("sector-loop", g, n)
    p = T.plan
    h = p.notes["strip"]
    enter = [p.depart[a] - 1 + k for a, k in enumerate(p.notes["far_from"])]
    assert max(enter) - min(enter) <= 1  # the early ones waited (one round: grid parity)
    start = max(enter)
    xs = T.pos[start + 1 : T.t_end - 1, :, 0]
    assert (xs.max(axis=1) - xs.min(axis=1) <= 1).all()
    assert T.t_end - start == g * h - 1  # one strip per robot, every cell once, no delay


def test_neighbours_are_adjacent_sectors_and_strips_both_ways():
    p = build_plan("sector-loop", 64, 16)
    strip_of = p.notes["strip_of"]
    for a, nb in enumerate(p.neighbours):
        assert len(set(nb)) == len(nb) <= 4 and a not in nb
        assert {(a - 1) % 16, (a + 1) % 16} <= set(nb)  # Sectors' ring
        for b in range(16):
            if abs(strip_of[b] - strip_of[a]) == 1:
                assert b in nb
        for b in nb:
            assert a in p.neighbours[b]


@pytest.mark.parametrize("radius", [0, 2, 40])
def test_any_switch_radius_covers_every_cell(radius):
    # R = 0: every robot only deploys to its sector's Start-Cell before its strip (Loop
    # Strips with Sectors' deployment); R ≥ g: all of Sectors' sweep comes first
    g, n = 24, 8
    p = sector_loop.plan(g, n, radius=radius)
    assert p.notes["radius"] == radius
    T = execute(p)
    assert (first_visit(T.pos, g) >= 0).all()
