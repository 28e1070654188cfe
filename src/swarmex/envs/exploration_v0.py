"""Exploration (seed 003) as a PettingZoo environment: learned policies choose frontier goals.

The environment drives the exploration simulator of ``swarmex.run("exploration", ...)``
unchanged — the true grid, the lasers, the mesh radio with its range, heartbeats, scan
flooding, ``GOAL`` / ``CHANGE_GOAL`` and AODV — in a worker thread
(:class:`~swarmex.envs.broker.DecisionBroker`). The one thing handed to the caller is the
decision the seed's robots take with a strategy: **which frontier cell to head for**, each
time a robot plans (on its 2 s timer, or unscheduled: goal reached, path blocked, a goal
conflict lost, ``CHANGE_GOAL`` received). Everything else a robot does (paths, motion,
messages, conflict resolution by priority) stays the robot's own code.

Native form: **Parallel**. One ``step`` is one decision: the simulation runs (100 ms ticks)
until some robot plans; that robot is the *deciding* agent, the others take the no-op. Robots
that plan in the same tick are asked one after the other, in id order, because that is how
the simulator plans them: each one's ``GOAL`` reaches its neighbours before the next one
chooses, so a later robot's exclusion zones (and whether a conflict makes it re-plan at all)
depend on the earlier robot's choice. ``infos[agent]["tick"]`` says which tick a step is at.
:func:`env` gives the AEC form through PettingZoo's ``parallel_to_aec``.

=====================  ====================================================================
Action                 ``Discrete(H*W + 1)``: ``y*W + x`` = head for cell (x, y) of the map
                       (row-major, the ``belief`` array's flat index); ``H*W`` = no-op
Mask (deciding robot)  the frontier cells it can reach on its own map (free cells next to
                       unknown ones, in regions at least a robot wide, reachable without
                       touching a known obstacle) — exactly the cells its strategy picks from
Mask (other robots)    the no-op only
Observation            ``Dict``: ``belief`` (H, W) uint8, the robot's own occupancy map, 0
                       unknown / 1 free / 2 occupied (full resolution: one entry per action
                       cell); ``position`` (x, y); ``goal`` its current goal (x, y), (-1, -1)
                       if none; ``team_goals`` (n, 2) the goal each neighbour last announced in
                       ``GOAL`` (its exclusion zone: the laser range around it), (-1, -1)
                       when none is fresh (within two planning periods); ``team_positions``
                       (n, 2) each neighbour's cell from its last heartbeat or ``GOAL``
                       (within the neighbour timeout), (-1, -1) otherwise; ``action_mask``
                       (H*W + 1,) int8. A robot's own rows in the team arrays are (-1, -1).
Reward                 shared: ``-0.1`` per elapsed 100 ms tick since the previous step
                       (seconds of exploration time), ``+10`` at the step the team completes
                       (every robot's map has no reachable frontier). An episode's return is
                       ``10·complete − makespan_seconds``.
Termination            every robot has finished (the record's ``complete``)
Truncation             the mission's own cap, ``max_ticks`` (default from the map size)
=====================  ====================================================================

Errors: bad params raise :class:`~swarmex.errors.InputError` as ``swarmex.run`` does. An
action that is not an integer in the space, or masked out (a non-frontier cell; anything but
the no-op for a robot that is not deciding), raises ``ValueError`` naming the agent, the
action and why, and the world is left as it was (the same decision is still pending). With
``invalid_action="project"`` (opt-in, for unmasked samplers such as PettingZoo's
``parallel_seed_test`` or a plain PPO) a masked-out action is replaced instead: a deciding
robot takes the ``a mod k``-th of its ``k`` valid cells (ascending flat index), the others
the no-op. Out-of-space actions raise in both modes.

Baseline and exactness: :func:`baseline_policy` answers each decision with the strategy named
in the params (``greedy``, ``greedy-exclusion``, ``utility``, ``minpos``, ``hungarian``,
``hungarian-exclusion``, ``adaptive-exclusion``),
called on the deciding robot's own :class:`~swarmex.missions.exploration.strategies.GoalContext`
(its map, frontiers and what it heard — :meth:`ExplorationEnv.decision_context`). Strategies
are pure functions that draw no random numbers (the run's generator is used only for the
robots' timer phases, before tick 0), and the goal cell is the whole decision, so no RNG
snapshot is needed: the simulator's robot receives the same cell it would have computed, and
the episode's :meth:`ExplorationEnv.record` equals ``swarmex.run``'s record for the same
params and seed (``wall_seconds`` aside).

Seeding: ``reset(seed=s)`` runs the mission with ``seed=s``; ``reset()`` without a seed uses
the params' ``seed`` first, then the next seed of its
:class:`~swarmex.envs.common.SeedChain` (one new episode per reset; docs/envs.md, Seeds).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv, ParallelEnv

from swarmex.envs.broker import DecisionBroker
from swarmex.envs.common import (
    BrokerEpisodeMixin,
    SeedChain,
    StepReturns,
    check_modes,
    parallel_to_aec,
    plain_int,
)
from swarmex.missions.base import python_spelling
from swarmex.missions.exploration.params import TICK_SECONDS, ExplorationParams
from swarmex.missions.registry import get as get_mission

if TYPE_CHECKING:
    from swarmex.engine.record import ResultRecord
    from swarmex.missions.exploration.mission import ExplorationWorld
    from swarmex.missions.exploration.sim import ExplorationRun
    from swarmex.missions.exploration.strategies import GoalContext

__all__ = [
    "COMPLETION_BONUS",
    "ExplorationEnv",
    "NAME",
    "baseline_policy",
    "env",
    "parallel_env",
    "raw_env",
]

NAME = "exploration_v0"
UNKNOWN, FREE, OCCUPIED = 0, 1, 2  # the belief's cell values
COMPLETION_BONUS = 10.0
INVALID_ACTION_MODES = ("raise", "project")
RENDER_MODES = ("rgb_array",)
Cell = tuple[int, int]


@dataclass
class Decision:
    """The pending decision: which robot plans, at which tick, and its valid goals."""

    robot: int
    t: int
    ctx: GoalContext
    valid: np.ndarray  # ascending flat indices y*W + x of the cells it may choose


class _Live:
    """What the simulator's worker shares with the environment (not the env itself, so an
    abandoned environment can be collected and its worker closed)."""

    run: ExplorationRun | None = None


class ExplorationEnv(BrokerEpisodeMixin, ParallelEnv[str, dict[str, np.ndarray], int]):
    """The native Parallel environment (``raw_env``); see the module docstring."""

    metadata: dict[str, Any] = {  # PettingZoo reads it from the class
        "name": NAME,
        "render_modes": list(RENDER_MODES),
        "is_parallelizable": True,
        "render_fps": 10,
    }

    _TRANSIENT = ("_broker", "_live", "_pending", "_finalizer", "_result")

    def __init__(
        self,
        render_mode: str | None = None,
        invalid_action: str = "raise",
        **params: Any,
    ) -> None:
        check_modes(render_mode, invalid_action, RENDER_MODES, INVALID_ACTION_MODES)
        mission = get_mission("exploration")
        with python_spelling(mission.params_type):
            self.params: ExplorationParams = mission.params(params)
            self.world: ExplorationWorld = mission.prepare(self.params)
        self.render_mode = render_mode
        self.invalid_action = invalid_action
        h, w = self.world.grid.shape
        self.shape = (int(h), int(w))
        self.noop = int(h * w)
        n = self.params.robots
        self.possible_agents = [f"robot_{i}" for i in range(n)]
        self._index = {a: i for i, a in enumerate(self.possible_agents)}
        self._obs_spaces = {a: self._observation_space() for a in self.possible_agents}
        self._act_spaces = {a: spaces.Discrete(h * w + 1) for a in self.possible_agents}
        self.agents: list[str] = []
        self._seeds = SeedChain(self.params.seed)
        self._seed = self.params.seed
        self._clear()

    def _clear(self) -> None:
        self._broker: DecisionBroker | None = None
        self._live = _Live()
        self._pending: Decision | None = None
        self._finalizer: weakref.finalize[Any, Any] | None = None
        self._t = 0
        self._result: ExplorationRun | None = None

    # ------------------------------------------------------------------ spaces
    def _observation_space(self) -> spaces.Dict:
        h, w = self.shape
        n = self.params.robots
        top = np.array([w - 1, h - 1], dtype=np.int64)
        team_top = np.tile(top, (n, 1))
        return spaces.Dict(
            {
                "belief": spaces.Box(0, 2, (h, w), np.uint8),
                "position": spaces.Box(np.zeros(2, np.int64), top, (2,), np.int64),
                "goal": spaces.Box(np.full(2, -1, np.int64), top, (2,), np.int64),
                "team_goals": spaces.Box(np.full((n, 2), -1, np.int64), team_top, (n, 2),
                                         np.int64),
                "team_positions": spaces.Box(np.full((n, 2), -1, np.int64), team_top,
                                             (n, 2), np.int64),
                "action_mask": spaces.Box(0, 1, (h * w + 1,), np.int8),
            }
        )

    # ------------------------------------------------------------------ episode
    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, dict[str, Any]]]:
        """Start a new run (``options`` is accepted and ignored)."""
        self._begin_reset(seed)
        params = replace(self.params, starts=self.world.starts, seed=self._seed)
        grid = self.world.grid
        live = self._live

        def run(ask: Callable[[Any], Any]) -> ExplorationRun:
            from swarmex.missions.exploration.sim import run_exploration

            def on_start(r: ExplorationRun) -> None:
                live.run = r
                cfg = r.robots[0].cfg
                # the robots keep their strategy's flags (exclusion, priorities, rivals);
                # only its choice is asked of the environment's caller (with the whole
                # distance field: no nearest-candidate shortcut, ``candidates``)
                asked = replace(cfg, strategy=replace(cfg.strategy, choose=ask,
                                                      candidates=None))
                for robot in r.robots:
                    robot.cfg = asked

            return run_exploration(grid, params, on_start=on_start)

        self._broker = DecisionBroker(run, name=f"swarmex-{NAME}")
        self._finalizer = weakref.finalize(self, self._broker.close)
        self.agents = self.possible_agents[:]
        self._arrive(self._broker.start())
        if self._pending is None:  # finished without a decision (the first scans saw it all)
            self.agents = []
        return self._observations(), self._infos()

    def step(
        self, actions: Mapping[str, Any]
    ) -> StepReturns:
        if self._pending is None or self._broker is None:
            if not actions:
                return {}, {}, {}, {}, {}
            raise RuntimeError(f"{NAME}: the episode has ended; call reset()")
        cell = self._goal_from(actions)
        t_before = self._t
        self._arrive(self._broker.answer(cell))
        reward = -TICK_SECONDS * (self._t - t_before)
        complete = bool(self._result is not None and self._result.complete)
        return self._step_returns(reward, complete, COMPLETION_BONUS)

    def _arrive(self, request: GoalContext | None) -> None:
        """Take the simulator's next request (None: the run has ended)."""
        if request is None:
            assert self._broker is not None
            self._result = self._broker.result
            self._pending = None
            self._t = int(self._result.makespan) if self._result is not None else self._t
            return
        run = self._live.run
        assert run is not None
        ctx = request
        w = self.shape[1]
        idx = np.nonzero(ctx.eligible)[0]
        valid = ctx.frontiers.ys[idx] * w + ctx.frontiers.xs[idx]
        t = int(run.robots[ctx.me].last_plan_t)
        self._pending = Decision(int(ctx.me), t, ctx, np.sort(valid.astype(np.int64)))
        self._t = t

    def _goal_from(self, actions: Mapping[str, Any]) -> Cell:
        """The deciding robot's goal cell, after checking every agent's action."""
        d = self._pending
        assert d is not None
        decider = self.possible_agents[d.robot]
        for agent in actions:
            if agent not in self._index:
                raise ValueError(f"{NAME}: unknown agent {agent!r} (agents: {self.agents})")
        chosen: int | None = None
        for agent, raw in actions.items():
            a = self._as_action(agent, raw)
            if agent != decider:
                if a != self.noop and self.invalid_action == "raise":
                    raise ValueError(
                        f"{NAME}: {agent} is not deciding now ({decider} is); its only valid "
                        f"action is the no-op {self.noop}, got {a}"
                    )
                continue
            k = int(np.searchsorted(d.valid, a))
            if k < d.valid.size and d.valid[k] == a:
                chosen = a
            elif self.invalid_action == "project":
                chosen = int(d.valid[a % d.valid.size])
            else:
                raise ValueError(f"{NAME}: {agent} chose action {a}: {self._why(d, a)}")
        if chosen is None:
            raise ValueError(
                f"{NAME}: no action for {decider}, the robot deciding at tick {d.t} "
                f"(it must choose one of {d.valid.size} frontier cells)"
            )
        w = self.shape[1]
        return chosen % w, chosen // w

    def _as_action(self, agent: str, raw: Any) -> int:
        value = plain_int(raw)
        if isinstance(value, bool) or not isinstance(value, int) or not (
            0 <= value <= self.noop
        ):
            raise ValueError(
                f"{NAME}: {agent}'s action {raw!r} is outside the action space "
                f"(an integer 0..{self.noop}: a cell y*{self.shape[1]}+x, or {self.noop} for "
                "the no-op)"
            )
        return value

    def _why(self, d: Decision, a: int) -> str:
        if a == self.noop:
            return "the no-op is not allowed for the robot that is deciding; choose a goal"
        w = self.shape[1]
        x, y = a % w, a // w
        return (
            f"cell ({x}, {y}) is not a reachable frontier cell of its map "
            f"({d.valid.size} valid cells; see the observation's action_mask)"
        )

    # ------------------------------------------------------------------ observations
    def _observations(self) -> dict[str, dict[str, np.ndarray]]:
        run = self._live.run
        if run is None:
            return {}
        return {a: self._observe(self._index[a], run) for a in self.possible_agents
                if a in self.agents}

    def _observe(self, i: int, run: ExplorationRun) -> dict[str, np.ndarray]:
        robot = run.robots[i]
        lo = robot.belief.grid.logodds
        belief = (lo < 0).astype(np.uint8)
        belief[lo > 0] = OCCUPIED
        n = len(run.robots)
        t = self._t
        cfg = robot.cfg
        team_goals = np.full((n, 2), -1, np.int64)
        for r, g in robot.belief.team_goals(t, cfg.goal_ttl).items():
            if r != i:
                team_goals[r] = g
        team_pos = np.full((n, 2), -1, np.int64)
        for r, p in robot.belief.team_positions(t, cfg.neighbour_timeout).items():
            if r != i:
                team_pos[r] = p
        mask = np.zeros(self.noop + 1, np.int8)
        d = self._pending
        if d is not None and d.robot == i:
            mask[d.valid] = 1
        else:
            mask[self.noop] = 1
        goal = robot.goal
        return {
            "belief": belief,
            "position": np.array(robot.pos, np.int64),
            "goal": np.array((-1, -1) if goal is None else goal, np.int64),
            "team_goals": team_goals,
            "team_positions": team_pos,
            "action_mask": mask,
        }

    def _infos(self) -> dict[str, dict[str, Any]]:
        d = self._pending
        return {
            a: {"tick": self._t, "deciding": d is not None and self._index[a] == d.robot}
            for a in self.agents
        }

    # ------------------------------------------------------------------ the run's own view
    @property
    def deciding(self) -> str | None:
        """The agent whose decision is pending (None when the episode has ended)."""
        return None if self._pending is None else self.possible_agents[self._pending.robot]

    def decision_context(self, agent: str) -> GoalContext | None:
        """The pending decision's context if ``agent`` is deciding, else None.

        It is built from that robot's own belief only (its map, frontiers, distances, the
        goals and positions it heard): what its strategy sees in the simulator.
        """
        d = self._pending
        if d is None or self.possible_agents[d.robot] != agent:
            return None
        return d.ctx

    def action_of(self, cell: Cell) -> int:
        """The action that heads for ``cell`` = (x, y)."""
        return int(cell[1]) * self.shape[1] + int(cell[0])

    def record(self) -> ResultRecord:
        """The run's ResultRecord (== ``swarmex.run``'s for baseline-driven episodes)."""
        if self._result is None:
            raise RuntimeError(f"{NAME}: record() is available once the episode has ended")
        from swarmex.missions.exploration.record import exploration_record

        return exploration_record(self._result)

    @property
    def run(self) -> ExplorationRun | None:
        """The simulator's run object (for renderers and tests; policies must not read it)."""
        return self._live.run

    # ------------------------------------------------------------------ render, close
    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            import gymnasium

            gymnasium.logger.warn(f"{NAME}: render() without a render_mode")
            return None
        run = self._live.run
        if run is None:
            raise RuntimeError(f"{NAME}: call reset() before render()")
        from swarmex.missions.exploration.frames import snapshot
        from swarmex.viz.exploration import rgb_frame

        h, w = self.shape
        scale = max(1, 240 // max(h, w))
        return rgb_frame(snapshot(self._t, run), run.trajectories, run.grid.free, scale)



raw_env = ExplorationEnv


def parallel_env(**kwargs: Any) -> ExplorationEnv:
    """The native Parallel environment: ``parallel_env(empty="3x3", cell=0.1, robots=2)``."""
    return ExplorationEnv(**kwargs)


def env(**kwargs: Any) -> AECEnv[str, dict[str, np.ndarray], int | None]:
    """The AEC form (PettingZoo's ``parallel_to_aec``, order-enforcing)."""
    return parallel_to_aec(ExplorationEnv(**kwargs))


def baseline_policy(
    environment: ParallelEnv[str, Any, Any] | AECEnv[str, Any, Any],
) -> Callable[[Mapping[str, Any], Mapping[str, Any]], dict[str, int]]:
    """The params' strategy as a policy ``(observations, infos) -> actions`` for the
    parallel env: the deciding robot takes its strategy's goal (computed on its own
    :meth:`ExplorationEnv.decision_context`), every other robot the no-op."""
    from swarmex.missions.exploration.strategies import get_strategy

    base = environment.unwrapped
    if not isinstance(base, ExplorationEnv):
        raise TypeError(f"baseline_policy needs a {NAME} environment, got {base!r}")
    strategy = get_strategy(base.params.strategy)

    def policy(observations: Mapping[str, Any], infos: Mapping[str, Any]) -> dict[str, int]:
        actions = dict.fromkeys(observations, base.noop)
        agent = base.deciding
        if agent is not None and agent in observations:
            ctx = base.decision_context(agent)
            assert ctx is not None
            goal = strategy.choose(ctx)
            if goal is None:  # never, with candidates; kept for safety
                raise RuntimeError(f"{strategy.name} chose no goal for {agent}")
            actions[agent] = base.action_of(goal)
        return actions

    return policy
