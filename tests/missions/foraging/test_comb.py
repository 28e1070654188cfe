"""Comb (issue 17.3): one block of robots, zero-cost staircase turns, every cell once."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.foraging.comb import passes
from swarmex.missions.foraging.patterns import ALGORITHMS, build_plan
from swarmex.missions.foraging.timed import timed_plan


def mean_discovery(name: str, g: int, n: int) -> float:
    pos = timed_plan(name, g, n).pos
    first = np.full((g, g), -1, dtype=np.int64)
    for t in range(len(pos) - 1, -1, -1):
        first[pos[t, :, 0], pos[t, :, 1]] = t
    first[g // 2, g // 2] = -1
    return float(first[first >= 0].mean())


def test_registered():
    assert "comb" in ALGORITHMS


@pytest.mark.parametrize(("g", "n"), [(16, 8), (24, 4), (30, 2), (8, 4)])
def test_unsupported_sizes_are_input_errors(g, n):
    with pytest.raises(InputError, match="comb needs the grid size"):
        build_plan("comb", g, n)


@pytest.mark.parametrize(("g", "n"), [(16, 4), (32, 8), (64, 16), (24, 2)])
def test_every_cell_once_apart_from_levelling_steps(g, n):
    # after the deployment the routes tile the grid; the only repeated cells are the
    # back-and-forth steps that level the comb where it runs straight into the other half
    p = build_plan("comb", g, n)
    owner: dict[tuple[int, int], int] = {}
    for a, route in enumerate(p.routes):
        explore = route[p.explore_from[a] :]
        for k, c in enumerate(explore):
            if c in owner:
                assert owner[c] == a, f"{c} explored by robots {owner[c]} and {a}"
                assert k >= 2 and (explore[k - 2] == c or explore[k - 1] == explore[k - 3]), c
            owner[c] = a
    assert len(owner) == g * g


def test_staircase_turn_shears_by_four_rounds_per_row_and_the_next_levels_it():
    # pass 0 goes West, turns up (staircase) into pass 1 going East, which turns up again into
    # pass 2: on the middle column of pass 1 the robots pass 4 rounds apart per row from the
    # next band's edge, on pass 2 all together (an independent reading of the timetable)
    g, n = 64, 8
    T = timed_plan("comb", g, n)
    ps = passes(g, n)
    assert [d for *_, d in ps[:3]] == [-1, 1, -1]

    def times(j: int) -> list[int]:
        band, first, last, _ = ps[j]
        mid = (first + last) // 2
        out = []
        for a in range(n):
            hit = np.where((T.pos[:, a, 0] == mid) & (T.pos[:, a, 1] // n == band))[0]
            out.append(int(hit.min()))
        return out

    t1 = sorted(times(1))
    assert np.diff(t1).tolist() == [4] * (n - 1)
    assert len(set(times(2))) == 1


@pytest.mark.parametrize(("g", "n"), [(64, 4), (64, 8), (96, 8), (128, 16)])
def test_explores_faster_on_average_than_strips_and_loop_strips(g, n):
    # with at least two bands per half-grid (g ≥ 8n); with one, the levelling costs more
    ours = mean_discovery("comb", g, n)
    assert ours < mean_discovery("strips", g, n)
    assert ours < mean_discovery("loop-strips", g, n)
    # within the levelling of the ideal T_dep + (g² − 1)/(2n)
    T = timed_plan("comb", g, n)
    assert ours <= T.t_sync + (g * g - 1) / (2 * n) + 4 * n


def test_neighbours_are_the_adjacent_rows():
    p = build_plan("comb", 32, 8)
    rows = p.notes["rows"]
    for a, nb in enumerate(p.neighbours):
        assert sorted(nb) == sorted(b for b in range(8) if abs(rows[b] - rows[a]) == 1)
