"""Recall (issue 17.3): the team chooses its pattern by replaying where food was found."""

from __future__ import annotations

import numpy as np
import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError
from swarmex.missions.foraging import recall
from swarmex.missions.foraging.grid import manhattan, nest_of
from swarmex.missions.foraging.sectors import sector_cells, to_grid
from swarmex.missions.foraging.timed import execute, timed_plan

G, N = 32, 8


def first_visits(pos: np.ndarray, g: int) -> np.ndarray:
    first = np.full((g, g), -1, dtype=np.int64)
    for t in range(len(pos) - 1, -1, -1):
        first[pos[t, :, 0], pos[t, :, 1]] = t
    return first


@pytest.mark.parametrize(("lo", "hi"), [(10, 14), (20, 24)])
def test_the_annulus_is_swept_first_then_the_smaller_side_and_every_cell_is_visited(lo, hi):
    first = first_visits(execute(recall.annulus_plan(G, N, lo, hi)).pos, G)
    nest = nest_of(G)
    assert (first >= 0).sum() == G * G  # food anywhere is found
    for a, cells in enumerate(sector_cells(G, N)):
        q = a // (N // 4)
        grid = [to_grid(nest, q, u, v) for u, v in cells]
        dist = [manhattan(c, nest) for c in grid]
        band = [first[c] for c, d in zip(grid, dist, strict=True) if lo <= d <= hi]
        # two cells off the annulus is never on a bridge between annulus cells
        inside = [first[c] for c, d in zip(grid, dist, strict=True) if d <= lo - 2]
        beyond = [first[c] for c, d in zip(grid, dist, strict=True) if d >= hi + 2]
        assert band and inside and beyond
        inside_n = sum(d < lo for d in dist)
        beyond_n = sum(d > hi for d in dist)
        if inside_n <= beyond_n:  # the smaller side next, then the other
            assert max(band) < min(beyond) and max(inside) < min(beyond), a
        else:
            assert max(band) < max(inside) and max(beyond) < max(inside), a
    sectors_first = first_visits(timed_plan("sectors", G, N).pos, G)
    ring = [(x, y) for x in range(G) for y in range(G) if lo <= manhattan((x, y), nest) <= hi]
    ring_e = np.mean([first[c] for c in ring])
    assert ring_e < 0.6 * np.mean([sectors_first[c] for c in ring])


def test_the_prediction_is_what_the_runs_give_and_the_choice_is_its_least():
    found = [(20, 28), (4, 10), (16, 30)]  # distances 16, 18, 14
    choice = recall.choose(G, N, found, 5, "relay-food", "seed")
    least = min(choice.predicted, key=choice.predicted.__getitem__)
    assert choice.pattern in (least, uniform_best(5))  # the least, or no significant gain
    assert "annulus 12-20" in choice.predicted  # 14 … 18 widened by (18 - 14) / 2
    name = choice.pattern
    timed = (
        execute(recall.annulus_plan(G, N, 12, 20))
        if name.startswith("annulus")
        else timed_plan(name, G, N)
    )

    def total(food):  # the chosen pattern's run, from the public API where it has a name
        if not name.startswith("annulus"):
            return swarmex.run("foraging", grid=G, agents=N, algorithm=name, food=food,
                               food_units=5).makespan  # fmt: skip
        from swarmex.missions.foraging.sim import run_mission

        return run_mission(timed, food, 5, "relay-food").makespan

    prior = recall.prior_of(G)
    assert sum(prior.share) == pytest.approx(1) and all(len(c) == 4 for c in prior.cells)
    uniform = sum(s * np.mean([total(c) for c in cells])
                  for s, cells in zip(prior.share, prior.cells, strict=True))  # fmt: skip
    rings = [recall.ring_cells(G, d) for d in (16, 18, 14)]
    remembered = np.mean([np.mean([total(c) for c in ring]) for ring in rings])
    assert choice.predicted[name] == pytest.approx((3 * remembered + uniform) / 4)


def uniform_best(units: int) -> str:
    """The pattern with the least mean total under uniform food, from the mission's runs on
    the prior's cells (each band's mean weighted by its cells)."""
    prior = recall.prior_of(G)

    def uniform(p):
        return sum(
            s * np.mean([swarmex.run("foraging", grid=G, agents=N, algorithm=p, food=c,
                                     food_units=units).makespan for c in cells])
            for s, cells in zip(prior.share, prior.cells, strict=True)
        )  # fmt: skip

    return min(recall.patterns_for(G, N), key=uniform)


def test_a_memory_that_looks_like_anywhere_keeps_the_pattern_for_anywhere():
    """Food found on uniformly drawn cells: Spiral has the least predicted total on these
    eight, but its gain over the pattern best for uniform food is not significant (2
    standard errors over the remembered distances), so the team keeps that pattern."""
    found = [(25, 24), (20, 5), (14, 30), (0, 23), (16, 14), (25, 19), (21, 10), (9, 4)]
    choice = recall.choose(G, N, found, 5, "relay-food", "seed")
    assert min(choice.predicted, key=choice.predicted.__getitem__) == "spiral"
    assert choice.pattern == uniform_best(5) != "spiral"
    # independently, from the runs: a gain, but within two standard errors
    nest = nest_of(G)
    ds = [manhattan(c, nest) for c in found]

    def rings(p):
        return np.array([np.mean([swarmex.run("foraging", grid=G, agents=N, algorithm=p, food=c,
                                              food_units=5).makespan
                                  for c in recall.ring_cells(G, d)]) for d in ds])  # fmt: skip

    gain = rings("spiral") - rings(choice.pattern)
    assert gain.mean() < 0 <= gain.mean() + 2 * gain.std(ddof=1) / np.sqrt(len(ds))


def test_a_remembered_distance_stands_for_its_whole_ring():
    nest = nest_of(G)
    for d in (1, 5, 16, 25, 31):
        cells = recall.ring_cells(G, d)
        everywhere = {(x, y) for x in range(G) for y in range(G) if manhattan((x, y), nest) == d}
        assert set(cells) <= everywhere and len(set(cells)) == min(8, len(everywhere))
    # spread round the ring: one cell in each octant around the nest for a ring inside the grid
    octants = {int((np.arctan2(nest[1] - y, x - nest[0]) % (2 * np.pi)) // (np.pi / 4))
               for x, y in recall.ring_cells(G, 12)}  # fmt: skip
    assert octants == set(range(8))
    assert recall.annulus_range(G, [20]) is None
    assert recall.annulus_range(G, [20, 30]) == (10, 32)  # widened by 10, kept to g


def test_without_memory_the_choice_has_the_least_worst_regret_over_the_bands():
    choice = recall.choose(G, N, (), 5, "relay-food", "seed")
    assert set(choice.predicted) == set(recall.patterns_for(G, N))  # no annulus: nothing known
    assert choice == recall.choose(G, N, [], 5, "relay-food", "seed")  # every robot agrees
    # brute force over the candidates, from the mission's runs
    prior = recall.prior_of(G)
    means = {
        p: [np.mean([swarmex.run("foraging", grid=G, agents=N, algorithm=p, food=c,
                                 food_units=5).makespan for c in cells]) for cells in prior.cells]
        for p in recall.patterns_for(G, N)
    }  # fmt: skip
    best = [min(m[b] for m in means.values()) for b in range(len(prior.cells))]
    regret = {p: max(v / b for v, b in zip(m, best, strict=True)) for p, m in means.items()}
    assert choice.pattern == min(regret, key=regret.__getitem__)
    assert choice.predicted[choice.pattern] == pytest.approx(min(regret.values()))


def test_a_memory_of_near_food_pays_off_on_near_food():
    """Food kept turning up near the nest: recall then sweeps from the nest, takes less than
    half Strips' time, and is within 10 % of the best thesis pattern there (4 trips: noise)."""
    nest = nest_of(G)
    rng = np.random.default_rng(5)
    near = [(x, y) for x in range(G) for y in range(G) if 1 <= manhattan((x, y), nest) <= 6]
    trips = [near[int(i)] for i in rng.choice(len(near), size=8, replace=False)]
    seeds = ("strips", "sectors", "spiral")
    mine, theirs = [], {p: [] for p in seeds}
    for i in range(4, 8):
        rec = swarmex.run("foraging", grid=G, agents=N, algorithm="recall", food=trips[i],
                          found=trips[:i], food_units=20)  # fmt: skip
        mine.append(rec.makespan)
        assert rec.extra["pattern"].split()[0] in ("annulus", "sectors", "spiral", "rings")
        for p in seeds:
            theirs[p].append(swarmex.run("foraging", grid=G, agents=N, algorithm=p,
                                         food=trips[i], food_units=20).makespan)  # fmt: skip
    assert np.mean(mine) < 0.5 * np.mean(theirs["strips"])
    assert np.mean(mine) <= 1.1 * min(np.mean(v) for v in theirs.values())


def test_the_record_names_the_memory_and_the_pattern_played():
    rec = swarmex.run("foraging", grid=G, agents=N, algorithm="recall", food=(3, 3),
                      found=[(2, 4), (28, 30)], food_units=3)  # fmt: skip
    assert rec.params["found"] == [[2, 4], [28, 30]]
    chosen = recall.choose(G, N, [(2, 4), (28, 30)], 3, "relay-food", "seed").pattern
    assert rec.extra["pattern"] == chosen
    # independently: the run is the chosen pattern's own run, robot for robot
    own = swarmex.run("foraging", grid=G, agents=N, algorithm=chosen, food=(3, 3), food_units=3)
    assert rec.makespan == own.makespan and rec.metrics == own.metrics
    assert [a.trajectory for a in rec.agents] == [a.trajectory for a in own.agents]
    plain = swarmex.run("foraging", grid=G, agents=N, algorithm="strips", food=(3, 3),
                        food_units=3)  # fmt: skip
    assert "found" not in plain.params and "pattern" not in plain.extra


def test_found_with_another_pattern_is_noted_and_changes_nothing():
    with pytest.warns(UserWarning, match="found is ignored: only recall reads"):
        noted = swarmex.run("foraging", grid=G, agents=N, algorithm="strips", food=(3, 3),
                            found=[(1, 1)])
    plain = swarmex.run("foraging", grid=G, agents=N, algorithm="strips", food=(3, 3))
    assert noted.makespan == plain.makespan and noted.agents == plain.agents


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"algorithm": "strips", "found": [(40, 1)]}, "outside the 32×32 grid"),
        ({"algorithm": "recall", "found": [(40, 1)]}, "outside the 32×32 grid"),
        ({"algorithm": "recall", "found": [(16, 16)]}, "is the nest"),
    ],
)
def test_bad_memories_are_input_errors(kwargs, needle):
    with pytest.raises(InputError, match=needle):
        swarmex.run("foraging", grid=G, agents=N, food=(3, 3), **kwargs)


def test_the_cli_takes_a_memory_and_refuses_a_bad_one(capsys):
    argv = ["forage", "--grid", "16", "--agents", "4", "--algorithm", "recall",
            "--food-units", "2"]  # fmt: skip
    assert main([*argv, "--found", "3,4;12,12"]) == 0
    chosen = recall.choose(16, 4, [(3, 4), (12, 12)], 2, "relay-food", "seed").pattern
    assert f"recall ({chosen})" in capsys.readouterr().out.replace("\n", "")  # what it played
    assert main([*argv, "--found", "3,4;99,1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--found 99,1 is outside" in err[0]


def test_recall_is_not_a_plan():
    from swarmex.missions.foraging.patterns import build_plan

    with pytest.raises(InputError, match="chooses its pattern per run"):
        build_plan("recall", G, N)


def test_a_pattern_beaten_by_another_in_every_band_is_not_replayed():
    g, n, k = 64, 16, 20
    choice = recall.choose(g, n, [], k, "relay-food", "seed")
    prior = recall.prior_of(g)
    means = {
        p: [np.mean([swarmex.run("foraging", grid=g, agents=n, algorithm=p, food=c,
                                 food_units=k).makespan for c in cells]) for cells in prior.cells]
        for p in recall.patterns_for(g, n)
    }  # fmt: skip
    dominated = {
        p for p in means
        if any(all(b <= 0.9 * a for a, b in zip(means[p], means[q], strict=True)) for q in means)
    }  # fmt: skip
    assert dominated  # the rule drops something here
    assert set(choice.predicted) == set(means) - dominated


def test_the_progress_callback_counts_every_replay_up_to_its_total():
    calls = []
    found = [(20, 28), (4, 10), (16, 30)]
    recall.choose(G, N, found, 4, "relay-food", "seed", on_replay=lambda *a: calls.append(a))
    done = [d for d, _ in calls]
    assert done == list(range(1, len(calls) + 1))
    cands = recall.candidates(G, N, [16, 18, 14])
    prior = sum(len(c) for c in recall.prior_of(G).cells)
    memory = sum(len(recall.ring_cells(G, d)) for d in (16, 18, 14))
    assert calls[0][1] == len(cands) * (prior + memory)  # before any candidate is dropped
    assert calls[-1][0] == calls[-1][1] == len(calls)


def test_a_recall_record_reruns_to_itself(tmp_path, capsys):
    out = tmp_path / "rec.json"
    argv = ["forage", "--grid", "32", "--agents", "8", "--algorithm", "recall",
            "--found", "3,4;20,20;28,2", "--food-units", "3", "--json", str(out)]  # fmt: skip
    assert main(argv) == 0
    assert main(["rerun", str(out)]) == 0
    assert "the same record" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("g", "n", "lo", "hi"),
    [(16, 4, 1, 32), (17, 8, 5, 5), (24, 16, 1, 3), (24, 8, 20, 24), (40, 24, 7, 30)],
)
def test_every_annulus_visits_every_cell(g, n, lo, hi):
    """Whatever the range (the whole grid, one distance, the corners only), food anywhere is
    found: the timetable visits every cell, and each route is a walk from the nest."""
    plan = recall.annulus_plan(g, n, lo, hi)
    plan.validate()
    assert (first_visits(execute(plan).pos, g) >= 0).all()


def test_an_annulus_with_equal_sides_sweeps_the_inner_side_first():
    """"The side with fewer cells first"; with as many cells inside ``lo`` as beyond ``hi``
    (sectors 2, 4, 5 and 7 of a 32 x 32 grid with 8 robots, annulus 12-20), the inner side,
    nearer the nest, comes first (module docstring: food just inside the range's lower end
    is what waited when the far side came first)."""
    lo, hi = 12, 20
    pos = execute(recall.annulus_plan(G, N, lo, hi)).pos
    nest = nest_of(G)
    tied = []
    for a, cells in enumerate(sector_cells(G, N)):
        first = first_visits(pos[:, a : a + 1], G)  # robot a's own route through sector a
        q = a // (N // 4)
        grid = [to_grid(nest, q, u, v) for u, v in cells]
        dist = [manhattan(c, nest) for c in grid]
        if sum(d < lo for d in dist) != sum(d > hi for d in dist):
            continue
        tied.append(a)
        band = [first[c] for c, d in zip(grid, dist, strict=True) if lo <= d <= hi]
        inside = [first[c] for c, d in zip(grid, dist, strict=True) if d <= lo - 2]
        beyond = [first[c] for c, d in zip(grid, dist, strict=True) if d >= hi + 2]
        assert max(band) < min(beyond) and max(inside) < min(beyond), a
    assert tied == [2, 4, 5, 7]


def test_the_annulus_range_is_rounded_outward_at_both_ends():
    """(max - min) / (m - 1) widening, "rounded outward": distances 10, 13, 15 widen by
    5 / 2 = 2.5 to [7.5, 17.5], so the range is 7 .. 18; kept to 1 .. g."""
    assert recall.annulus_range(G, [10, 13, 15]) == (7, 18)
    assert recall.annulus_range(G, [15, 13, 10]) == (7, 18)  # order does not matter
    assert recall.annulus_range(G, [2, 3]) == (1, 4)  # 1 - 1 = 0: kept to 1


def test_an_annulus_holding_exactly_half_the_cells_is_a_candidate():
    """"At most MAX_SHARE of the cells inside it": on a 9 x 9 grid the remembered distances
    2 and 3 widen to 1 .. 4, which holds 4 + 8 + 12 + 16 = 40 of the 80 non-nest cells
    (counted here by brute force), exactly half: still a candidate."""
    g, nest = 9, nest_of(9)
    cells = [(x, y) for x in range(g) for y in range(g) if 1 <= manhattan((x, y), nest) <= 4]
    assert len(cells) == 40 == (g * g - 1) // 2 and recall.MAX_SHARE == 0.5
    assert recall.annulus_range(g, [2, 3]) == (1, 4)
    assert recall.share_within(g, 1, 4) == 0.5
    assert recall.candidates(g, 8, [2, 3])[-1] == ("annulus", 1, 4)


def test_the_share_within_a_range_counts_non_nest_cells_only():
    """``share_within``: "the share of the non-nest cells at a distance lo .. hi" (brute
    force on a 9 x 9 grid): a range starting at 0 does not count the nest."""
    g, nest = 9, nest_of(9)
    dist = [manhattan((x, y), nest) for x in range(g) for y in range(g)]
    for lo, hi in ((0, 2), (1, 2), (0, 16)):
        brute = sum(lo <= d <= hi and d > 0 for d in dist) / (g * g - 1)
        assert recall.share_within(g, lo, hi) == pytest.approx(brute)
    assert recall.share_within(g, 0, 16) == 1.0
