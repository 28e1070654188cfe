"""Every cell is explored by every pattern for every supported n (small grids)."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.foraging.timed import timed_plan

CASES = [
    ("strips", 16, (1, 2, 4, 8, 16)),
    ("strips", 15, (1, 3, 5)),
    ("zigzag", 16, (1, 4, 16)),
    ("zigzag", 24, (4, 16)),
    ("hilbert", 16, (4, 16)),
    ("sectors", 16, (4, 8, 16)),
    ("sectors", 21, (8, 16)),
    ("spiral", 16, (1, 2, 4, 8, 16)),
    ("spiral", 17, (4, 8)),
    ("modified-zigzag", 16, (8,)),
    ("rings", 16, (4, 8, 16)),
    ("loop-strips", 16, (1, 2, 4, 8)),
    ("loop-strips", 30, (3, 5)),
    ("sector-loop", 16, (8,)),
    ("sector-loop", 32, (8, 16)),
    ("sector-loop", 48, (8, 16)),
    ("comb", 16, (1, 2, 4)),
    ("comb", 32, (1, 2, 4, 8)),
    ("comb", 24, (2, 3, 6)),
]


@pytest.mark.parametrize(("name", "g", "ns"), CASES)
def test_every_cell_is_explored(name, g, ns):
    for n in ns:
        T = timed_plan(name, g, n)
        seen = np.zeros((g, g), dtype=bool)
        seen[T.pos[:, :, 0].ravel(), T.pos[:, :, 1].ravel()] = True
        assert seen.all(), f"{name} n={n} g={g} misses {np.argwhere(~seen)[:5].tolist()}"


def test_exploration_regions_of_the_regular_patterns_do_not_overlap():
    # Strips, ZigZag, Hilbert and Modified ZigZag tile the grid: no cell explored twice
    cases = [("strips", 16, 4), ("zigzag", 16, 16), ("hilbert", 32, 4), ("loop-strips", 32, 8)]
    for name, g, n in cases:
        T = timed_plan(name, g, n)
        p = T.plan
        cells = [c for a, r in enumerate(p.routes) for c in r[p.explore_from[a] :]]
        assert len(cells) == len(set(cells)) == g * g
