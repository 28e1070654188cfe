"""Helpers shared by the PettingZoo environment tests (was written in each test file)."""

from __future__ import annotations


def play(env, policy):
    """Play a parallel env to its end: (steps, last rewards, terminations, truncations)."""
    obs, infos = env.reset()
    steps = 0
    while env.agents:
        obs, rewards, terms, truncs, infos = env.step(policy(obs, infos))
        steps += 1
    return steps, rewards, terms, truncs


def without_wall(record):
    """A run record as a dict without its wall-clock time (the one field that varies)."""
    d = record.to_dict()
    d.pop("wall_seconds")
    return d


def render_test_rgb_array(make_env, **params):
    """PettingZoo's render_test on an env that supports rgb_array alone.

    render_test first builds the env with render_mode="human" only to read its metadata;
    that probe gets None.
    """
    from pettingzoo.test import render_test

    def make(render_mode=None):
        mode = None if render_mode == "human" else render_mode
        return make_env(render_mode=mode, **params)

    render_test(make)
