"""The compiled timetable (fastloop.timetable_rounds) equals the Python loop of
timed.execute, the rule as written, for every pattern: same positions every round, the same
end, synchronisation round and Start-Cell arrivals."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.foraging import timed
from swarmex.missions.foraging.patterns import build_plan

CASES = [(alg, g, n) for alg in ("strips", "sectors", "spiral", "comb")
         for g, n in ((16, 4), (32, 8), (64, 16))]
CASES += [("strips", 48, 8), ("sectors", 50, 8), ("spiral", 45, 16)]
CASES += [(alg, g, n) for alg in ("zigzag", "hilbert") for g, n in ((16, 4), (32, 16), (64, 4))]
CASES += [("sector-loop", 32, 8), ("sector-loop", 64, 16)]


@pytest.mark.parametrize(("algorithm", "g", "n"), CASES)
def test_compiled_timetable_equals_the_python_loop(algorithm, g, n):
    plan = build_plan(algorithm, g, n)
    ref = timed.execute(plan, compiled=False)
    got = timed.execute(plan)
    assert (got.t_end, got.t_sync) == (ref.t_end, ref.t_sync)
    assert got.pos.dtype == ref.pos.dtype and got.pos.shape == ref.pos.shape
    assert np.array_equal(got.pos, ref.pos)
    assert np.array_equal(got.explore_start, ref.explore_start)


@pytest.mark.parametrize(("name", "n"), [("strips", 4), ("sectors", 8), ("spiral", 4)])
def test_first_visits_is_each_cells_first_round_in_the_timetable(name, n):
    """``Timed.first_visits`` (the exact mean exploration time's source) against a plain
    walk through the timetable."""
    table = timed.timed_plan(name, 32, n)
    first: dict[tuple[int, int], int] = {}
    for t, row in enumerate(table.pos):
        for x, y in row:
            first.setdefault((int(x), int(y)), t)
    del first[table.plan.nest]
    expect = np.full((32, 32), -1)
    for (x, y), t in first.items():
        expect[x, y] = t
    assert np.array_equal(table.first_visits(), expect)
