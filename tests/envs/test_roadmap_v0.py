"""The roadmap PettingZoo environment: PettingZoo's own checks, baseline == swarmex.run,
clear errors for bad params and bad actions, beliefs not truth, SuperSuit vectorisation.

Small worlds throughout (60-80 roadmap nodes on the 640 × 480 example environments).
"""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import (  # noqa: E402
    api_test,
    parallel_api_test,
    parallel_seed_test,
    render_test,
    seed_test,
)

import swarmex  # noqa: E402
from swarmex.envs import roadmap_v0  # noqa: E402
from swarmex.missions.roadmap.replay import replay_problems  # noqa: E402
from swarmex.worlds.polygon import load_polygon_world  # noqa: E402

from ._helpers import without_wall  # noqa: E402

FIG8 = "examples/roadmap_fig8.json"
FIG14 = "examples/roadmap_fig14.json"
SMALL = dict(env=FIG8, agents=2, nodes=60, step=40, sensor_range="1eps", seed=3)


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # PettingZoo's advice (dict observations, masks)
        yield


def drive(aec, policy=None):
    """Play one episode on an AEC env: the policy's actions, else random open ones."""
    decisions = 0
    for agent in aec.agent_iter():
        obs, _, term, trunc, info = aec.last()
        if term or trunc:
            aec.step(None)
            continue
        if policy is None:
            action = aec.action_space(agent).sample(obs["action_mask"])
        else:
            action = policy({agent: obs}, {agent: info})[agent]
        aec.step(action)
        decisions += 1
    return decisions


# ------------------------------------------------------------------ PettingZoo's checks


@pytest.mark.parametrize("planner", ["wma-rrt", "prm"])
def test_api(planner):
    api_test(roadmap_v0.env(planner=planner, **SMALL), num_cycles=100)


@pytest.mark.parametrize("planner", ["wma-rrt-takeover", "prm"])
def test_parallel_api(planner):
    parallel_api_test(roadmap_v0.parallel_env(planner=planner, **SMALL), num_cycles=100)


def test_seed():
    seed_test(lambda: roadmap_v0.env(**SMALL), num_cycles=50)
    seed_test(lambda: roadmap_v0.env(planner="prm", **SMALL), num_cycles=50)


def test_parallel_seed():
    # the test samples actions without the mask: an illegal one ends the episode (PettingZoo's
    # TerminateIllegalWrapper) instead of raising
    parallel_seed_test(lambda: roadmap_v0.parallel_env(illegal_reward=-1.0, **SMALL))


def test_render_rgb_array():
    def make(render_mode=None):
        # render_test builds one env with "human" only to read metadata["render_modes"]
        return roadmap_v0.env(render_mode=None if render_mode == "human" else render_mode, **SMALL)

    render_test(make)


# ------------------------------------------------------------------ baseline == swarmex.run


@pytest.mark.parametrize(
    "params",
    [
        dict(SMALL, planner="wma-rrt"),
        dict(SMALL, planner="prm"),
        dict(SMALL, planner="wma-rrt-takeover", agents=3, nodes=80),
        dict(SMALL, planner="wma-rrt-fairshare", agents=3, nodes=80),
        dict(env=FIG8, task="search", goal=(500, 300), planner="wma-rrt-fairshare", agents=2,
             nodes=60, step=40, sensor_range="inf", seed=1),
        dict(env=FIG8, task="search", goal=(500, 300), planner="wma-rrt", agents=2, nodes=60,
             step=40, sensor_range="inf", seed=1),
        dict(env=FIG8, task="search", goal=(500, 300), planner="prm", agents=2, nodes=60,
             step=40, sensor_range="inf", seed=1),
        dict(env=FIG14, task="search", planner="wma-rrt", agents=2, nodes=60, step=40,
             sensor_range="inf", seed=0),
    ],
    ids=["wma-cover", "prm-cover", "takeover-cover", "fairshare-cover", "fairshare-search",
         "wma-search", "prm-search",
         "wma-unreachable"],
)
def test_baseline_episode_is_swarmex_run(params):
    par = roadmap_v0.parallel_env(**params)
    policy = roadmap_v0.baseline_policy(par)
    obs, infos = par.reset(seed=params["seed"])
    steps = 0
    while par.agents:
        obs, _, _, _, infos = par.step(policy(obs, infos))
        steps += 1
    assert steps > 5  # the agents really decided
    record = par.unwrapped.record()
    assert without_wall(record) == without_wall(swarmex.run("roadmap", **params))
    par.close()


def test_baseline_on_the_aec_form_and_the_search_outcome():
    params = dict(env=FIG8, task="search", goal=(500, 300), planner="wma-rrt", agents=2,
                  nodes=60, step=40, sensor_range="inf", seed=1)
    aec = roadmap_v0.env(**params)
    aec.reset()  # the params' seed
    drive(aec, roadmap_v0.baseline_policy(aec))
    record = aec.unwrapped.record()
    assert record.metrics["goal_found"] and record.complete
    assert without_wall(record) == without_wall(swarmex.run("roadmap", **params))


def test_an_episode_that_ends_inside_reset_leaves_no_agents():
    """PRM walkers on Fig. 14 with seed 1 never get a choice: the parallel form must end the
    episode at once (no agents, no observations) so the usual loop simply does not run, and
    the record is still the one ``swarmex.run`` gives."""
    params = dict(env=FIG14, agents=3, nodes=80, step=40, sensor_range="1eps", task="search",
                  planner="prm", seed=1)
    par = roadmap_v0.parallel_env(**params)
    obs, infos = par.reset(seed=1)
    assert obs == {} and par.agents == []
    policy = roadmap_v0.baseline_policy(par)
    while par.agents:  # the documented loop: must not ask for missing observations
        obs, _, _, _, infos = par.step(policy(obs, infos))
    assert par.step({}) == ({}, {}, {}, {}, {})
    record = par.unwrapped.record()
    assert without_wall(record) == without_wall(swarmex.run("roadmap", **params))
    obs, _ = par.reset(seed=0)  # a seed with decisions: the env is usable again
    assert obs and par.agents == par.possible_agents
    par.close()


# ------------------------------------------------------------------ errors


def test_bad_params_are_the_same_input_error_as_swarmex_run():
    for bad in (dict(agents="three"), dict(agnts=2), dict(nodes=1), dict(task="search",
                                                                          env=FIG8)):
        params = {**SMALL, **bad}
        if "agnts" in bad:
            params.pop("agents")
        with pytest.raises(swarmex.InputError) as ours:
            roadmap_v0.env(**params)
        with pytest.raises(swarmex.InputError) as theirs:
            swarmex.run("roadmap", **{k: v for k, v in params.items() if k != "seed"},
                        seed=params["seed"])
        assert str(ours.value) == str(theirs.value)
    with pytest.raises(swarmex.InputError, match="render_mode"):
        roadmap_v0.env(render_mode="human", **SMALL)
    with pytest.raises(swarmex.InputError, match="max_edges"):
        roadmap_v0.env(max_edges=0, **SMALL)
    with pytest.raises(swarmex.InputError, match="max_edges=50"):  # the PRM has ~190 edges
        roadmap_v0.env(planner="prm", max_edges=50, **SMALL).reset()

    # numpy refused a negative reset seed from deep inside the run, without naming it
    env = roadmap_v0.env(**SMALL)
    for seed, needle in ((-3, "reset seed must be at least 0"), ("x", "must be an integer"),
                         (3.0, "must be an integer")):
        with pytest.raises(swarmex.InputError, match=needle):
            env.reset(seed=seed)
    env.close()
    with pytest.raises(swarmex.InputError, match="illegal_reward must be a finite number"):
        roadmap_v0.env(illegal_reward="x", **SMALL)
    # a copy of the parallel form is a fresh env: it lists no agents before its reset
    par = roadmap_v0.parallel_env(**SMALL)
    par.reset()
    assert pickle.loads(pickle.dumps(par)).agents == []
    par.close()


def test_bad_actions_raise_naming_agent_action_and_why():
    aec = roadmap_v0.env(**SMALL)
    aec.reset()
    agent = aec.agent_selection
    mask = aec.observe(agent)["action_mask"]
    closed = int(np.flatnonzero(mask == 0)[0])
    with pytest.raises(ValueError, match=rf"{agent}: action {closed} is not open: .*open actions"):
        aec.step(closed)
    with pytest.raises(ValueError, match=rf"{agent}: action 999 is outside the action space"):
        aec.step(999)
    with pytest.raises(ValueError, match=rf"{agent}: action 1.5 is not an integer"):
        aec.step(1.5)
    with pytest.raises(ValueError, match=r"is not an integer"):
        aec.step(np.array([1.0]))  # a one-element array is read, but still needs an integer
    with pytest.raises(ValueError, match=rf"{agent}: no action"):
        aec.step(None)
    stay = aec.unwrapped.stay_action
    if not mask[stay]:
        with pytest.raises(ValueError, match="only a free WMA-RRT agent at the Main Root"):
            aec.step(stay)
    # nothing happened: the same decision is still pending, and a good action goes through
    assert aec.agent_selection == agent
    assert np.array_equal(aec.observe(agent)["action_mask"], mask)
    # a one-element array, as SB3 and torch policies give, like the other three envs
    aec.step(np.array([np.flatnonzero(mask)[0]]))


def test_record_before_the_end_is_an_error():
    aec = roadmap_v0.env(**SMALL)
    aec.reset()
    with pytest.raises(RuntimeError, match="not ended"):
        aec.unwrapped.record()


# ------------------------------------------------------------------ semantics


def test_observations_are_beliefs_and_the_shared_board():
    aec = roadmap_v0.env(**SMALL)
    aec.reset()
    for _ in range(10):
        aec.step(aec.unwrapped.baseline_action(aec.agent_selection))
    me = aec.agent_selection
    other = next(a for a in aec.agents if a != me)
    mine, theirs = aec.observe(me), aec.observe(other)
    assert mine["action_mask"].sum() >= 2 and theirs["action_mask"].sum() == 0
    for key in ("edge_weights", "sync", "branch_weight", "edge_nodes", "node_xy", "goal_found"):
        assert np.array_equal(mine[key], theirs[key])  # the board: the one channel they share
    space = aec.observation_space(me)
    assert space.contains(mine) and space.contains(theirs)
    # its own position and node, never the other's
    run_agents = aec.unwrapped._episode.agents
    i = aec.unwrapped.possible_agents.index(me)
    assert np.allclose(mine["position"], run_agents[i].xy)
    assert mine["node"][0] == run_agents[i].node


@pytest.mark.parametrize("planner", ["wma-rrt", "wma-rrt-takeover", "wma-rrt-fairshare"])
def test_random_policies_keep_the_wma_guarantee(planner):
    """Whatever the open actions chosen, a complete WMA-RRT coverage travelled every edge, and
    the record passes the independent replay."""
    aec = roadmap_v0.env(planner=planner, **SMALL)
    for seed in (0, 1):
        aec.reset(seed=seed)
        drive(aec)
        record = aec.unwrapped.record()
        assert record.complete
        assert record.metrics["edges_traversed"] == record.metrics["tree_edges"]
        assert replay_problems(record.to_dict(), load_polygon_world(FIG8)) == []


def test_rewards_and_dones():
    aec = roadmap_v0.env(planner="prm", **SMALL)
    aec.reset()
    start_coverage, start_t = aec.unwrapped._last_coverage, aec.unwrapped._last_t
    assert start_t >= 2  # every agent's first step is its entry leg, taken without asking
    total = 0.0
    for agent in aec.agent_iter():
        _, reward, term, trunc, _ = aec.last()
        if agent == "agent_0":
            total += reward
        aec.step(None if term or trunc else aec.unwrapped.baseline_action(agent))
        if term or trunc:
            assert trunc and not term  # PRM coverage ends at its step budget
    record = aec.unwrapped.record()
    # every agent gets the team's reward: 100 x coverage gained - 1 per step, from the first
    # decision on (no completion bonus: the budget ended the run)
    run = aec.unwrapped._episode.run
    expected = 100 * (run.raster.coverage() - start_coverage) - (record.metrics["steps"] - start_t)
    assert total == pytest.approx(expected)


def test_reset_without_seed_moves_on_and_pickle_gives_a_fresh_env():
    aec = roadmap_v0.env(**SMALL)
    aec.reset()
    drive(aec)
    assert aec.unwrapped.record().seed == 3
    aec.reset()
    drive(aec)
    assert aec.unwrapped.record().seed == np.random.default_rng(3).integers(2**31)
    copy = pickle.loads(pickle.dumps(aec.unwrapped))
    copy.reset(seed=3)
    assert copy.agent_selection in copy.possible_agents
    copy.close()


def test_supersuit_vector_env():
    ss = pytest.importorskip("supersuit")
    vec = ss.pettingzoo_env_to_vec_env_v1(roadmap_v0.parallel_env(**SMALL))
    vec = ss.concat_vec_envs_v1(vec, num_vec_envs=2, num_cpus=0)
    obs, _ = vec.reset(seed=0)
    assert vec.num_envs == 4 and obs["action_mask"].shape == (4, 61)
    rng = np.random.default_rng(0)
    ended = 0
    for _ in range(200):
        masks = obs["action_mask"]
        actions = np.array([rng.choice(np.flatnonzero(m)) if m.any() else 0 for m in masks])
        obs, rewards, terms, truncs, _ = vec.step(actions)
        assert rewards.shape == (4,)
        ended += int(terms.any() or truncs.any())
    assert ended >= 1  # an episode ended and the vector env started the next
    vec.close()


def test_ompl_prm_baseline_episode_is_swarmex_run():
    """OMPL's PRM in the environment: its roadmap fits the default edge capacity (10 K) and
    the seed algorithm's episode is the mission's run."""
    pytest.importorskip("ompl.base")
    params = dict(SMALL, planner="ompl-prm")
    par = roadmap_v0.parallel_env(**params)
    policy = roadmap_v0.baseline_policy(par)
    obs, infos = par.reset(seed=params["seed"])
    while par.agents:
        obs, _, _, _, infos = par.step(policy(obs, infos))
    record = par.unwrapped.record()
    assert record.to_dict()["roadmap"]["kind"] == "ompl-prm"
    assert without_wall(record) == without_wall(swarmex.run("roadmap", **params))
    par.close()


def test_illegal_reward_keeps_the_clear_errors_for_actions_outside_the_space():
    """PettingZoo's TerminateIllegalWrapper indexed the mask with the action first: 61 for
    Discrete(61) or a float was an IndexError. Only a masked-out action ends the episode."""
    from swarmex.errors import InputError

    aec = roadmap_v0.env(illegal_reward=-5.0, **SMALL)
    aec.reset()
    n = aec.action_space(aec.agent_selection).n
    with pytest.raises(InputError, match=f"outside the action space Discrete\\({n}\\)"):
        aec.step(n)
    with pytest.raises(InputError, match="is not an integer"):
        aec.step(1.5)
    mask = aec.observe(aec.agent_selection)["action_mask"]
    closed = int(np.flatnonzero(mask == 0)[0])
    offender = aec.agent_selection
    aec.step(closed)  # masked out: the wrapper's penalty, and the episode ends
    assert aec.rewards[offender] == -5.0 and all(aec.terminations.values())
    aec.close()
