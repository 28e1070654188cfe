"""``close()`` in the middle of an episode abandons it the same way in every environment: no
agents are left, and a step asks for ``reset()`` instead of failing on an internal assert
(traversal and roadmap) or naming a run the caller never saw (exploration)."""

from __future__ import annotations

import warnings

import pytest

pytest.importorskip("pettingzoo")

from swarmex.envs import exploration_v0, foraging_v0, roadmap_v0, traversal_v0  # noqa: E402

CASES = {
    "traversal": (traversal_v0, dict(grid="6x5", agents=3)),
    "foraging": (foraging_v0, dict(grid=8, agents=4, algorithm="sectors", food_units=2)),
    "exploration": (exploration_v0, dict(empty="3x3", cell=0.1, robots=2, laser_range=0.6)),
    "roadmap": (roadmap_v0, dict(env="examples/roadmap_fig8.json", agents=2, nodes=60,
                                 step=40, sensor_range="1eps", seed=3)),
}


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # PettingZoo's "step() after all agents are done"
        yield


@pytest.mark.parametrize("name", list(CASES))
def test_a_parallel_episode_closed_midway_has_no_agents_and_plays_again(name):
    module, params = CASES[name]
    env = module.parallel_env(**params)
    policy = module.baseline_policy(env)
    obs, infos = env.reset(seed=1)
    obs, *_, infos = env.step(policy(obs, infos))
    assert env.agents, "the episode should still be running after one step"
    env.close()
    assert env.agents == [] and env.unwrapped.agents == []
    env.close()  # twice is fine
    obs, infos = env.reset(seed=1)  # and a new episode runs to its end
    steps = 0
    while env.agents and steps < 10_000:
        obs, *_, infos = env.step(policy(obs, infos))
        steps += 1
    assert not env.agents


@pytest.mark.parametrize("name", list(CASES))
def test_an_aec_episode_closed_midway_has_no_agents_to_iterate(name):
    module, params = CASES[name]
    env = module.env(**params)
    env.reset(seed=1)
    env.close()
    assert env.agents == [] and list(env.agent_iter()) == []


@pytest.mark.parametrize(("name", "form"), [("traversal", "aec"), ("roadmap", "aec"),
                                            ("exploration", "parallel"),
                                            ("foraging", "parallel")])
def test_a_step_after_a_midway_close_asks_for_reset(name, form):
    """On each env's own form (its raw AEC env, or its parallel env)."""
    module, params = CASES[name]
    if form == "aec":
        env = module.raw_env(**params)
        env.reset()
        action = 0
    else:
        env = module.parallel_env(**params)
        obs, infos = env.reset()
        action = module.baseline_policy(env)(obs, infos)
    env.close()
    assert env.agents == []
    with pytest.raises(RuntimeError, match="episode has ended; call reset"):
        env.step(action)
