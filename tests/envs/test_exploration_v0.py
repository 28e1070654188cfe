"""The exploration PettingZoo environment: PettingZoo's own checks, baseline == swarmex.run,
observations from the robot's belief, clear errors for bad actions, SuperSuit vectorising."""

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
from swarmex.envs import exploration_v0  # noqa: E402
from swarmex.missions.exploration.strategies import get_strategy  # noqa: E402

from ._helpers import play, render_test_rgb_array, without_wall  # noqa: E402

# a 30×30-cell room with a short laser: tens of decisions, goal conflicts included
SMALL = {"empty": "3x3", "cell": 0.1, "robots": 2, "laser_range": 0.6}
CAPPED = {**SMALL, "max_ticks": 300}  # random goals: a bounded episode
STRATEGIES = ["greedy", "greedy-exclusion", "utility", "minpos", "hungarian",
              "hungarian-exclusion", "adaptive-exclusion"]

pytestmark = pytest.mark.filterwarnings(
    # PettingZoo's api_test recommends Box/Discrete observations; ours is a Dict with a mask
    "ignore:Observation is not a NumPy array",
    "ignore:Observation space for each agent probably should be",
)


# ---------------------------------------------------------------- PettingZoo's checks


def test_api_test_aec():
    api_test(exploration_v0.env(**CAPPED), num_cycles=200)


def test_parallel_api_test():
    parallel_api_test(exploration_v0.parallel_env(**CAPPED), num_cycles=200)


def test_seed_test_aec():
    seed_test(lambda: exploration_v0.env(**CAPPED), num_cycles=100)


def test_parallel_seed_test():
    # parallel_seed_test samples actions without the mask: the opt-in projection mode
    # makes every sampled action valid (the default mode would raise on them)
    parallel_seed_test(
        lambda: exploration_v0.parallel_env(invalid_action="project", **CAPPED), num_cycles=100
    )


def test_render_test_rgb_array():
    render_test_rgb_array(exploration_v0.env, **CAPPED)


def test_render_is_the_exploration_renderer():
    env = exploration_v0.parallel_env(render_mode="rgb_array", **SMALL)
    env.reset(seed=2)
    img = env.render()
    assert img.dtype == np.uint8 and img.shape == (240, 240, 3)
    env.close()


# ---------------------------------------------------------------- baseline == swarmex.run


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_baseline_episode_is_the_run_record(strategy):
    # hungarian-exclusion assigns only with two rivals in view: three robots
    kw = {**SMALL, "robots": 3} if strategy == "hungarian-exclusion" else SMALL
    env = exploration_v0.parallel_env(strategy=strategy, seed=4, **kw)
    steps, rewards, terms, truncs = play(env, exploration_v0.baseline_policy(env))
    record = env.record()
    assert without_wall(record) == without_wall(
        swarmex.run("exploration", strategy=strategy, seed=4, **kw)
    )
    assert record.complete and all(terms.values()) and not any(truncs.values())
    assert steps >= 10  # many decisions, not a trivial run
    if strategy == "greedy-exclusion":
        assert record.metrics["conflicts"] > 0  # in-tick order matters and was kept


def test_baseline_through_reset_seed_and_aec_form():
    env = exploration_v0.parallel_env(strategy="greedy-exclusion", **SMALL)
    policy = exploration_v0.baseline_policy(env)
    env.reset(seed=7)
    obs, infos = env.reset(seed=9)  # a reset in the middle abandons the first run
    while env.agents:
        obs, *_, infos = env.step(policy(obs, infos))
    expected = without_wall(swarmex.run("exploration", strategy="greedy-exclusion", seed=9,
                                        **SMALL))
    assert without_wall(env.record()) == expected

    aec = exploration_v0.env(strategy="greedy-exclusion", **SMALL)
    aec.reset(seed=9)
    base = aec.unwrapped
    for agent in aec.agent_iter():
        obs, reward, term, trunc, info = aec.last()
        if term or trunc:
            aec.step(None)
            continue
        ctx = base.decision_context(agent)
        goal = None if ctx is None else get_strategy("greedy-exclusion").choose(ctx)
        aec.step(base.noop if goal is None else base.action_of(goal))
    assert without_wall(base.record()) == expected


def test_return_is_completion_bonus_minus_exploration_seconds():
    env = exploration_v0.parallel_env(strategy="utility", seed=1, **SMALL)
    policy = exploration_v0.baseline_policy(env)
    obs, infos = env.reset()
    total = 0.0
    while env.agents:
        obs, rewards, terms, truncs, infos = env.step(policy(obs, infos))
        assert rewards["robot_0"] == rewards["robot_1"]  # a team reward
        total += rewards["robot_0"]
    rec = env.record()
    assert total == pytest.approx(exploration_v0.COMPLETION_BONUS - 0.1 * rec.makespan)


def test_the_mission_cap_truncates():
    env = exploration_v0.parallel_env(strategy="greedy", seed=1, **{**SMALL, "max_ticks": 15})
    steps, rewards, terms, truncs = play(env, exploration_v0.baseline_policy(env))
    assert all(truncs.values()) and not any(terms.values())
    assert not env.record().complete and env.record().makespan == 15


# ---------------------------------------------------------------- observations


def test_observation_is_the_robots_own_belief():
    env = exploration_v0.parallel_env(strategy="greedy-exclusion", seed=3, **SMALL)
    policy = exploration_v0.baseline_policy(env)
    obs, infos = env.reset()
    run = env.unwrapped.run
    h, w = run.grid.shape
    heard_a_goal = False
    for _ in range(12):
        deciding = [a for a in env.agents if infos[a]["deciding"]]
        assert deciding == [env.unwrapped.deciding]
        for a in env.agents:
            i = int(a.split("_")[1])
            robot = run.robots[i]
            o = obs[a]
            assert env.observation_space(a).contains(o)
            lo = robot.belief.grid.logodds
            assert np.array_equal(o["belief"] == 1, lo < 0)
            assert np.array_equal(o["belief"] == 2, lo > 0)
            assert np.array_equal(o["belief"] == 0, lo == 0)
            assert tuple(o["position"]) == robot.pos
            assert tuple(o["team_goals"][i]) == (-1, -1)
            heard_a_goal |= bool((o["team_goals"] >= 0).any())
            mask = o["action_mask"]
            if a in deciding:
                ctx = env.unwrapped.decision_context(a)
                cells = set(zip(ctx.frontiers.xs[ctx.eligible], ctx.frontiers.ys[ctx.eligible],
                                strict=True))
                assert {(k % w, k // w) for k in np.flatnonzero(mask)} == cells
                assert mask[env.unwrapped.noop] == 0 and 0 < mask.sum() < mask.size // 4
            else:
                assert np.flatnonzero(mask).tolist() == [env.unwrapped.noop]
        obs, _, _, _, infos = env.step(policy(obs, infos))
    assert heard_a_goal  # greedy-exclusion's GOAL messages reach the observations
    # the maps are beliefs, not the truth: the first robot's map at tick 0 has unknown cells
    env.reset(seed=3)
    assert (env.unwrapped._observe(0, env.unwrapped.run)["belief"] == 0).any()
    env.close()


# ---------------------------------------------------------------- params and actions


def test_bad_params_are_the_runs_input_errors():
    for bad in ({"robots": "two"}, {"strategy": "nearest"}, {"empty": "3x3"},
                {"robot": 2, "empty": "3x3"}):
        with pytest.raises(swarmex.InputError) as run_error:
            swarmex.run("exploration", **bad)
        with pytest.raises(swarmex.InputError) as env_error:
            exploration_v0.parallel_env(**bad)
        assert str(env_error.value) == str(run_error.value)
    with pytest.raises(swarmex.InputError, match="laser_range"):
        exploration_v0.parallel_env(**{**SMALL, "laser_range": 0.1})  # a world check
    with pytest.raises(swarmex.InputError, match="render_mode"):
        exploration_v0.parallel_env(render_mode="human", **SMALL)
    with pytest.raises(swarmex.InputError, match="invalid_action"):
        exploration_v0.parallel_env(invalid_action="ignore", **SMALL)
    with pytest.raises(swarmex.InputError, match="^seed must be"):
        exploration_v0.parallel_env(seed=-1, **SMALL)


def test_reset_refuses_a_bad_seed_clearly():
    """reset(seed=-1) used to fail deep in NumPy ("expected non-negative integer")."""
    env = exploration_v0.parallel_env(**SMALL)
    for bad in (-1, 2.5, "3", True):
        with pytest.raises(swarmex.InputError, match="seed must be an integer >= 0"):
            env.reset(seed=bad)
    obs, _ = env.reset(seed=np.int64(4))
    assert set(obs) == set(env.possible_agents)


def test_bad_actions_raise_and_leave_the_world_as_it_was():
    env = exploration_v0.parallel_env(strategy="minpos", seed=5, **SMALL)
    policy = exploration_v0.baseline_policy(env)
    obs, infos = env.reset()
    base = env.unwrapped
    good = policy(obs, infos)
    me = base.deciding
    other = next(a for a in env.agents if a != me)
    not_frontier = int(np.flatnonzero(obs[me]["action_mask"] == 0)[0])
    cases = [
        ({**good, me: base.noop + 1}, "outside the action space"),
        ({**good, me: -1}, "outside the action space"),
        ({**good, me: 2.5}, "outside the action space"),
        ({**good, me: not_frontier}, "not a reachable frontier cell"),
        ({**good, me: base.noop}, "no-op is not allowed"),
        ({**good, other: good[me]}, f"{other} is not deciding"),
        ({other: base.noop}, f"no action for {me}"),
        ({**good, "robot_9": 0}, "unknown agent"),
    ]
    for actions, why in cases:
        with pytest.raises(ValueError, match=why):
            env.step(actions)
        assert base.deciding == me  # the same decision is still pending
    good[me] = np.int64(good[me])  # numpy integers are actions too
    obs, *_, infos = env.step(good)
    while env.agents:
        obs, *_, infos = env.step(policy(obs, infos))
    assert without_wall(env.record()) == without_wall(
        swarmex.run("exploration", strategy="minpos", seed=5, **SMALL)
    )
    with pytest.raises(RuntimeError, match="ended"):
        env.step({"robot_0": 0})


def test_project_mode_maps_masked_out_actions_onto_valid_ones():
    env = exploration_v0.parallel_env(invalid_action="project", seed=5, **CAPPED)
    obs, infos = env.reset()
    base = env.unwrapped
    me = base.deciding
    valid = np.flatnonzero(obs[me]["action_mask"])
    a = int(np.flatnonzero(obs[me]["action_mask"] == 0)[3])
    env.step({agent: a for agent in env.agents})  # every agent sends a masked-out action
    assert base.run.robots[int(me.split("_")[1])].goal == (
        int(valid[a % valid.size]) % base.shape[1], int(valid[a % valid.size]) // base.shape[1]
    )
    with pytest.raises(ValueError, match="outside the action space"):
        env.step({agent: base.noop + 1 for agent in env.agents})
    env.close()


def test_record_before_the_end_and_closing_midway():
    env = exploration_v0.parallel_env(**SMALL)
    with pytest.raises(RuntimeError, match="ended"):
        env.record()
    env.reset(seed=1)
    worker = env.unwrapped._broker._thread
    assert worker.is_alive()
    env.close()
    assert not worker.is_alive()
    assert all(t is not worker for t in threading.enumerate())


def test_a_dropped_env_closes_its_worker():
    env = exploration_v0.parallel_env(**SMALL)
    env.reset(seed=1)
    worker = env._broker._thread
    del env
    gc.collect()
    worker.join(10)
    assert not worker.is_alive()


def test_a_run_without_any_decision_ends_at_reset():
    params = {"empty": "0.6x0.6", "cell": 0.1, "robots": 1, "robot_radius": 0.05}
    env = exploration_v0.parallel_env(**params)
    obs, infos = env.reset()  # the first scan sees the whole room: no frontier, no decision
    assert obs == {} and infos == {} and env.agents == []
    assert without_wall(env.record()) == without_wall(swarmex.run("exploration", **params))
    aec = exploration_v0.env(**params)  # the AEC form too (it died in PettingZoo's selector)
    aec.reset()
    assert aec.agents == [] and list(aec.agent_iter()) == []
    assert without_wall(aec.unwrapped.record()) == without_wall(env.record())


def test_reset_without_a_seed_moves_to_the_next_one():
    env = exploration_v0.parallel_env(seed=11, **CAPPED)
    env.reset()
    assert env.unwrapped._seed == 11  # the params' seed first
    env.reset()
    assert env.unwrapped._seed == int(np.random.default_rng(11).integers(2**31))
    env.reset(seed=3)
    env.reset()
    assert env.unwrapped._seed == int(np.random.default_rng(3).integers(2**31))
    env.close()


# ---------------------------------------------------------------- SuperSuit


def test_supersuit_vector_env():
    ss = pytest.importorskip("supersuit")
    vec = ss.pettingzoo_env_to_vec_env_v1(exploration_v0.parallel_env(**CAPPED))
    vec = ss.concat_vec_envs_v1(vec, num_vec_envs=2, num_cpus=0)
    assert vec.num_envs == 4  # 2 worlds × 2 robots
    obs, infos = vec.reset(seed=0)
    assert obs["belief"].shape == (4, 30, 30) and obs["action_mask"].shape == (4, 901)
    rng = np.random.default_rng(0)
    episodes = 0
    for _ in range(150):
        actions = np.array([rng.choice(np.flatnonzero(m)) for m in obs["action_mask"]])
        obs, rewards, terms, truncs, infos = vec.step(actions)
        assert rewards.shape == (4,)
        episodes += int((terms | truncs).sum())
    assert episodes > 0  # episodes end and the vector env resets them
    vec.close()


def test_same_seed_same_episode_with_random_goals():
    # (parallel_seed_test stops after one step: it tests any() of a dict's keys)
    def episode():
        env = exploration_v0.parallel_env(**CAPPED)
        obs, infos = env.reset(seed=21)
        rng = np.random.default_rng(0)
        seen = []
        while env.agents:
            actions = {a: int(rng.choice(np.flatnonzero(obs[a]["action_mask"])))
                       for a in env.agents}
            obs, rewards, terms, truncs, infos = env.step(actions)
            seen.append((actions, {a: {k: v.tolist() for k, v in o.items()}
                                   for a, o in obs.items()}, rewards, terms, truncs, infos))
        return seen, without_wall(env.record())

    first, second = episode(), episode()
    assert len(first[0]) > 5 and first == second
