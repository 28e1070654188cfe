"""``madgta-r`` (swarmex.missions.traversal.rollout): rollout over MADGTA.

What is pinned: it is registered and completes missions (identical and mixed teams, perfect
and lossy channels); before the end game it *is* MADGTA (same records); the compiled
simulation predicts a mission it can see whole; the same belief gives the same decision and
the policy never writes the belief; compiled and interpreted kernels agree; and it lowers
the makespan where the docs say it does (an open grid with 16 agents).
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.comm.channel import Channel
from swarmex.missions.traversal import (
    make_policy,
    run_metrics,
    run_traversal,
    uniform_agents,
)
from swarmex.missions.traversal.policies import POLICIES, Madgta
from swarmex.missions.traversal.rollout import MadgtaR
from swarmex.missions.traversal.rollout_sim import ABSENT, FREE, NEAR, _fill_rows, _simulate
from swarmex.worlds import random_obstacles

from ._helpers import corridor, mixed_agents
from .checking import checking, jit_and_python_agree


def _all_done(run) -> None:
    assert run.complete
    assert np.all(run.job_count[run.reachable] >= 1)


def test_registered_and_selectable():
    assert POLICIES["madgta-r"] is MadgtaR
    policy = make_policy("madgta-r")
    assert isinstance(policy, MadgtaR) and isinstance(policy, Madgta)
    assert policy.name == "madgta-r" and policy.madgta_branch2
    assert not MadgtaR(far=2).madgta_branch2  # distant targets compete with neighbours
    for bad in (dict(k=0), dict(objective="sum"), dict(far=-1), dict(horizon=0),
                dict(outside="nearest"), dict(unknown="wall")):
        with pytest.raises(ValueError):
            MadgtaR(**bad)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("fleet", ["same", "mixed"])
def test_completes_every_job_once(seed, fleet):
    world = random_obstacles(12, 12, 0.2, seed=seed)
    if fleet == "same":
        free = np.nonzero(~world.blocked)[0]
        agents = uniform_agents([int(v) for v in free[:5]], 2.0, 9.0)
    else:
        agents = mixed_agents(world, 5, seed)
    policy = MadgtaR()
    run = run_traversal(world, agents, policy, seed=seed)
    _all_done(run)
    assert run_metrics(run, 1.0)[0]["duplicate_jobs"] == 0
    assert policy.rollouts > 0


@pytest.mark.parametrize("options", [dict(), dict(far=2, ties=2, samples=2),
                                     dict(objective="mix", horizon=30, outside="madgta+"),
                                     dict(objective="lex", tol=0.5, unknown="walled"),
                                     dict(objective="makespan"), dict(nest=True)])
def test_completes_over_a_lossy_range_limited_channel(options):
    world = random_obstacles(10, 10, 0.2, seed=3)
    agents = mixed_agents(world, 4, 3)
    run = run_traversal(world, agents, MadgtaR(**options), seed=3,
                        channel=Channel(loss=0.3, range=4.0))
    assert run.complete


def test_before_the_end_game_it_is_madgta_record_for_record():
    """With max_vacant=0 no decision is rolled out: the same paths and metrics as MADGTA's
    (the same draws from the generator, too, or the paths would part)."""
    world = random_obstacles(14, 14, 0.2, seed=7)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 6, 2.0, 9.0)
    ours = run_traversal(world, agents, MadgtaR(max_vacant=0), seed=7)
    theirs = run_traversal(world, agents, "madgta", seed=7)
    assert ours.path_strings() == theirs.path_strings()
    assert run_metrics(ours, 1.0)[0] == run_metrics(theirs, 1.0)[0]


def test_the_simulation_predicts_a_mission_it_sees_whole():
    """A corridor 0-1-2-3-4 (2 s per edge, 9 s per job); agent 1 at 0, deciding at t = 0,
    takes candidate 1; agent 2 works at 4 until t = 5. By hand: agent 1 reaches 1 at 2, works
    to 11; agent 2 moves to 3 (7), works to 16; agent 1 moves to 2 (13), works to 22; then
    nothing is left. Makespan 22, sum 22 + 11."""
    g = corridor(5)
    n = 5
    blocked = np.zeros(n, dtype=bool)
    status = np.zeros(n, dtype=np.int32)
    status[0] = 1  # agent 1's nest job done
    status[4] = 2  # agent 2 working at 4 until t = 5
    reserved = np.zeros(n, dtype=np.int32)
    vacant = np.array([1, 2, 3], dtype=np.int64)
    table = np.empty((3, n), dtype=np.int32)
    row_of = np.full(n, -1, dtype=np.int64)
    row_of[vacant] = np.arange(3)
    _fill_rows(g.indptr, g.indices, blocked, vacant, row_of[vacant], table,
               np.empty(n, dtype=np.int32))
    assert table[row_of[1]].tolist() == [1, 0, 1, 2, 3]
    loc = np.array([-1, 0, 4])
    mode = np.array([ABSENT, FREE, 2])  # agent 2 WORKING
    tfree = np.array([0.0, 0.0, 5.0])
    tpu = np.array([0.0, 2.0, 2.0])
    jt = np.array([0.0, 9.0, 9.0])
    mk, total = _simulate(
        1, 1, NEAR, 0.0, 10**6, g.indptr, g.indices, blocked, status, reserved, vacant,
        table, row_of, loc, loc.copy(), tfree, mode, np.full(3, -1), np.full(3, -1), tpu, jt,
        1.0, np.arange(n, dtype=np.int64),
    )
    assert mk == pytest.approx(22.0)
    assert total == pytest.approx((2 + 9 + 2 + 9) + (2 + 9))


def test_never_writes_the_belief_and_is_deterministic():
    world = random_obstacles(10, 10, 0.2, seed=5)
    spy = checking(MadgtaR, 60)
    run = run_traversal(world, mixed_agents(world, 4, 5), spy, seed=5)
    assert run.complete and spy.checked > 20 and spy.rollouts > 0


def test_compiled_and_interpreted_give_the_same_run(tmp_path):
    code = """
    import json
    import numpy as np
    from swarmex.missions.traversal import run_traversal, run_metrics, uniform_agents
    from swarmex.missions.traversal.rollout import MadgtaR
    from swarmex.worlds import random_obstacles
    world = random_obstacles(9, 9, 0.2, seed=2)
    free = np.nonzero(~world.blocked)[0]
    run = run_traversal(world, uniform_agents([int(free[0])] * 4, 2.0, 9.0),
                        MadgtaR(far=2), seed=2)
    print(json.dumps([run.path_strings(), run_metrics(run, 1.0)[0]["max_total_time"]]))
    """
    jit_and_python_agree(code, tmp_path)


def test_lower_makespan_than_madgta_on_an_open_grid_with_16_agents():
    """docs/traversal-variants.md §4: on empty-16-16 with 16 agents the rollout cuts MADGTA's
    makespan by about 5 %; here on a generated open 16x16 grid, three seeds."""
    world = random_obstacles(16, 16, 0.0, seed=0)
    ratios = []
    for seed in range(3):
        rng = np.random.default_rng(seed)
        nests = [int(v) for v in rng.choice(world.graph.n_nodes, 16, replace=False)]
        agents = uniform_agents(nests, 2.0, 9.0)
        ours = run_metrics(run_traversal(world, agents, "madgta-r", seed=seed), 1.0)[0]
        base = run_metrics(run_traversal(world, agents, "madgta", seed=seed), 1.0)[0]
        ratios.append(ours["max_total_time"] / base["max_total_time"])
    assert np.mean(ratios) < 0.99, ratios


def test_cells_walled_in_by_known_walls_are_not_counted_as_vacant():
    """A free cell inside a ring of known walls (or an unknown one behind them) can never be
    reached: it must not count towards ``max_vacant`` nor enter the simulation."""
    from swarmex.missions.traversal.belief import TraversalBelief
    from swarmex.planning.fieldcache import KnownGraph

    world = random_obstacles(7, 7, 0.0, seed=0)
    ring = [y * 7 + x for y in range(3, 6) for x in range(3, 6) if (x, y) != (4, 4)]
    known = KnownGraph(world.graph)
    belief = TraversalBelief(1, 1, known, np.array([0.0, 2.0]), np.array([0.0, 9.0]))
    belief.loc[1] = 0
    belief.see_obstacles(ring)
    vacant = MadgtaR._vacant(belief)
    assert 4 * 7 + 4 not in vacant.tolist()
    assert vacant.size == 49 - len(ring) - 1


def test_lex_keeps_a_near_best_makespan_and_takes_the_least_sum():
    """objective='lex': among the candidates whose simulated makespan is within ``tol`` of the
    best, the least simulated sum; with ``tol=0`` the same choices as 'makespan' (ties by
    the sum)."""
    world = random_obstacles(8, 8, 0.15, seed=5)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 3, 2.0, 9.0)
    lex0 = run_traversal(world, agents, MadgtaR(objective="lex", tol=0.0), seed=5)
    mk = run_traversal(world, agents, MadgtaR(objective="makespan"), seed=5)
    assert lex0.path_strings() == mk.path_strings()
    policy = MadgtaR(objective="lex")
    run = run_traversal(world, agents, policy, seed=5)
    _all_done(run)
    assert policy.rollouts > 0


def test_walled_world_guesses_only_unsensed_cells_next_to_known_walls():
    """unknown='walled': the simulated world adds as walls the unsensed cells next to a known
    wall; sensed cells and candidates never become walls."""
    world = random_obstacles(10, 10, 0.25, seed=2)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 3, 2.0, 9.0)
    seen: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    policy = MadgtaR(unknown="walled")
    original = policy._walled_world

    def spy(belief, cands, vacant):
        worlds = original(belief, cands, vacant)
        for blocked, *_ in worlds:
            seen.append((blocked & ~belief.known.blocked, policy._sensed(belief), cands))
        return worlds

    policy._walled_world = spy  # type: ignore[method-assign]
    run = run_traversal(world, agents, policy, seed=2)
    _all_done(run)
    assert seen
    for added, sensed, cands in seen:
        assert not (added & sensed).any()
        assert not added[cands].any()


def test_nested_rollout_completes_and_is_deterministic():
    """nest=True: rivals roll out their first simulated decision; every job is done once and
    the same seed gives the same run."""
    world = random_obstacles(6, 6, 0.15, seed=4)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 3, 2.0, 9.0)
    runs = [run_traversal(world, agents, MadgtaR(nest=True), seed=4) for _ in range(2)]
    _all_done(runs[0])
    assert run_metrics(runs[0], 1.0)[0]["duplicate_jobs"] == 0
    assert runs[0].path_strings() == runs[1].path_strings()
