"""Pieces the broker-driven environments share: argument checks and the episode plumbing
(space accessors, the reset preamble, close and pickling) of a run driven by a
:class:`~swarmex.envs.broker.DecisionBroker`."""

from __future__ import annotations

import math
import weakref
from typing import Any, ClassVar

import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv
from pettingzoo.utils.conversions import (
    parallel_to_aec_wrapper,
    turn_based_aec_to_parallel_wrapper,
)
from pettingzoo.utils.wrappers import OrderEnforcingWrapper

from swarmex.errors import InputError


def check_modes(
    render_mode: str | None,
    invalid_action: str,
    render_modes: tuple[str, ...],
    invalid_action_modes: tuple[str, ...],
) -> None:
    """Raise :class:`InputError` for an unknown ``render_mode`` or ``invalid_action``."""
    if render_mode is not None and render_mode not in render_modes:
        raise InputError(
            f"render_mode must be one of {', '.join(render_modes)} or None, "
            f"got {render_mode!r}"
        )
    if invalid_action not in invalid_action_modes:
        raise InputError(
            f"invalid_action must be one of {', '.join(invalid_action_modes)}, "
            f"got {invalid_action!r}"
        )


def check_finite(*named: tuple[str, Any]) -> None:
    """Raise :class:`InputError` for the first ``(name, value)`` that is not a finite number."""
    for name, value in named:
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise InputError(f"{name} must be a finite number, got {value!r}")


def plain_int(raw: Any) -> Any:
    """``raw`` with a one-element array or a NumPy integer turned into a Python value."""
    value = raw.item() if isinstance(raw, np.ndarray) and raw.size == 1 else raw
    if isinstance(value, np.integer):
        value = int(value)
    return value


class _EndsOnClose:
    """``close()`` of a PettingZoo conversion: abandon the run in progress, and end the
    episode here too. Why: a conversion keeps its own copy of ``agents``, which a mid-episode
    close left listing the team, so ``while env.agents:`` and ``agent_iter()`` went on into
    the closed run."""

    agents: list[Any]

    def close(self) -> None:
        super().close()  # type: ignore[misc]
        self.agents = []


class TurnBasedParallel(_EndsOnClose, turn_based_aec_to_parallel_wrapper):
    """PettingZoo's turn-based AEC-to-Parallel conversion, for a run that can end in ``reset``.

    Why: an event-driven mission can finish before anyone decides (a tiny world seen whole by
    the first scans). The AEC form then lists every agent as terminated or truncated, as the
    AEC API wants, but PettingZoo's conversion copied that list into the parallel ``agents``
    while returning no observations, so the usual loop ``while env.agents:
    env.step(policy(obs, infos))`` asked for observations that did not exist. Here the dead
    agents are stepped out of the AEC env at once and the parallel ``agents`` is empty, as
    the Parallel API says an ended episode must be. A ``step`` after the end returns the five
    empty dicts of the Parallel API (PettingZoo's conversion returns four).
    """

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[Any, Any], dict[Any, Any]]:
        observations, infos = super().reset(seed=seed, options=options)
        aec = self.aec_env
        if aec.agents and all(aec.terminations[a] or aec.truncations[a] for a in aec.agents):
            while aec.agents:
                aec.step(None)
            self.agents: list[Any] = []
        return observations, infos

    def __getstate__(self) -> dict[str, Any]:
        """A copy (SuperSuit's, a pickle) is a fresh env, not reset yet: no agents listed."""
        state = self.__dict__.copy()
        state["agents"] = []
        return state

    def step(self, actions: dict[Any, Any]) -> tuple[dict[Any, Any], ...]:
        """One decision: the deciding agent's action (``infos[a]["active_agent"]``); the
        other agents' entries are ignored. Clear errors for what PettingZoo's conversion
        met with a ``KeyError`` or an ``AttributeError``."""
        if not hasattr(self, "agents"):
            raise RuntimeError("step() before reset(): call reset() first")
        if not self.agents:  # PettingZoo's conversion returns four dicts here, not five
            return {}, {}, {}, {}, {}
        if not isinstance(actions, dict):
            raise InputError(f"step: actions must be a dict of agent -> action, got "
                             f"{type(actions).__name__}")
        unknown = [a for a in actions if a not in self.possible_agents]
        if unknown:
            raise InputError(f"step: no agent {unknown[0]!r} (agents: "
                             f"{', '.join(map(str, self.possible_agents))})")
        deciding = self.aec_env.agent_selection
        if deciding not in actions:
            raise InputError(f"step: no action for {deciding!r}, the agent deciding now (the "
                             "one whose action_mask has a 1; infos[a]['active_agent'])")
        return tuple(super().step(actions))


class _ParallelToAEC(_EndsOnClose, parallel_to_aec_wrapper):
    """PettingZoo's Parallel-to-AEC conversion, for a run that can end in ``reset``.

    Why: PettingZoo's agent selector cannot start an empty team, so when the first scans see
    the whole world (the parallel env then has no agents) the AEC ``reset`` died with a
    ``ZeroDivisionError``. Here that episode is simply over: no agents, ``agent_iter()``
    yields nothing, and the record is complete.
    """

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> None:
        try:
            super().reset(seed=seed, options=options)
        except ZeroDivisionError:  # the selector's modulo over an empty team
            if self.env.agents:
                raise
            self.agents: list[Any] = []
            self.agent_selection = None
            self.rewards: dict[Any, float] = {}
            self._cumulative_rewards: dict[Any, float] = {}
            self.terminations: dict[Any, bool] = {}
            self.truncations: dict[Any, bool] = {}
            self.infos: dict[Any, dict[str, Any]] = {}


def parallel_to_aec(par_env: Any) -> AECEnv[Any, Any, Any]:
    """The AEC form of one of our parallel envs, order-enforcing (as PettingZoo's
    ``parallel_to_aec``), that also survives an episode ending inside ``reset``."""
    return OrderEnforcingWrapper(_ParallelToAEC(par_env))


#: what a parallel env's ``step`` returns: observations, rewards, terminations,
#: truncations and infos, each by agent (named once for the envs' and the mixin's signatures)
StepReturns = tuple[
    dict[str, dict[str, np.ndarray]],
    dict[str, float],
    dict[str, bool],
    dict[str, bool],
    dict[str, dict[str, Any]],
]

#: seeds a chain draws are below this (numpy takes any; a record's seed stays a plain int)
SEED_LIMIT = 2**31


class SeedChain:
    """The seeds of an environment's successive episodes.

    ``next(s)`` runs seed ``s``; ``next(None)`` runs the params' seed the first time, then
    the next seed of a generator seeded by the last explicit seed (the params' until one is
    given). Why a generator and not "the previous seed + 1": SuperSuit's vector env seeds its
    copies s, s + 1, …, and with + 1 copy i replayed copy i + 1's episodes one reset later;
    streams from different seeds do not meet. Pickled with the environment, so a copy goes on
    where the original was.
    """

    def __init__(self, first: int) -> None:
        self.first = int(first)
        self._rng: np.random.Generator | None = None

    def next(self, seed: int | None) -> int:
        if seed is not None:
            self._rng = np.random.default_rng(int(seed))
            return int(seed)
        if self._rng is None:
            self._rng = np.random.default_rng(self.first)
            return self.first
        return int(self._rng.integers(SEED_LIMIT))


class BrokerEpisodeMixin:
    """Space accessors, reset preamble, the end of ``step``, ``close`` and pickling of a
    parallel environment whose run lives behind a broker; ``_TRANSIENT`` names the attributes
    of a run in progress, ``_pending`` is the decision the run waits for (None: it has
    ended)."""

    _TRANSIENT: ClassVar[tuple[str, ...]] = ()
    _obs_spaces: dict[str, spaces.Space[Any]]
    _act_spaces: dict[str, spaces.Space[Any]]
    _finalizer: weakref.finalize[Any, Any] | None
    _seeds: SeedChain
    _seed: int
    _pending: Any
    agents: list[str]

    def _clear(self) -> None:
        raise NotImplementedError

    def _observations(self) -> dict[str, dict[str, np.ndarray]]:
        raise NotImplementedError

    def _infos(self) -> dict[str, dict[str, Any]]:
        raise NotImplementedError

    def _step_returns(
        self, reward: float, complete: bool, completion_bonus: float
    ) -> StepReturns:
        """The five dicts a ``step`` returns once the run has taken the actions: every agent
        shares ``reward``; when the run has ended (``_pending`` is None) the agents are
        terminated if it is ``complete`` (which adds ``completion_bonus``), truncated if not,
        and leave the episode. One place, so the environments end an episode alike."""
        obs, infos = self._observations(), self._infos()
        agents = self.agents
        if self._pending is None:  # the run has ended
            if complete:
                reward += completion_bonus
            self.agents = []
            terms = dict.fromkeys(agents, complete)
            truncs = dict.fromkeys(agents, not complete)
        else:
            terms = dict.fromkeys(agents, False)
            truncs = dict.fromkeys(agents, False)
        return obs, dict.fromkeys(agents, reward), terms, truncs, infos

    def observation_space(self, agent: str) -> spaces.Space[Any]:
        return self._obs_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space[Any]:
        return self._act_spaces[agent]

    def _begin_reset(self, seed: int | None) -> None:
        """End any run, take ``seed`` (if given), and clear the episode state."""
        seed = plain_int(seed)
        if seed is not None and (
            isinstance(seed, bool) or not isinstance(seed, int) or seed < 0
        ):  # checked here, not deep in NumPy's generator ("expected non-negative integer")
            raise InputError(f"reset: seed must be an integer >= 0 or None, got {seed!r}")
        self.close()
        self._seed = self._seeds.next(seed)
        self._clear()

    def close(self) -> None:
        """Abandon a run in progress (its worker thread ends, or its generator is closed):
        the episode ends, no agents left, and a ``step`` asks for ``reset()``."""
        if self._finalizer is not None:
            self._finalizer()  # closes the broker (or the generator) once
            self._finalizer = None
        self._pending = None
        self.agents = []

    def __getstate__(self) -> dict[str, Any]:
        """Picklable before or between episodes (SuperSuit copies envs with cloudpickle):
        the run in progress, if any, is not part of the state."""
        state = self.__dict__.copy()
        for key in self._TRANSIENT:
            state.pop(key, None)
        state["agents"] = []
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._clear()
