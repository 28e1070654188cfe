"""resolve.sidesteps, written out for speed, is the rule it replaced: the in-grid neighbours
in NEIGH order."""

from swarmex.missions.foraging.resolve import NEIGH, sidesteps


def test_sidesteps_are_the_in_grid_neighbours_in_neigh_order():
    for g in (1, 2, 3, 6):
        for x in range(g):
            for y in range(g):
                expect = [(x + dx, y + dy) for dx, dy in NEIGH
                          if 0 <= x + dx < g and 0 <= y + dy < g]  # fmt: skip
                assert sidesteps((x, y), g) == expect
