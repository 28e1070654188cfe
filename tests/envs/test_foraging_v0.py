"""The foraging PettingZoo environment: PettingZoo's own checks, baseline == swarmex.run,
observations from what the robot knows, clear errors for bad actions, legal worlds under any
policy, SuperSuit vectorising. Tiny grids throughout (a run is tens of rounds)."""

from __future__ import annotations

import gc
import threading

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import (  # noqa: E402
    api_test,
    parallel_api_test,
    parallel_seed_test,
    seed_test,
)

import swarmex  # noqa: E402
from swarmex.envs import foraging_v0  # noqa: E402
from swarmex.missions.foraging import replay  # noqa: E402
from swarmex.missions.foraging.patterns import ALGORITHMS  # noqa: E402
from swarmex.missions.foraging.run import run_forage, to_record  # noqa: E402

from ._helpers import play, render_test_rgb_array, without_wall  # noqa: E402

SMALL = {"grid": 16, "agents": 4, "food": (12, 3), "food_units": 3}
TINY = {"grid": 8, "agents": 4, "algorithm": "sectors", "food_units": 2, "max_rounds": 60}

pytestmark = pytest.mark.filterwarnings(
    # PettingZoo's api_test recommends Box/Discrete observations; ours is a Dict with a mask
    "ignore:Observation is not a NumPy array",
    "ignore:Observation space for each agent probably should be",
)


def random_policy(rng):
    def policy(obs, infos):
        return {a: int(rng.choice(np.flatnonzero(o["action_mask"]))) for a, o in obs.items()}

    return policy


# ---------------------------------------------------------------- PettingZoo's checks


def test_api_test_aec():
    api_test(foraging_v0.env(**TINY), num_cycles=100)


def test_parallel_api_test():
    parallel_api_test(foraging_v0.parallel_env(**TINY), num_cycles=100)


def test_seed_test_aec():
    seed_test(lambda: foraging_v0.env(**TINY), num_cycles=50)


def test_parallel_seed_test():
    # parallel_seed_test samples actions without the mask: the opt-in projection mode turns
    # a move off the grid into "stay" (the default mode would raise on it)
    parallel_seed_test(
        lambda: foraging_v0.parallel_env(invalid_action="project", **TINY), num_cycles=50
    )


def test_render_test_rgb_array():
    render_test_rgb_array(foraging_v0.env, **TINY)


def test_render_is_the_foraging_renderer():
    env = foraging_v0.parallel_env(render_mode="rgb_array", algorithm="sectors", **SMALL)
    policy = foraging_v0.baseline_policy(env)
    obs, infos = env.reset()
    for _ in range(30):
        obs, *_, infos = env.step(policy(obs, infos))
    img = env.render()
    assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3
    assert img.shape[:2] == (400, 400)  # viz.foraging's 5-inch, 80-dpi animation frame
    env.close()
    with pytest.warns(UserWarning, match="render_mode"):
        assert foraging_v0.parallel_env(**SMALL, algorithm="sectors").render() is None


# ---------------------------------------------------------------- baseline == swarmex.run


@pytest.mark.parametrize(
    ("algorithm", "transport"),
    [("sectors", "relay-food"), ("strips", "end-to-end"), ("spiral", "relay-path"),
     ("zigzag", "relay-food"), ("hilbert", "end-to-end"), ("rings", "relay-path"),
     ("loop-strips", "relay-food"), ("sector-loop", "relay-food"),
     ("comb", "relay-path")],
)  # fmt: skip
def test_baseline_episode_is_the_run_record(algorithm, transport):
    params = {**SMALL, "algorithm": algorithm, "transport": transport}
    if algorithm == "sector-loop":  # a multiple of 8 robots
        params["agents"] = 8
    env = foraging_v0.parallel_env(**params)
    steps, rewards, terms, truncs = play(env, foraging_v0.baseline_policy(env))
    record = env.record()
    assert without_wall(record) == without_wall(swarmex.run("foraging", **params))
    assert record.complete and all(terms.values()) and not any(truncs.values())
    assert steps == record.makespan > 40  # one step per round, every round asked
    assert replay(record.to_dict()) == []


def test_baseline_modified_zigzag_with_a_drawn_food_cell_and_reset_seed():
    params = {"grid": 16, "agents": 8, "algorithm": "modified-zigzag", "food_distance": "40-80",
              "food_units": 4, "transport": "relay-path"}  # fmt: skip
    env = foraging_v0.parallel_env(**params)
    policy = foraging_v0.baseline_policy(env)
    env.reset(seed=2)
    obs, infos = env.reset(seed=5)  # a reset in the middle abandons the first run
    while env.agents:
        obs, *_, infos = env.step(policy(obs, infos))
    assert without_wall(env.record()) == without_wall(swarmex.run("foraging", seed=5, **params))


def test_baseline_through_the_aec_form():
    params = {**SMALL, "algorithm": "strips", "transport": "end-to-end"}
    aec = foraging_v0.env(**params)
    aec.reset(seed=1)
    base = aec.unwrapped
    for agent in aec.agent_iter():
        obs, reward, term, trunc, info = aec.last()
        if term or trunc:
            aec.step(None)
            continue
        aec.step(int(base.baseline_actions()[base.possible_agents.index(agent)]))
    expected = swarmex.run("foraging", seed=1, **params)
    assert without_wall(base.record()) == without_wall(expected)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
@pytest.mark.parametrize("transport", ["relay-food", "relay-path", "end-to-end"])
def test_the_hook_answering_the_seed_plays_the_same_run(algorithm, transport):
    """The decision hook (run_forage(decide=)) with the seed's answers is the run without it
    (the Python loop from round 0 == the timetable, this loop and the compiled tail)."""
    n = 8 if algorithm in ("modified-zigzag", "sector-loop") else 4
    for food in [(12, 3), (1, 14), (9, 8)]:
        args = (algorithm, 16, n, food, 5, transport)
        plain = to_record(run_forage(*args), 0, {}).to_dict()
        hooked = run_forage(*args, decide=lambda compute: compute.builtin)
        decided = to_record(hooked, 0, {}).to_dict()
        plain.pop("wall_seconds")
        decided.pop("wall_seconds")
        assert decided == plain


def test_return_is_deliveries_plus_bonus_minus_time():
    env = foraging_v0.parallel_env(algorithm="sectors", **SMALL)
    policy = foraging_v0.baseline_policy(env)
    obs, infos = env.reset()
    total, rounds = 0.0, 0
    while env.agents:
        obs, rewards, terms, truncs, infos = env.step(policy(obs, infos))
        assert len(set(rewards.values())) == 1  # a team reward
        total += rewards["robot_0"]
        rounds += 1
    rec = env.record()
    assert infos["robot_0"]["round"] == rec.makespan == rounds
    assert total == pytest.approx(3 + 10 - 0.01 * rec.makespan)


def test_max_rounds_truncates_with_the_missions_stopped_record():
    params = {**SMALL, "algorithm": "sectors"}
    env = foraging_v0.parallel_env(max_rounds=25, **params)
    steps, rewards, terms, truncs = play(env, foraging_v0.baseline_policy(env))
    assert steps == 25 and all(truncs.values()) and not any(terms.values())
    rec = env.record()
    assert not rec.complete and rec.makespan == 25

    def stop(frame):
        if frame.t >= 25:
            raise swarmex.StopRun

    assert without_wall(rec) == without_wall(swarmex.run("foraging", on_frame=stop, **params))


# ---------------------------------------------------------------- observations


def test_observation_is_what_the_robot_knows():
    env = foraging_v0.parallel_env(algorithm="sectors", **SMALL)
    policy = foraging_v0.baseline_policy(env)
    obs, infos = env.reset()
    m = env.unwrapped.mission
    seen_neighbour = told_someone = False
    modes = set()
    while env.agents:
        for i, a in enumerate(env.possible_agents):
            o = obs[a]
            assert env.observation_space(a).contains(o)
            x, y = m.pos[i]
            assert tuple(o["position"]) == (x, y) and tuple(o["nest"]) == (8, 8)
            assert o["round"][0] == m.t == infos[a]["round"]
            assert o["informed"][0] == m.informed[i] and o["carrying"][0] == m.carrying[i]
            assert tuple(o["food"]) == ((12, 3) if m.informed[i] else (-1, -1))
            for j in range(4):  # robots within distance 2 only, never itself
                d = abs(m.pos[j][0] - x) + abs(m.pos[j][1] - y)
                expect = m.pos[j] if j != i and d <= foraging_v0.SENSING else (-1, -1)
                assert tuple(o["team_positions"][j]) == expect
                seen_neighbour |= j != i and d <= 2
            told = np.flatnonzero(o["to_tell"]).tolist()
            assert told == (sorted(m.targets[i]) if m.mode[i] in (1, 2) else [])
            told_someone |= bool(told)
            modes.add(foraging_v0.MODES[o["mode"][0]])
            mask = o["action_mask"].astype(bool)
            assert mask[0] and mask[1] == (y > 0) and mask[2] == (x < 15)
            assert mask[3] == (y < 15) and mask[4] == (x > 0)
        obs, _, _, _, infos = env.step(policy(obs, infos))
    assert seen_neighbour and told_someone
    assert {"explore", "relay"} <= modes and modes & {"follow", "communicate"}


# ---------------------------------------------------------------- params and actions


def test_bad_params_are_the_runs_input_errors():
    for bad in (
        {"grid": 16, "agents": 4, "algorithm": "sector"},
        {"grid": 16, "agents": 4, "algorithm": "sectors", "food": (8, 8)},
        {"grid": 15, "agents": 4, "algorithm": "strips"},
        {"grid": 16, "agents": "four", "algorithm": "sectors"},
        {"grid": 16, "agent": 4, "algorithm": "sectors"},
        {"grid": 16, "agents": 4, "algorithm": "sectors", "food_units": 0},
    ):
        with pytest.raises(swarmex.InputError) as run_error:
            swarmex.run("foraging", **bad)
        with pytest.raises(swarmex.InputError) as env_error:
            foraging_v0.parallel_env(**bad)
        assert str(env_error.value) == str(run_error.value)
    good = {**SMALL, "algorithm": "sectors"}
    for extra, name in (
        ({"render_mode": "human"}, "render_mode"),
        ({"invalid_action": "ignore"}, "invalid_action"),
        ({"max_rounds": 0}, "max_rounds"),
        ({"max_rounds": 10**9}, "max_rounds"),
        ({"time_cost": "x"}, "time_cost"),
        ({"completion_bonus": float("nan")}, "completion_bonus"),
    ):
        with pytest.raises(swarmex.InputError, match=name):
            foraging_v0.parallel_env(**good, **extra)


def test_reset_refuses_a_bad_seed_clearly():
    """reset(seed=-1) used to fail deep in NumPy ("expected non-negative integer")."""
    env = foraging_v0.parallel_env(**SMALL, algorithm="sectors")
    for bad in (-1, 2.5, "3", True):
        with pytest.raises(swarmex.InputError, match="seed must be an integer >= 0"):
            env.reset(seed=bad)
    obs, _ = env.reset(seed=np.int64(4))
    assert set(obs) == set(env.possible_agents)


def test_bad_actions_raise_and_leave_the_world_as_it_was():
    params = {**SMALL, "algorithm": "sectors"}
    env = foraging_v0.parallel_env(**params)
    policy = foraging_v0.baseline_policy(env)
    obs, infos = env.reset()
    base = env.unwrapped
    good = policy(obs, infos)
    a = "robot_2"
    x, y = obs[a]["position"]  # every robot starts in the nest (8, 8): walk one to the border
    cases = [
        ({**good, a: 5}, "outside the action space"),
        ({**good, a: -1}, "outside the action space"),
        ({**good, a: 2.0}, "outside the action space"),
        ({**good, a: True}, "outside the action space"),
        ({**good, a: None}, "outside the action space"),
        ({k: v for k, v in good.items() if k != a}, f"no action for {a}"),
        ({**good, "robot_9": 0}, "unknown agent"),
    ]
    for actions, why in cases:
        with pytest.raises(ValueError, match=why):
            env.step(actions)
        assert base.round == 0  # the same round is still pending
    good[a] = np.int64(good[a])  # numpy integers are actions too
    obs, *_, infos = env.step(good)
    while env.agents:
        obs, *_, infos = env.step(policy(obs, infos))
    assert without_wall(env.record()) == without_wall(swarmex.run("foraging", **params))
    with pytest.raises(RuntimeError, match="ended"):
        env.step({"robot_0": 0})


def test_a_move_off_the_grid_raises_or_projects_to_stay():
    for mode in ("raise", "project"):
        env = foraging_v0.parallel_env(invalid_action=mode, grid=2, agents=1,
                                       algorithm="spiral", food=(0, 0), food_units=1)  # fmt: skip
        obs, _ = env.reset()
        assert tuple(obs["robot_0"]["position"]) == (1, 1)  # the nest of a 2×2 grid
        assert obs["robot_0"]["action_mask"].tolist() == [1, 1, 0, 0, 1]
        if mode == "raise":
            with pytest.raises(ValueError, match=r"robot_0 chose action 2 \(east\) at cell "
                               r"\(1, 1\) in round 0: cell \(2, 1\) is off the 2×2 grid"):
                env.step({"robot_0": 2})
            assert env.unwrapped.round == 0
        else:
            obs, *_ = env.step({"robot_0": 3})  # south: off the grid, so it stays
            assert tuple(obs["robot_0"]["position"]) == (1, 1)
            with pytest.raises(ValueError, match="outside the action space"):
                env.step({"robot_0": 7})
        env.close()


# ---------------------------------------------------------------- any policy, a legal world


@pytest.mark.parametrize("transport", ["relay-food", "relay-path", "end-to-end"])
def test_random_and_mixed_policies_keep_the_world_legal(transport):
    """Robots of any policy never share a non-nest cell, move one cell a round, pick up at the
    food and drop in the nest (the independent replay of the record); crowded grids too."""
    rng = np.random.default_rng(7)
    completed = 0
    for i, (g, n, alg) in enumerate([(6, 16, "sectors"), (8, 4, "strips"), (5, 8, "spiral"),
                                     (8, 16, "zigzag"), (6, 4, "rings")]):  # fmt: skip
        env = foraging_v0.parallel_env(grid=g, agents=n, algorithm=alg, food_units=3, seed=i,
                                       transport=transport, max_rounds=300)  # fmt: skip
        baseline = foraging_v0.baseline_policy(env)
        share = i / 4  # 0: random … 1: the seed's moves
        obs, infos = env.reset()
        while env.agents:
            seed_moves = baseline(obs, infos)
            actions = {a: seed_moves[a] if rng.random() < share else
                       int(rng.choice(np.flatnonzero(o["action_mask"]))) for a, o in obs.items()}
            obs, rewards, terms, truncs, infos = env.step(actions)
        rec = env.record()
        assert replay(rec.to_dict()) == []
        completed += rec.complete
    assert completed >= 2


def test_a_robot_pulled_off_its_route_or_the_relay_path_is_handled_by_the_seed_rules():
    """Deviations from the seed's moves: a robot kept still waits (its timetable shifts), one
    moved elsewhere leaves its pattern, a relay robot moved off the path walks back and
    re-joins; the seed's moves afterwards still bring every unit home."""
    env = foraging_v0.parallel_env(algorithm="sectors", **SMALL)
    policy = foraging_v0.baseline_policy(env)
    obs, infos = env.reset()
    m = env.unwrapped.mission
    for _ in range(3):  # robot_1 kept in the nest: it waits, its timetable shifts
        actions = {**policy(obs, infos), "robot_1": 0}
        obs, *_, infos = env.step(actions)
    assert m.delay[1] == 3 and not m.displaced[1]
    actions = policy(obs, infos)
    moves = [k for k in range(1, 5) if obs["robot_3"]["action_mask"][k] and k != actions[
        "robot_3"]]
    actions["robot_3"] = moves[0]  # anywhere but its route's next cell: off the pattern
    obs, *_, infos = env.step(actions)
    assert m.displaced[3]
    rejoined = False
    while env.agents:
        actions = policy(obs, infos)
        relay = [i for i in range(4) if m.mode[i] == 3 and m.tmode[i] == 1 and m.pidx[i] > 2]
        if relay and not rejoined:
            i = relay[0]
            x, y = m.pos[i]
            off = [k for k in range(1, 5) if obs[f"robot_{i}"]["action_mask"][k]
                   and (x + foraging_v0.MOVES[k][0], y + foraging_v0.MOVES[k][1])
                   not in m.path_index]  # fmt: skip
            actions[f"robot_{i}"] = off[0]
            obs, *_, infos = env.step(actions)
            if m.pos[i] != (x, y):
                assert m.tmode[i] == 0  # JOIN: back to the nearest path cell
                rejoined = True
            continue
        obs, *_, infos = env.step(actions)
    assert rejoined
    rec = env.record()
    assert rec.complete and replay(rec.to_dict()) == []


# ---------------------------------------------------------------- episodes


def test_record_before_the_end_and_closing_midway():
    env = foraging_v0.parallel_env(**TINY)
    with pytest.raises(RuntimeError, match="ended"):
        env.record()
    with pytest.raises(RuntimeError, match="no round is pending"):
        env.unwrapped.baseline_actions()
    threads = threading.active_count()
    env.reset(seed=1)
    assert threading.active_count() == threads  # the run is stepped in the caller's thread
    rounds = env.unwrapped._rounds
    assert rounds.gi_frame is not None  # suspended at round 0's Compute
    env.close()
    assert rounds.gi_frame is None  # closed: the run is abandoned
    with pytest.raises(RuntimeError, match="ended"):
        env.step({a: 0 for a in env.possible_agents})


def test_a_dropped_env_closes_its_run():
    env = foraging_v0.parallel_env(**TINY)
    env.reset(seed=1)
    rounds = env._rounds
    del env
    gc.collect()
    assert rounds.gi_frame is None


def test_reset_without_a_seed_moves_to_the_next_one():
    env = foraging_v0.parallel_env(seed=11, **TINY)
    env.reset()
    assert env.unwrapped._seed == 11  # the params' seed first
    env.reset()
    assert env.unwrapped._seed == int(np.random.default_rng(11).integers(2**31))
    env.reset(seed=3)
    env.reset()
    assert env.unwrapped._seed == int(np.random.default_rng(3).integers(2**31))
    env.close()


def test_same_seed_same_episode_with_random_moves():
    def episode():
        env = foraging_v0.parallel_env(**TINY)
        obs, infos = env.reset(seed=21)
        policy = random_policy(np.random.default_rng(0))
        seen = []
        while env.agents:
            actions = policy(obs, infos)
            obs, rewards, terms, truncs, infos = env.step(actions)
            seen.append((actions, {a: {k: v.tolist() for k, v in o.items()}
                                   for a, o in obs.items()}, rewards, terms, truncs, infos))
        return seen, without_wall(env.record())

    first, second = episode(), episode()
    assert len(first[0]) > 5 and first == second


# ---------------------------------------------------------------- SuperSuit


def test_supersuit_vector_env():
    ss = pytest.importorskip("supersuit")
    vec = ss.pettingzoo_env_to_vec_env_v1(foraging_v0.parallel_env(**TINY))
    vec = ss.concat_vec_envs_v1(vec, num_vec_envs=2, num_cpus=0)
    assert vec.num_envs == 8  # 2 worlds × 4 robots
    obs, infos = vec.reset(seed=0)
    assert obs["team_positions"].shape == (8, 4, 2) and obs["action_mask"].shape == (8, 5)
    rng = np.random.default_rng(0)
    episodes = 0
    for _ in range(150):
        actions = np.array([rng.choice(np.flatnonzero(m)) for m in obs["action_mask"]])
        obs, rewards, terms, truncs, infos = vec.step(actions)
        assert rewards.shape == (8,)
        episodes += int((terms | truncs).sum())
    assert episodes > 0  # episodes end and the vector env resets them
    vec.close()


def test_recall_is_a_baseline_policy_with_the_teams_memory():
    """``recall`` with its memory in the env: the baseline policy plays the pattern the team
    chose, and the record is ``swarmex.run``'s."""
    params = {**SMALL, "agents": 8, "grid": 32, "algorithm": "recall", "found": [(28, 30)]}
    env = foraging_v0.parallel_env(**params)
    play(env, foraging_v0.baseline_policy(env))
    record = env.record()
    from swarmex.missions.foraging.recall import choose

    assert record.extra["pattern"] == choose(32, 8, [(28, 30)], 3, "relay-food", "seed").pattern
    assert record.params["found"] == [[28, 30]]
    assert without_wall(record) == without_wall(swarmex.run("foraging", seed=0, **params))


@pytest.mark.parametrize("comm", ["seed", "omniscient"])
def test_baseline_breaks_a_crowd_frozen_while_others_communicate(comm):
    """A run whose End-to-End crowd froze while two robots still communicated (it never
    finished before the frozen-crowd rule covered the mixed phase, docs/foraging.md): the
    environment's seed moves play the plain run, which now finishes."""
    params = {"grid": 14, "agents": 48, "algorithm": "sectors", "food": (8, 5),
              "food_units": 20, "transport": "end-to-end", "comm": comm}  # fmt: skip
    env = foraging_v0.parallel_env(**params)
    play(env, foraging_v0.baseline_policy(env))
    record = env.record()
    assert record.complete
    assert without_wall(record) == without_wall(swarmex.run("foraging", **params))
    assert replay(record.to_dict()) == []
