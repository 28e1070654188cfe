"""Traversal (seed 000, MADGTA) as a PettingZoo environment.

Every agent must have a job done at every free cell of a grid with obstacles it discovers as
it goes; agents talk over the mission's radio (``comm_range``, ``loss``, ``delay``). This is
the simulator of ``swarmex.run("traversal", ...)`` itself, run unchanged in a worker thread
(:mod:`swarmex.envs.broker`): the policy object the simulator calls is a stub that hands each
agent's decision to the environment's caller.

Native form: **AEC**. Agents decide asynchronously, when they take off, when they reach the
vertex they announced and when a job ends; ``agent_selection`` is the agent whose decision
the simulator is waiting for. The same agent may decide twice in a row, so the Parallel form
is PettingZoo's ``turn_based_aec_to_parallel`` conversion (one agent acts per parallel step;
``aec_to_parallel`` needs agents that act in a fixed cycle, which an event-driven mission does
not have).

Action: ``Discrete(n)``, the agent's next *target vertex* (vertex ``y * width + x`` of cell
``(x, y)``), with an ``action_mask`` of the vertices it may choose: not in its KM (not known
done, not a known obstacle, not claimed by a rival's C05) and reachable on its known graph.
The target is turned into MADGTA's decision: its own vertex -> do the job there (branch 1);
a neighbour -> move there (branch 2); any other vertex -> one step along a shortest path on the
known graph (branch 3, the next hop drawn among the shortest-path neighbours from the run's
generator, as MADGTA draws it). The agent decides again at its next vertex. An agent whose mask
would be empty finishes by itself (the seed algorithm's "no vacant vertex left").

``baseline_policy(env)`` plays the seed algorithm named by ``algorithm`` (madgta, madgta+,
madgta-h, madgta-r, madgta-p, madgta-k, madgta-f, madgta-s, nearest); ``env.unwrapped.record()`` is
then exactly ``swarmex.run``'s record
(docs/envs.md). With ``algorithm="madgta-h"`` an agent also finishes when that policy's own
rule retires it (a cheaper rival does the rest: ``MadgtaH.retires``), whatever the actions;
so does madgta-s's agent with no route in the team plan (``MadgtaP.retires``).

Example::

    from swarmex.envs import traversal_v0
    env = traversal_v0.parallel_env(grid="6x6", obstacles="2,2;3,2", agents=3, seed=1)
    observations, infos = env.reset()
    policy = traversal_v0.baseline_policy(env)
    while env.agents:
        observations, rewards, terminations, truncations, infos = env.step(
            policy(observations, infos))
    record = env.unwrapped.record()       # == swarmex.run("traversal", ..., seed=1)
"""

from __future__ import annotations

import contextlib
import dataclasses
import numbers
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, cast

import gymnasium
import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv, ParallelEnv
from pettingzoo.utils import wrappers

from swarmex.envs.broker import Ask, DecisionBroker
from swarmex.envs.common import SeedChain, TurnBasedParallel
from swarmex.errors import InputError
from swarmex.missions.base import python_spelling

#: what ``observe`` reports per vertex in ``status``
VACANT, DONE, OBSTACLE, CLAIMED = 0, 1, 2, 3
#: algorithms that are sequential policies (``optimal`` is a MILP over the whole mission)
BASELINES = ("madgta", "madgta+", "madgta-h", "madgta-r", "madgta-p", "madgta-k", "madgta-f",
             "madgta-s", "nearest")
INVALID_ACTIONS = ("raise", "project")

Obs = dict[str, np.ndarray]


@dataclass
class _Request:
    """A decision the simulator waits for: agent ``me`` (1-based), its own belief and the
    generator its policy draws tie-breaks from, the mission time and the action mask."""

    me: int
    belief: Any  # TraversalBelief
    rng: np.random.Generator
    t: float
    mask: np.ndarray
    builtin: tuple[Any, Any, int] | None = None  # (Decision, rng state before, target)


class _Stub:
    """The policy object handed to ``run_traversal``: asks the environment for each decision.

    Runs in the simulator's thread. It reads only the deciding agent's belief.
    """

    def __init__(self, env: raw_env, name: str, ask: Ask) -> None:
        self.env = env
        self.name = name
        self.ask = ask
        # a baseline that may stop early (madgta-h) announces it: the agent core reads this
        self.announce_leave = bool(getattr(env._builtin, "announce_leave", False))

    def decide(self, belief: Any, rng: np.random.Generator) -> Any:
        from swarmex.missions.traversal.policies import Decision

        env = self.env
        me = int(belief.me)
        env._decided.add(me)
        env._beliefs[me] = belief
        mask = env._choices(belief)
        retires = getattr(env._builtin, "retires", None)
        # no vacant vertex reachable: Algorithm 1 ends for this agent; or the baseline's own
        # rule stops it early (madgta-h: a cheaper rival does the rest more cheaply;
        # madgta-s: the team plan gives it no route)
        if not mask.any() or (retires is not None and retires(belief)):
            env._finished.append(me)
            return Decision("finish")
        return self.ask(_Request(me, belief, rng, float(belief.now), mask))


class raw_env(AECEnv):  # noqa: N801 - PettingZoo's module convention
    """The traversal mission as an AEC environment (see the module docstring).

    ``params`` are ``swarmex.run("traversal", ...)``'s parameters, with the same names, defaults
    and validation (bad ones raise :class:`~swarmex.errors.InputError`); ``seed`` is the
    default episode seed. ``invalid_action="raise"`` (default) rejects an action outside the
    space or masked out with a ValueError naming the agent, the action and why; ``"project"``
    replaces it by the first allowed vertex at or after it (cyclically) and reports the
    original in ``infos[agent]["invalid_action"]`` (for learners that sample without masks).
    """

    metadata = {  # noqa: RUF012 - PettingZoo reads it from the class
        "name": "traversal_v0",
        "render_modes": ["rgb_array"],
        "render_fps": 4,
        "is_parallelizable": False,
    }

    def __init__(
        self, render_mode: str | None = None, invalid_action: str = "raise", **params: Any
    ) -> None:
        from swarmex.missions.registry import get
        from swarmex.missions.traversal.params import algorithm_name

        super().__init__()
        mission = get("traversal")
        with python_spelling(mission.params_type):
            self.params = mission.params(params)
        if algorithm_name(self.params.algorithm) not in BASELINES:
            raise InputError(
                f"traversal_v0: algorithm {self.params.algorithm!r} is the exact MILP over the "
                f"whole mission, not a policy that decides step by step; choose one of "
                f"{', '.join(BASELINES)}"
            )
        if render_mode is not None and render_mode != "rgb_array":
            raise InputError(
                f"traversal_v0: render_mode {render_mode!r} is not supported (use 'rgb_array')"
            )
        if invalid_action not in INVALID_ACTIONS:
            raise InputError(
                f"traversal_v0: invalid_action must be one of {', '.join(INVALID_ACTIONS)}, "
                f"got {invalid_action!r}"
            )
        self.render_mode = render_mode
        self.invalid_action = invalid_action
        with python_spelling(mission.params_type):
            self.prepared = mission.prepare(self.params)
        self.world = self.prepared.world
        n = int(self.world.graph.n_nodes)
        m = len(self.prepared.nests)
        self.n_vertices, self.n_agents = n, m
        self.possible_agents = [f"agent_{i}" for i in range(1, m + 1)]
        self._index = {a: i for i, a in enumerate(self.possible_agents, start=1)}
        inf = np.inf
        obs_space = spaces.Dict(
            {
                "action_mask": spaces.Box(0, 1, (n,), np.int8),
                "status": spaces.Box(0, 3, (n,), np.int8),
                "position": spaces.Box(-1, n - 1, (1,), np.int64),
                "positions": spaces.Box(-1, n - 1, (m,), np.int64),
                "targets": spaces.Box(-1, n - 1, (m,), np.int64),
                "free_at": spaces.Box(0.0, inf, (m,), np.float64),
                "time": spaces.Box(0.0, inf, (1,), np.float64),
            }
        )
        self.observation_spaces = {a: obs_space for a in self.possible_agents}
        self.action_spaces = {a: spaces.Discrete(n) for a in self.possible_agents}
        from swarmex.missions.traversal.mission import fleet_record

        # each agent's own job and edge seconds (a fleet's rows, else the options)
        rows = fleet_record(self.params, self.prepared)
        self._job_time = {int(r["id"]): float(r["job_time"]) for r in rows}
        self._edge_time = {int(r["id"]): float(r["travel_time"]) for r in rows}
        self._seeds = SeedChain(int(self.params.seed))
        self._broker: DecisionBroker | None = None
        self._fresh_episode_state()

    # ------------------------------------------------------------------ spaces
    def observation_space(self, agent: str) -> gymnasium.Space[Any]:
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> gymnasium.Space[Any]:
        return self.action_spaces[agent]

    # ------------------------------------------------------------------ episode
    def _fresh_episode_state(self) -> None:
        self.agents: list[str] = []
        self.rewards: dict[str, float] = {}
        self._cumulative_rewards: dict[str, float] = {}
        self.terminations: dict[str, bool] = {}
        self.truncations: dict[str, bool] = {}
        self.infos: dict[str, dict[str, Any]] = {}
        self.agent_selection: str = self.possible_agents[0]
        self._request: _Request | None = None
        self._beliefs: dict[int, Any] = {}
        self._decided: set[int] = set()
        self._finished: list[int] = []
        self._costs: dict[int, float] = {}
        self._run: Any = None
        self._run_params: Any = None
        self._builtin: Any = None
        self._now = 0.0
        self._trails: dict[int, list[tuple[float, int]]] = {}
        self._jobs: dict[int, list[tuple[float, int]]] = {}

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> None:
        """Start an episode. ``seed`` is the run's seed; without one, the first episode uses
        the ``seed`` parameter and each later one the next of its
        :class:`~swarmex.envs.common.SeedChain`."""
        from swarmex.missions.traversal.policies import make_policy

        self._stop_run()
        self._fresh_episode_state()
        if seed is not None:
            if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
                raise InputError(f"traversal_v0: seed must be an integer, got {seed!r}")
            if seed < 0:  # numpy's generators refuse it, from the simulator's thread
                raise InputError(f"traversal_v0: seed must be at least 0, got {seed}")
        episode_seed = self._seeds.next(None if seed is None else int(seed))
        p = dataclasses.replace(self.params, seed=episode_seed)
        self._run_params = p
        self._builtin = make_policy(p.algorithm)
        self.agents = self.possible_agents[:]
        self.rewards = dict.fromkeys(self.agents, 0.0)
        self._cumulative_rewards = dict.fromkeys(self.agents, 0.0)
        self.terminations = dict.fromkeys(self.agents, False)
        self.truncations = dict.fromkeys(self.agents, False)
        self.infos = {a: {} for a in self.agents}
        name = p.algorithm  # the record names the spec, options and all (madgta-f@ils=60)
        # the worker thread holds the env only weakly: an env dropped mid-episode without
        # close() is then collected, and its __del__ ends the thread (a strong reference from
        # the waiting thread kept both alive for the life of the process)
        env = cast("raw_env", weakref.proxy(self))
        prepared = self.prepared

        def run(ask: Ask) -> Any:  # a closure without self: the thread keeps no env alive
            from swarmex.missions.traversal.mission import simulate

            return simulate(p, prepared, _Stub(env, name, ask), lambda f: env._on_frame(f))

        self._broker = DecisionBroker(run)
        request = self._broker.start()
        # an agent done before the first decision ends with the first step (after a reset,
        # PettingZoo wants every agent alive)
        self._take(request, first=True)

    def _on_frame(self, frame: Any) -> None:
        """After every start, arrival and job end (simulator thread): the trails drawn by
        ``render`` and the job an agent starts on arrival (it then takes no decision)."""
        a = int(frame.agent)
        if frame.event in ("start", "arrive"):
            x, y = next((x, y) for i, x, y in frame.positions if i == a)
            node = int(self.world.node(round(x), round(y)))
            self._trails.setdefault(a, []).append((float(frame.t), node))
            if frame.event == "arrive" and a not in self._decided:
                self._charge(a, self._job_time[a])
                self._jobs.setdefault(a, []).append((float(frame.t), node))
        self._decided.clear()
        self._now = float(frame.t)

    def _charge(self, me: int, seconds: float) -> None:
        self._costs[me] = self._costs.get(me, 0.0) + seconds

    def _take(self, request: _Request | None, first: bool = False) -> None:
        """Book what happened since the last hand-over and select the next agent."""
        for a in self.agents:
            self.rewards[a] = -self._costs.get(self._index[a], 0.0)
        self._costs.clear()
        if not first:
            for me in self._finished:
                self.terminations[f"agent_{me}"] = True
            self._finished.clear()
        self._request = request
        if request is not None:
            self._now = request.t
            self.agent_selection = f"agent_{request.me}"
        else:
            self._end_of_run()
        self._accumulate_rewards()
        if not first:
            self._deads_step_first()

    def _end_of_run(self) -> None:
        """The simulator returned: every agent still here ends, terminated when the agents
        stopped by themselves, truncated when the mission's event cap stopped the run; each of
        them is charged its own ``job_time + travel_time`` (a fleet row's, else the options')
        per reachable vertex left undone."""
        assert self._broker is not None
        run = self._run = self._broker.result
        missed = int(np.sum(run.job_count[run.reachable] == 0))
        self._finished.clear()
        for a in self.agents:
            if not (self.terminations[a] or self.truncations[a]):
                if run.stopped_early:
                    self.truncations[a] = True
                else:
                    self.terminations[a] = True
                me = self._index[a]
                self.rewards[a] -= missed * (self._job_time[me] + self._edge_time[me])

    def step(self, action: Any) -> None:
        agent = self.agent_selection
        if self.terminations[agent] or self.truncations[agent]:
            self._was_dead_step(action)
            return
        request = self._request
        if request is None or self._broker is None:  # closed mid-run (python -O drops asserts)
            raise RuntimeError("traversal_v0: the episode has ended; call reset()")
        target = self._check(agent, action, request)
        decision = self._decision(request, target)
        self._cumulative_rewards[agent] = 0.0
        self._clear_rewards()
        for a in self.agents:
            self.infos[a] = {}
        if not _is_action(action, target):  # projected (an array action compares elementwise)
            self.infos[agent]["invalid_action"] = action
        next_request = self._broker.answer(decision)
        self._take(next_request)

    # ------------------------------------------------------------------ decisions
    def _choices(self, belief: Any) -> np.ndarray:
        """The action mask of a deciding agent: vertices not in its KM, reachable on its
        known graph (its own vertex included when vacant)."""
        mask = np.zeros(self.n_vertices, dtype=np.int8)
        vacant = np.flatnonzero(~belief.km_mask())
        if vacant.size:
            d = belief.known.distances(belief.here, vacant)
            mask[vacant[np.isfinite(d)]] = 1
        return mask

    def _check(self, agent: str, action: Any, request: _Request) -> int:
        n = self.n_vertices
        raw = action
        if isinstance(raw, np.ndarray) and raw.size == 1:
            raw = raw.reshape(()).item() if raw.dtype.kind in "iu" else raw
        if isinstance(raw, bool | np.bool_) or not isinstance(raw, numbers.Integral):
            if self.invalid_action == "project":
                raw = 0
            else:
                raise ValueError(
                    f"traversal_v0: {agent}: action {action!r} is not a vertex number "
                    f"(expected an integer in [0, {n}))"
                )
        a = int(raw)
        if 0 <= a < n and request.mask[a]:
            return a
        if self.invalid_action == "project":
            allowed = np.flatnonzero(request.mask)
            after = allowed[allowed >= a % n]
            return int(after[0] if after.size else allowed[0])
        if not 0 <= a < n:
            raise ValueError(
                f"traversal_v0: {agent}: action {a} is outside the action space "
                f"Discrete({n}) (vertex y * {self.world.width} + x of cell x,y)"
            )
        x, y = self.world.xy(a)
        raise ValueError(
            f"traversal_v0: {agent} may not choose vertex {a} (cell {x},{y}) at "
            f"t = {request.t:g} s: {self._why(request, a)}; choose a vertex whose "
            f"action_mask entry is 1"
        )

    def _why(self, request: _Request, v: int) -> str:
        b = request.belief
        st, holder = int(b.status[v]), int(b.reserved[v])
        if st == -1:
            return "it knows the cell is an obstacle"
        if st > 0:
            return "it knows the job there is done (or under way)"
        if holder not in (0, request.me):
            return f"agent_{holder} has announced it as its next vertex"
        return "it is not reachable on the graph the agent knows"

    @property
    def deciding(self) -> str | None:
        """The agent whose decision the simulator waits for (None once the run has ended)."""
        return None if self._request is None else f"agent_{self._request.me}"

    def builtin_action(self, agent: str | None = None) -> int:
        """The seed algorithm's choice (``algorithm`` of the params) for the pending decision.

        Computed from the deciding agent's own belief with its policy's own generator (the
        draws are undone unless the agent then takes exactly this action). ``agent`` defaults
        to ``agent_selection``; asking for an agent that is not deciding is a ValueError.
        """
        request = self._request
        if request is None or (agent is not None and agent != f"agent_{request.me}"):
            raise ValueError(f"traversal_v0: no decision of {agent or 'any agent'} is pending")
        return self._builtin_decision(request)[2]

    def _builtin_decision(self, request: _Request) -> tuple[Any, Any, int]:
        if request.builtin is None:
            before = request.rng.bit_generator.state
            d = self._builtin.decide(request.belief, request.rng)
            target = d.node if d.kind == "job" else d.target
            request.builtin = (d, before, int(target))
        return request.builtin

    def _may_be_builtin(self, request: _Request, target: int) -> bool:
        """False when MADGTA's branches 1-2 (shared by every baseline) cannot pick ``target``:
        a vacant own vertex is always taken, else a vacant neighbour if there is one."""
        if not getattr(self._builtin, "madgta_branch2", True):
            return True  # its branch 2 is its own (madgta-h): always ask it
        b = request.belief
        here = int(b.here)
        if request.mask[here]:
            return target == here
        nbrs = b.graph.neighbors(here)
        vacant = nbrs[request.mask[nbrs] == 1]
        return not vacant.size or bool(np.any(vacant == target))

    def _decision(self, request: _Request, target: int) -> Any:
        """The Decision for ``target``: the built-in one when it chose the same target (same
        draws, same branch counters), else MADGTA's three branches applied to ``target``."""
        from swarmex.missions.traversal.policies import decision_towards

        if request.builtin is not None or self._may_be_builtin(request, target):
            d, before, chosen = self._builtin_decision(request)
            if chosen == target:
                self._book(request, d)
                return d
            request.rng.bit_generator.state = before  # undo the built-in policy's draws
            request.builtin = None
        d = decision_towards(request.belief, target, request.rng)
        self._book(request, d)
        return d

    def _book(self, request: _Request, d: Any) -> None:
        """Charge the decision's seconds (a job, or the edge it starts on) to the agent."""
        from swarmex.missions.traversal.agent import edge_length

        b, me = request.belief, request.me
        if d.kind == "job":
            self._charge(me, float(b.job_time[me]))
            self._jobs.setdefault(me, []).append((request.t, int(d.node)))
        elif d.kind == "move":
            self._charge(me, edge_length(b.graph, b.here, d.node) * float(b.time_per_unit[me]))

    # ------------------------------------------------------------------ observations
    def observe(self, agent: str) -> Obs:
        n, m = self.n_vertices, self.n_agents
        me = self._index[agent]
        b = self._beliefs.get(me)
        mask = np.zeros(n, dtype=np.int8)
        request = self._request
        if request is not None and request.me == me:
            mask[:] = request.mask
        time = np.array([self._now], dtype=np.float64)
        if b is None:  # not started yet: it knows nothing and is nowhere
            return {
                "action_mask": mask,
                "status": np.zeros(n, dtype=np.int8),
                "position": np.full(1, -1, dtype=np.int64),
                "positions": np.full(m, -1, dtype=np.int64),
                "targets": np.full(m, -1, dtype=np.int64),
                "free_at": np.zeros(m, dtype=np.float64),
                "time": time,
            }
        st = b.status
        status = np.zeros(n, dtype=np.int8)
        status[st > 0] = DONE
        status[st == -1] = OBSTACLE
        rv = b.reserved
        status[(st == 0) & (rv != 0) & (rv != me)] = CLAIMED
        targets = np.array(b.next_loc[1:], dtype=np.int64)
        targets[me - 1] = -1
        free_at = np.maximum(np.array(b.free_at[1:], dtype=np.float64), 0.0)
        free_at[me - 1] = 0.0
        return {
            "action_mask": mask,
            "status": status,
            "position": np.array([b.loc[me]], dtype=np.int64),
            "positions": np.array(b.loc[1:], dtype=np.int64),
            "targets": targets,
            "free_at": free_at,
            "time": time,
        }

    # ------------------------------------------------------------------ results
    def record(self) -> Any:
        """The ended episode's ResultRecord: ``swarmex.run``'s record of the same run."""
        from swarmex.missions.traversal import traversal_record
        from swarmex.missions.traversal.mission import record_params

        if self._run is None:
            raise RuntimeError("traversal_v0: the episode has not ended; no record yet")
        return traversal_record(
            self._run, record_params(self._run_params, self.prepared), self.prepared.unit_length
        )

    def render(self) -> np.ndarray | None:
        """``rgb_array``: the run so far, drawn by :mod:`swarmex.viz.traversal` (the frame
        its animation shows at the current mission time)."""
        if self.render_mode is None:
            gymnasium.logger.warn("traversal_v0: render() without a render_mode")
            return None
        return self._draw()

    def _draw(self) -> np.ndarray:
        from swarmex.viz.traversal import traversal_frame

        pos = self.world.graph.pos
        agents = []
        for i in range(1, self.n_agents + 1):
            trail = [[t, *pos[v].tolist()] for t, v in self._trails.get(i, [])]
            jobs = [[t, *pos[v].tolist()] for t, v in self._jobs.get(i, [])]
            agents.append({"id": i, "trajectory": trail, "jobs": jobs})
        algorithm = self.params.algorithm
        record = {"agents": agents, "algorithm": algorithm}
        title = f"traversal_v0 · {algorithm} · t = {self._now:,.1f} s"
        return traversal_frame(record, self.world, self._now + 1e-9, title)

    # ------------------------------------------------------------------ lifecycle
    def _stop_run(self) -> None:
        if self._broker is not None:
            self._broker.close()
            self._broker = None

    def close(self) -> None:
        """Abandon a run in progress: its thread ends, and so does the episode (no agents
        left; a ``step`` asks for ``reset()``). ``record()`` of a finished run still works."""
        self._stop_run()
        self._request = None
        self.agents = []

    def __getstate__(self) -> dict[str, Any]:
        """Pickles as a fresh, not yet reset environment (a run's thread cannot be copied)."""
        state = self.__dict__.copy()
        state["_broker"] = None
        for key in ("_request", "_run", "_builtin"):
            state[key] = None
        state["_beliefs"], state["_trails"], state["_jobs"] = {}, {}, {}
        return state

    def __del__(self) -> None:
        with contextlib.suppress(Exception):  # best effort, also at interpreter shutdown
            self._stop_run()


def env(**params: Any) -> AECEnv:
    """The AEC environment, checked by PettingZoo's order-enforcing wrapper."""
    return wrappers.OrderEnforcingWrapper(raw_env(**params))


def parallel_env(**params: Any) -> ParallelEnv:
    """The Parallel form: one agent (the one the mission waits for) acts per step; the
    actions given for the other agents are ignored (``env.unwrapped.deciding`` names the agent
    that acts; so does ``infos[agent]["active_agent"]`` after a step)."""
    return TurnBasedParallel(env(**params))


def baseline_policy(env: Any) -> Callable[[dict[str, Any], dict[str, Any]], dict[str, int]]:
    """The seed algorithm of the env's ``algorithm`` param as a parallel-env policy.

    Returns ``policy(observations, infos) -> actions``: the deciding agent gets the built-in
    algorithm's target, computed from its own belief (``raw_env.builtin_action``); the other
    agents, whose actions the env ignores, get vertex 0. Works on the AEC env too
    (``policy({agent: obs}, {})[agent]``) and on :func:`vector_env_ready`.
    """
    raw = env.unwrapped

    def policy(observations: dict[str, Any], infos: dict[str, Any]) -> dict[str, int]:
        actions = dict.fromkeys(observations, 0)
        deciding = raw.deciding
        if deciding is not None:
            actions[deciding] = raw.builtin_action()
        return actions

    return policy


class VectorReady(ParallelEnv):
    """A Parallel traversal env that SuperSuit's vector constructors accept.

    ``pettingzoo_env_to_vec_env_v1`` needs every possible agent present in every step and one
    Box observation; traversal agents finish one by one and observe a Dict. This wrapper keeps
    every agent until the episode ends (an agent that finished observes zeros, gets reward 0,
    and its actions are ignored; all agents end together) and flattens the observation into a
    float32 vector ``[action_mask (n), status (n), position (1), positions (m), targets (m),
    free_at (m), time (1)]``, so ``obs[:n]`` is the action mask (also in
    ``infos[agent]["action_mask"]``).
    """

    metadata = raw_env.metadata

    def __init__(self, par: Any) -> None:
        self.env = par
        raw = par.unwrapped
        self.possible_agents = list(par.possible_agents)
        self.agents: list[str] = []
        self.render_mode = raw.render_mode
        n, m = raw.n_vertices, raw.n_agents
        self._n, self._m = n, m
        inf = np.inf
        low = np.concatenate([np.zeros(2 * n), [-1.0], np.full(2 * m, -1.0), np.zeros(m + 1)])
        high = np.concatenate(
            [np.ones(n), np.full(n, 3.0), [n - 1.0], np.full(2 * m, n - 1.0), np.full(m + 1, inf)]
        )
        self._space = spaces.Box(low.astype(np.float32), high.astype(np.float32), dtype=np.float32)
        self._ended: dict[str, tuple[bool, bool]] = {}

    @property
    def unwrapped(self) -> Any:
        return self.env.unwrapped

    def observation_space(self, agent: str) -> gymnasium.Space[Any]:
        return self._space

    def action_space(self, agent: str) -> gymnasium.Space[Any]:
        return self.env.action_space(agent)

    def _flat(self, obs: Obs | None) -> np.ndarray:
        if obs is None:
            return np.zeros(self._space.shape, dtype=np.float32)
        return np.concatenate(
            [
                obs["action_mask"],
                obs["status"],
                obs["position"],
                obs["positions"],
                obs["targets"],
                obs["free_at"],
                obs["time"],
            ]
        ).astype(np.float32)

    def _infos(self, obs: dict[str, Obs], infos: dict[str, Any]) -> dict[str, Any]:
        out = {}
        for a in self.possible_agents:
            o = obs.get(a)
            mask = o["action_mask"] if o is not None else np.zeros(self._n, dtype=np.int8)
            out[a] = {**infos.get(a, {}), "action_mask": mask}
        return out

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        obs, infos = self.env.reset(seed=seed, options=options)
        self.agents = self.possible_agents[:]
        self._ended = {}
        return {a: self._flat(obs.get(a)) for a in self.agents}, self._infos(obs, infos)

    def step(self, actions: dict[str, Any]) -> tuple[dict[str, Any], ...]:
        live = set(self.env.agents)
        obs, rew, term, trunc, infos = self.env.step(
            {a: act for a, act in actions.items() if a in live}
        )
        for a in self.possible_agents:
            if term.get(a) or trunc.get(a):
                self._ended.setdefault(a, (bool(term.get(a)), bool(trunc.get(a))))
        over = not self.env.agents
        flat = {
            a: self._flat(None if a in self._ended and not over else obs.get(a))
            for a in self.possible_agents
        }
        if over:
            terms = {a: self._ended.get(a, (True, False))[0] for a in self.possible_agents}
            truncs = {a: self._ended.get(a, (False, True))[1] for a in self.possible_agents}
            self.agents = []
        else:
            terms = dict.fromkeys(self.possible_agents, False)
            truncs = dict.fromkeys(self.possible_agents, False)
        rewards = {a: float(rew.get(a, 0.0)) for a in self.possible_agents}
        return flat, rewards, terms, truncs, self._infos(obs, infos)

    def render(self) -> Any:
        return self.env.render()

    def close(self) -> None:
        self.env.close()


def vector_env_ready(**params: Any) -> Any:
    """:func:`parallel_env` wrapped in :class:`VectorReady`, for SuperSuit.

    Example: ``supersuit.concat_vec_envs_v1(supersuit.pettingzoo_env_to_vec_env_v1(
    traversal_v0.vector_env_ready(grid="8x8", agents=4)), num_vec_envs=2, num_cpus=0)``.
    """
    return VectorReady(parallel_env(**params))



def _is_action(action: Any, target: int) -> bool:
    """Whether ``action`` is the integer ``target`` (a 0-d or one-element integer array too)."""
    try:
        arr = np.asarray(action)
    except (TypeError, ValueError):
        return False
    return arr.size == 1 and arr.dtype.kind in "iu" and int(arr.reshape(()).item()) == target

__all__ = [
    "BASELINES",
    "VectorReady",
    "baseline_policy",
    "env",
    "parallel_env",
    "raw_env",
    "vector_env_ready",
]
