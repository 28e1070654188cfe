"""Exact traversal orders on small grids, hand-derived from the thesis's algorithms/tables."""

from __future__ import annotations

from fractions import Fraction

import pytest

from swarmex.missions.foraging.grid import walk
from swarmex.missions.foraging.hilbert import hilbert_moves, hilbert_route
from swarmex.missions.foraging.modified_zigzag import ring
from swarmex.missions.foraging.patterns import build_plan
from swarmex.missions.foraging.sectors import sector_cells, slopes, to_frame
from swarmex.missions.foraging.zigzag import zigzag_route


def test_strips_g8_n2_deployment_and_sweep():
    # Alg. 2–4 on 8×8, nest (4,4): strip = 4; first robot out takes the farther Start-Cell
    # (0,3) (bottom corner of strip 0), the second (0,4) (top corner of strip 1).
    p = build_plan("strips", 8, 2)
    r0, r1 = p.routes
    assert r0[:13] == [
        (4, 4), (3, 4), (2, 4), (1, 4), (0, 4),  # West to the border
        (0, 3),  # along the border to the Start-Cell
        (0, 2), (0, 1), (0, 0),  # North(strip - 1)
        (1, 0),  # East(1)
        (1, 1), (1, 2), (1, 3),  # South(strip - 1)
    ]  # fmt: skip
    assert r1[4:12] == [(0, 4), (0, 5), (0, 6), (0, 7), (1, 7), (1, 6), (1, 5), (1, 4)]
    assert p.depart == [1, 2]
    assert p.explore_from == [5, 4]
    assert p.neighbours == [[1], [0]]


def test_zigzag_table1_code1_rings():
    # Direction(1) for code 1: E − N1 − W1 − N − E2 − S2, then Direction(3) starts E − N3 …
    start = (0, 10)
    moves = [("E", 1), ("N", 1), ("W", 1), ("N", 1), ("E", 2), ("S", 2), ("E", 1), ("N", 3)]
    assert zigzag_route(start, 1, 4)[:12] == [start, *walk(start, moves)][:12]
    r = zigzag_route(start, 1, 4)
    assert len(r) == 16 and len(set(r)) == 16  # a 4×4 block, each cell once


def test_zigzag_n4_start_block_and_codes():
    p = build_plan("zigzag", 8, 4)
    starts = [r[p.explore_from[a]] for a, r in enumerate(p.routes)]
    assert starts == [(3, 3), (4, 3), (3, 4), (4, 4)]  # NW, NE, SW, SE around the nest (4,4)
    # NE robot (code 1): E, N, W, N, E, E, S, S …
    assert p.routes[1][1:9] == [(4, 3), (5, 3), (5, 2), (4, 2), (4, 1), (5, 1), (6, 1), (6, 2)]


def test_hilbert_examples_from_the_thesis():
    assert hilbert_moves(3, 1) == ["St", "S", "E", "N"]  # "3(St) gives St − S − E − N"
    # Alg. 8–10 by hand for code 3, order 2: sub-codes [7, 3, 3, 2]
    assert hilbert_moves(3, 2) == (
        ["St", "E", "S", "W", "S", "S", "E", "N", "E", "S", "E", "N", "N", "W", "N", "E"]
    )
    assert hilbert_route((0, 0), 3, 4) == [
        (0, 0), (1, 0), (1, 1), (0, 1), (0, 2), (0, 3), (1, 3), (1, 2),
        (2, 2), (2, 3), (3, 3), (3, 2), (3, 1), (2, 1), (2, 0), (3, 0),
    ]  # fmt: skip


def test_hilbert_every_code_is_hamiltonian():
    for code in range(1, 9):
        for size in (2, 4, 8, 16):
            r = hilbert_route((100, 100), code, size)
            xs = {x for x, _ in r}
            ys = {y for _, y in r}
            assert len(set(r)) == size * size == len(r)
            assert len(xs) == size and len(ys) == size


def test_sectors_emission_order_matches_the_thesis_example():
    # §3.4.3: 8 robots in a quadrant leave as A7 → A3 → A5 → A1 → A6 → A2 → A4 → A0
    p = build_plan("sectors", 128, 32)
    order = sorted(range(8), key=lambda a: p.depart[a])
    assert order == [7, 3, 5, 1, 6, 2, 4, 0]
    # Alg. 11: Start-Cells are the sectors' nearest cells; lower half sorted by u
    starts = {a: to_frame(p.nest, p.routes[a][p.explore_from[a]])[1:] for a in range(8)}
    assert starts[0] == (1, 0)
    assert starts[3][0] > starts[1][0] > starts[2][0] >= starts[0][0]


@pytest.mark.parametrize(("g", "n"), [(9, 8), (16, 8), (17, 16), (31, 24), (64, 64), (65, 40)])
def test_sector_cells_match_the_division_cell_by_cell(g, n):
    # §3.4: cell (u, v) of a quadrant lies in the last sector whose lower slope v/u reaches
    # (exact fractions here, one cell at a time); each sector lists its cells row by row
    nest = (g // 2, g // 2)
    lows = slopes(n // 4)
    expected: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for y in range(g):
        for x in range(g):
            if (x, y) != nest:
                q, u, v = to_frame(nest, (x, y))
                s = max(i for i, lo in enumerate(lows) if Fraction(v, u) >= lo)
                expected[q * (n // 4) + s].append((u, v))
    assert sector_cells(g, n) == expected


def test_sectors_n8_first_levels():
    # n = 8: the NE quadrant's lower sector [0°, 45°) is swept column by column (East),
    # starting at its nearest cell (1, 0) in the frame, i.e. the cell East of the nest.
    p = build_plan("sectors", 16, 8)
    r = p.routes[0]
    assert r[: p.explore_from[0] + 1] == [(8, 8), (9, 8)]
    frame = [to_frame(p.nest, c)[1:] for c in r[1:12]]
    # column u=3 holds v = 0..2; the sweep ended column 2 at v=1 (a tie between the ends),
    # so it bridges East to (3,1), sweeps down to (3,0) and up to (3,2): one cell twice
    assert frame == [
        (1, 0), (2, 0), (2, 1), (3, 1), (3, 0), (3, 1), (3, 2), (4, 2), (4, 3), (4, 2), (4, 1)
    ]  # fmt: skip


def test_modified_zigzag_inner_ring_order_table4():
    # inner code for NE (Table 4, code 4): N − E1 − S1 − E − N2 − W2 from the inner corner
    cells = [c for r in range(3) for c in ring(r, outward_odd=True)]
    assert cells[:9] == [(0, 0), (0, 1), (1, 1), (1, 0), (2, 0), (2, 1), (2, 2), (1, 2), (0, 2)]
    p = build_plan("modified-zigzag", 16, 8)
    ne_inner = p.routes[4]
    start = ne_inner[p.explore_from[4]]
    assert start == (8, 7)  # inner corner of the NE quadrant, next to the nest (8, 8)
    assert ne_inner[p.explore_from[4] : p.explore_from[4] + 4] == [(8, 7), (8, 6), (9, 6), (9, 7)]
    ne_outer = p.routes[0]
    # outer code 3: from the border corner on the nest's row, North along the border
    assert ne_outer[p.explore_from[0] : p.explore_from[0] + 3] == [(15, 7), (15, 6), (15, 5)]


def test_spiral_arms_partition_the_grid():
    for n in (1, 2, 4, 8, 16):
        p = build_plan("spiral", 32, n)
        assert p.depart == [1] * n
        assert len(p.neighbours) == n


def test_loop_strips_g8_n2():
    # strip 0 = rows 0..3. Deploy up the column next to the nest to the middle of the strip,
    # sweep the upper half (rows 0-1) West, the lower half (rows 2-3) East across the grid,
    # the upper half back West to the nest's column: every cell once.
    p = build_plan("loop-strips", 8, 2)
    a = p.notes["strip_of"].index(0)
    r = p.routes[a]
    assert r[: p.explore_from[a] + 1] == [(4, 4), (3, 4), (3, 3), (3, 2), (3, 1)]
    assert r[p.explore_from[a] :] == [
        (3, 1), (3, 0), (2, 0), (2, 1), (1, 1), (1, 0), (0, 0), (0, 1),  # upper half, West
        (0, 2), (0, 3), (1, 3), (1, 2), (2, 2), (2, 3), (3, 3), (3, 2),  # lower half, East
        (4, 2), (4, 3), (5, 3), (5, 2), (6, 2), (6, 3), (7, 3), (7, 2),
        (7, 1), (7, 0), (6, 0), (6, 1), (5, 1), (5, 0), (4, 0), (4, 1),  # upper half, back
    ]  # fmt: skip
    assert p.depart == [1, 2]
