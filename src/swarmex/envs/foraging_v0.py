"""Foraging (seed 002) as a PettingZoo environment: every robot chooses its move every round.

The environment drives the foraging run of ``swarmex.run("foraging", ...)`` — the pattern's
timetable, the Look phase (sensing the food, telling robots at distance ≤ 1, pick-up, drop,
relay hand-over), the communication and transport rules and the collision resolution of
:mod:`swarmex.missions.foraging.resolve`. The one thing handed to the caller is the Compute of
each synchronous Look-Compute-Move round: **which move each robot makes**. The run is the
mission's *hooked* run (:mod:`swarmex.missions.foraging.hook`), a generator that stops at every
round's Compute with every robot's seed move and resumes with the moves the caller chose; the
moves are then made collision-free together, by the mission's own resolution, and applied.
``step`` resumes it for one round in the caller's own thread (no worker thread).

Native form: **Parallel** (synchronous rounds: every robot acts every round; one ``step`` is
one round). :func:`env` gives the AEC form through PettingZoo's ``parallel_to_aec``.

=====================  ====================================================================
Action                 ``Discrete(5)``: 0 stay, 1 North (y − 1), 2 East (x + 1), 3 South
                       (y + 1), 4 West (x − 1); (0, 0) is the top-left cell
Mask                   stay, and each move that stays on the g×g grid
Observation            ``Dict`` of what the robot knows: ``position`` (x, y); ``carrying``
                       (1,) 0/1; ``informed`` (1,) 0/1, whether it knows where the food is;
                       ``food`` (x, y) if it knows, (−1, −1) otherwise; ``nest`` (x, y);
                       ``round`` (1,); ``mode`` (1,) its phase (:data:`MODES`); ``to_tell``
                       (n,) 0/1, the pattern neighbours it still has to tell;
                       ``team_positions`` (n, 2), the cells of the robots within its sensing
                       distance (:data:`SENSING`, Manhattan), (−1, −1) for the others and its
                       own row; ``action_mask`` (5,) int8. The arrays are read-only
                       (several are shared between robots and rounds): copy one to change it
Reward                 shared by the team: ``delivery_reward`` (1) per unit that reaches the
                       nest in the round, − ``time_cost`` (0.01) per round, + ``completion_bonus``
                       (10) at the round the k-th unit is home
Termination            all k units are in the nest (the record's ``complete``)
Truncation             ``max_rounds`` (default: the mission's own round limit,
                       ``200·g·(k + g) + 10 000``): the run is stopped there (the mission's
                       ``StopRun``) and its record is incomplete
=====================  ====================================================================

Errors: bad params raise :class:`~swarmex.errors.InputError` as ``swarmex.run`` does. An action
that is not an integer of the space, a missing action, or a masked-out move (off the grid)
raises ``ValueError`` naming the agent, the action and why, and the world is left as it was
(the same round is still pending). With ``invalid_action="project"`` (opt-in, for samplers
that ignore the mask, such as PettingZoo's ``parallel_seed_test``) a masked-out move is
replaced by *stay* (a robot that walks into the border stays put). Out-of-space actions raise in
both modes.

Baseline and exactness: in each round's Compute the mission computes every robot's options,
the seed's ordered wishes (its route's next cell, a walk toward the neighbour it must tell,
the relay or End-to-End transport move, or — for an idle robot — staying and yielding its
cell), and the env offers the first one's direction as that robot's *built-in* action
(:meth:`ForagingEnv.baseline_actions`); :func:`baseline_policy` returns them. A robot whose
action equals its built-in one keeps the seed's whole decision (its fallbacks and its rank as
a route follower in the resolution); any other action becomes the wish "that cell, else stay"
with no route-follower rank (:mod:`swarmex.missions.foraging.hook`). The mission draws no
random numbers after placing the food (in ``prepare``, before round 0), so no generator
snapshot is needed: a baseline-driven episode
plays exactly the rounds of ``swarmex.run``, and :meth:`ForagingEnv.record` equals its record
(``wall_seconds`` aside). With a decision hook the run is played round by round from round 0
to the end (the timetable's rounds and the transport tail included, which ``swarmex.run`` plays
from a table and in a many-rounds compiled loop): by the mission's Python round loop, and by
compiled ports of that loop's round before anyone knows the food and once everyone transports
(the module docstring of :mod:`swarmex.missions.foraging.sim` says why the rounds are the same).

Speed: one ``step`` of 16 robots costs about 40 µs of CPU in those compiled phases (the
observations about 12 of them) and about 140 µs in the communication phase's Python rounds;
``bench/bench_envs.py`` compares it with POGEMA (docs/envs.md).

Seeding: ``reset(seed=s)`` runs the mission with ``seed=s`` (which draws the food cell when
``food`` is not given); ``reset()`` without a seed uses the params' ``seed`` first, then the
next seed of its :class:`~swarmex.envs.common.SeedChain` (one new episode per reset;
docs/envs.md, Seeds).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Generator, Mapping
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv, ParallelEnv

from swarmex.envs.common import (
    BrokerEpisodeMixin,
    SeedChain,
    StepReturns,
    check_finite,
    check_modes,
    parallel_to_aec,
    plain_int,
)
from swarmex.errors import InputError
from swarmex.missions.base import python_spelling
from swarmex.missions.foraging.hook import STAY, STEPS
from swarmex.missions.foraging.sim import COMM, FOLLOW, TRANSPORT, Compute
from swarmex.missions.registry import get as get_mission
from swarmex.sensing.teammates import team_view

if TYPE_CHECKING:
    from swarmex.engine.record import ResultRecord
    from swarmex.missions.foraging.mission import ForagingWorld
    from swarmex.missions.foraging.params import ForagingParams
    from swarmex.missions.foraging.run import ForageRun
    from swarmex.missions.foraging.sim import Mission

    Rounds = Generator[Compute, np.ndarray, ForageRun]

__all__ = [
    "ACTIONS",
    "MODES",
    "SENSING",
    "ForagingEnv",
    "NAME",
    "baseline_policy",
    "env",
    "parallel_env",
    "raw_env",
]

NAME = "foraging_v0"
ACTIONS = ("stay", "north", "east", "south", "west")
MOVES = np.array(STEPS, dtype=np.int64)  # (dx, dy) of each action (the mission's move codes)
# a robot's phase: the mission's modes, the transport ones split by how it transports
MODES = ("explore", "follow", "communicate", "join", "relay", "end-to-end", "idle")
SENSING = 2  # robots seen within this Manhattan distance (what collision avoidance looks at)
INVALID_ACTION_MODES = ("raise", "project")
RENDER_MODES = ("rgb_array",)
Cell = tuple[int, int]


class ForagingEnv(BrokerEpisodeMixin, ParallelEnv[str, dict[str, np.ndarray], int]):
    """The native Parallel environment (``raw_env``); see the module docstring.

    Keyword arguments: the mission's parameters (the names and checks of
    ``swarmex.run("foraging", ...)``: ``grid``, ``agents``, ``algorithm``, ``transport``,
    ``food``, ``food_distance``, ``food_units``, ``seed``), plus ``render_mode`` (None or
    "rgb_array"), ``invalid_action`` ("raise" or "project"), ``max_rounds`` (truncation) and
    the reward's terms ``delivery_reward``, ``time_cost``, ``completion_bonus``.
    """

    metadata: dict[str, Any] = {  # PettingZoo reads it from the class
        "name": NAME,
        "render_modes": list(RENDER_MODES),
        "is_parallelizable": True,
        "render_fps": 10,
    }

    _TRANSIENT = (
        "_rounds", "_mission", "_pending", "_pos", "_cells", "_finalizer", "_result",
        "_record", "_run_params", "_world",
    )  # fmt: skip

    def __init__(
        self,
        render_mode: str | None = None,
        invalid_action: str = "raise",
        max_rounds: int | None = None,
        delivery_reward: float = 1.0,
        time_cost: float = 0.01,
        completion_bonus: float = 10.0,
        **params: Any,
    ) -> None:
        check_modes(render_mode, invalid_action, RENDER_MODES, INVALID_ACTION_MODES)
        check_finite(
            ("delivery_reward", delivery_reward),
            ("time_cost", time_cost),
            ("completion_bonus", completion_bonus),
        )
        mission = get_mission("foraging")
        with python_spelling(mission.params_type):
            self.params: ForagingParams = mission.params(params)
        p = self.params
        g, n, k = p.grid, p.agents, p.food_units
        limit = 200 * g * (k + g) + 10_000  # the mission's own round limit (sim.Mission.run)
        if max_rounds is None:
            max_rounds = limit
        elif (
            isinstance(max_rounds, bool)
            or not isinstance(max_rounds, int | np.integer)
            or not 1 <= max_rounds <= limit
        ):
            raise InputError(
                f"max_rounds must be an integer from 1 to the mission's limit {limit:,} "
                f"(200·g·(k + g) + 10 000), got {max_rounds!r}"
            )
        self.max_rounds = int(max_rounds)
        self.render_mode = render_mode
        self.invalid_action = invalid_action
        self.delivery_reward = float(delivery_reward)
        self.time_cost = float(time_cost)
        self.completion_bonus = float(completion_bonus)
        self.g = g
        self.nest: Cell = p.nest
        self.possible_agents = [f"robot_{i}" for i in range(n)]
        self._index = {a: i for i, a in enumerate(self.possible_agents)}
        space = self._observation_space()
        self._obs_spaces = dict.fromkeys(self.possible_agents, space)
        self._act_spaces = {a: spaces.Discrete(len(ACTIONS)) for a in self.possible_agents}
        xs, ys = np.meshgrid(np.arange(g), np.arange(g), indexing="ij")  # [x, y]
        self._cell_masks = np.stack(
            [np.ones_like(xs, dtype=bool), ys > 0, xs < g - 1, ys < g - 1, xs > 0], axis=2
        ).astype(np.int8)  # (g, g, 5): the action mask of a robot at cell (x, y)
        self._shared_arrays()
        self.agents: list[str] = []
        self._seeds = SeedChain(p.seed)
        self._seed = p.seed
        self._clear()

    def _clear(self) -> None:
        self._rounds: Rounds | None = None
        self._mission: Mission | None = None
        self._pending: Compute | None = None
        self._pos: np.ndarray | None = None  # (n, 2) int64: the cells, after the last Look
        self._cells: list[int] = []  # the same cells as x·g + y
        self._food_obs = self._unknown_food  # the food cell, set when a run starts
        self._finalizer: weakref.finalize[Any, Any] | None = None
        self._run_params: ForagingParams | None = None
        self._world: ForagingWorld | None = None
        self._result: ForageRun | None = None
        self._record: ResultRecord | None = None
        self._delivered = 0

    # ------------------------------------------------------------------ spaces
    def _observation_space(self) -> spaces.Dict:
        g, n = self.g, self.params.agents
        top = np.array([g - 1, g - 1], dtype=np.int64)

        def box(low: Any, high: Any, shape: tuple[int, ...], dtype: Any) -> spaces.Box:
            return spaces.Box(low, high, shape, dtype)

        return spaces.Dict(
            {
                "position": box(np.zeros(2, np.int64), top, (2,), np.int64),
                "carrying": box(0, 1, (1,), np.int8),
                "informed": box(0, 1, (1,), np.int8),
                "food": box(np.full(2, -1, np.int64), top, (2,), np.int64),
                "nest": box(np.zeros(2, np.int64), top, (2,), np.int64),
                "round": box(0, self.max_rounds, (1,), np.int64),
                "mode": box(0, len(MODES) - 1, (1,), np.int8),
                "to_tell": box(0, 1, (n,), np.int8),
                "team_positions": box(-1, g - 1, (n, 2), np.int64),
                "action_mask": box(0, 1, (len(ACTIONS),), np.int8),
            }
        )

    # ------------------------------------------------------------------ episode
    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, dict[str, Any]]]:
        """Start a new run (``options`` is accepted and ignored)."""
        self._begin_reset(seed)
        mission = get_mission("foraging")
        params: ForagingParams = replace(self.params, seed=self._seed)
        with python_spelling(mission.params_type):
            world: ForagingWorld = mission.prepare(params)  # draws the food from the seed
        self._run_params, self._world = params, world
        self._food_obs = np.array(world.food, dtype=np.int64)
        self._food_obs.flags.writeable = False
        from swarmex.missions.foraging.run import forage_rounds

        p = params
        rounds = forage_rounds(
            p.algorithm, p.grid, p.agents, world.food, p.food_units, p.transport,
            comm=p.comm, stop_at=self.max_rounds, found=p.found,
        )  # fmt: skip
        self._rounds = rounds
        self._finalizer = weakref.finalize(self, rounds.close)
        self.agents = self.possible_agents[:]
        self._advance(None)
        obs, infos = self._observations(), self._infos()
        if self._pending is None:  # ended before any Compute (cannot happen: kept for safety)
            self.agents = []
        return obs, infos

    def step(
        self, actions: Mapping[str, Any]
    ) -> StepReturns:
        if self._pending is None or self._rounds is None:
            if not actions:
                return {}, {}, {}, {}, {}
            raise RuntimeError(f"{NAME}: the episode has ended; call reset()")
        moves = self._moves_from(actions)
        before = self._delivered
        self._advance(moves)
        reward = self.delivery_reward * (self._delivered - before) - self.time_cost
        complete = bool(self._result is not None and self._result.outcome.complete)
        return self._step_returns(reward, complete, self.completion_bonus)

    def _advance(self, moves: np.ndarray | None) -> None:
        """Resume the run with ``moves`` (None: start it) up to its next Compute or its end."""
        assert self._rounds is not None
        try:
            request = self._rounds.send(moves)  # type: ignore[arg-type]
        except StopIteration as stop:
            self._result = stop.value
            self._pending = None
            if self._finalizer is not None:
                self._finalizer.detach()
                self._finalizer = None
            m = self._mission
            if m is not None:
                self._delivered = m.delivered
                self._locate(np.array(m.pos, dtype=np.int64).reshape(m.n, 2))
            return
        m = self._mission = request.mission
        self._delivered = m.delivered
        self._pending = request
        self._locate(request.positions)

    def _locate(self, pos: np.ndarray) -> None:
        """Take the robots' cells, an (n, 2) array (the state after the last Look)."""
        self._pos = pos
        self._cells = (pos[:, 0] * self.g + pos[:, 1]).tolist()

    def _moves_from(self, actions: Mapping[str, Any]) -> np.ndarray:
        """Every robot's move as an (n,) array, after checking every action. The usual case
        (every robot, plain ints in the space, all on the grid) is a few Python-level passes
        over n values, no numpy until the result."""
        agents = self.possible_agents
        if actions.keys() != self._index.keys():
            for agent in actions:
                if agent not in self._index:
                    raise ValueError(f"{NAME}: unknown agent {agent!r} (agents: {self.agents})")
            missing = [a for a in agents if a not in actions]
            raise ValueError(
                f"{NAME}: no action for {', '.join(missing)}: every robot moves every round "
                f"(0 stay, 1 N, 2 E, 3 S, 4 W)"
            )
        raw = list(map(actions.__getitem__, agents))
        if set(map(type, raw)) != {int} or min(raw) < 0 or max(raw) >= len(ACTIONS):
            raw = [self._as_action(a, v) for a, v in zip(agents, raw, strict=True)]
        # on the grid: the (cell, action) table, indexed by 5·cell + action
        on_grid = self._on_grid
        if all([on_grid[5 * c + a] for c, a in zip(self._cells, raw, strict=True)]):
            return np.array(raw, dtype=np.int64)
        moves = np.array(raw, dtype=np.int64)
        ok = np.array([on_grid[5 * c + a] for c, a in zip(self._cells, raw, strict=True)])
        if self.invalid_action == "project":
            moves[~ok] = STAY
            return moves
        i = int(np.flatnonzero(~ok)[0])
        raise ValueError(f"{NAME}: {agents[i]} {self._why(i, moves[i])}")

    def _as_action(self, agent: str, raw: Any) -> int:
        value = plain_int(raw)
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < len(ACTIONS):
            raise ValueError(
                f"{NAME}: {agent}'s action {raw!r} is outside the action space "
                "(an integer 0..4: 0 stay, 1 north, 2 east, 3 south, 4 west)"
            )
        return value

    def _why(self, i: int, a: int) -> str:
        d, pos = self._pending, self._pos
        assert d is not None and pos is not None
        x, y = (int(v) for v in pos[i])
        dx, dy = (int(v) for v in MOVES[a])
        return (
            f"chose action {a} ({ACTIONS[a]}) at cell ({x}, {y}) in round {d.t}: cell "
            f"({x + dx}, {y + dy}) is off the {self.g}×{self.g} grid (see the action_mask)"
        )

    # ------------------------------------------------------------------ observations
    def _shared_arrays(self) -> None:
        """The observation arrays that take few values, made once, read-only and shared by
        every robot and round that shows that value (a step then allocates only the team's
        positions, the round and the lists of robots still to tell)."""
        g, n = self.g, self.params.agents

        def frozen(values: Any, dtype: Any) -> np.ndarray:
            a = np.array(values, dtype=dtype)
            a.flags.writeable = False
            return a

        self._cell_pos = [frozen((x, y), np.int64) for x in range(g) for y in range(g)]
        self._on_grid: list[bool] = self._cell_masks.reshape(-1).astype(bool).tolist()
        self._cell_mask = [frozen(self._cell_masks[x, y], np.int8)
                           for x in range(g) for y in range(g)]  # fmt: skip
        self._flag = (frozen((0,), np.int8), frozen((1,), np.int8))
        self._phase = [frozen((k,), np.int8) for k in range(len(MODES))]
        self._nest_obs = frozen(self.nest, np.int64)
        self._unknown_food = frozen((-1, -1), np.int64)
        self._nobody = frozen(np.zeros(n), np.int8)

    def _observations(self) -> dict[str, dict[str, np.ndarray]]:
        m = self._mission
        pos = self._pos
        if m is None or pos is None or not self.agents:
            return {}
        # the team's positions as each robot sees them: one (n, n, 2) array, a row per robot
        team = team_view(pos, SENSING)
        team.flags.writeable = False
        t = np.array((m.t,), dtype=np.int64)
        t.flags.writeable = False
        food = self._food_obs
        cell_pos, cell_mask, flag, phase = self._cell_pos, self._cell_mask, self._flag, self._phase
        nest, unknown, nobody = self._nest_obs, self._unknown_food, self._nobody
        out: dict[str, dict[str, np.ndarray]] = {}
        for i, (agent, c, row, informed, carrying, mode, tmode) in enumerate(zip(
            self.possible_agents, self._cells, team, m.informed, m.carrying, m.mode, m.tmode,
            strict=True,
        )):  # fmt: skip
            if mode in (COMM, FOLLOW):
                to_tell = np.zeros(len(self._cells), dtype=np.int8)
                to_tell[m.targets[i]] = 1
                to_tell.flags.writeable = False
            else:
                to_tell = nobody
            out[agent] = {
                "position": cell_pos[c],
                "carrying": flag[carrying],
                "informed": flag[informed],
                "food": food if informed else unknown,
                "nest": nest,
                "round": t,
                "mode": phase[3 + tmode if mode == TRANSPORT else mode],
                "to_tell": to_tell,
                "team_positions": row,
                "action_mask": cell_mask[c],
            }
        return out

    def _infos(self) -> dict[str, dict[str, Any]]:
        m = self._mission
        t = m.t if m is not None else 0
        return {a: {"round": t} for a in self.agents}

    # ------------------------------------------------------------------ the run's own view
    def baseline_actions(self) -> np.ndarray:
        """The seed's move for every robot this round (index i: ``robot_i``), from the
        mission's own Compute; raises when no round is pending."""
        if self._pending is None:
            raise RuntimeError(f"{NAME}: no round is pending (call reset(), or the run ended)")
        return self._pending.builtin.copy()

    @property
    def round(self) -> int | None:
        """The pending round (None when no episode is running)."""
        return None if self._pending is None else self._pending.t

    @property
    def mission(self) -> Mission | None:
        """The simulator's state (for renderers and tests; policies must not read it)."""
        return self._mission

    def record(self) -> ResultRecord:
        """The run's ResultRecord (== ``swarmex.run``'s for baseline-driven episodes,
        ``wall_seconds`` aside: here the run's time includes waiting for the decisions)."""
        if self._result is None or self._run_params is None:
            raise RuntimeError(f"{NAME}: record() is available once the episode has ended")
        if self._record is None:
            from swarmex.missions.foraging.run import to_record

            p = self._run_params
            self._record = to_record(
                self._result, p.seed, {"food_distance": p.food_distance, "seed": p.seed}
            )
        return self._record

    # ------------------------------------------------------------------ render, close
    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            import gymnasium

            gymnasium.logger.warn(f"{NAME}: render() without a render_mode")
            return None
        m = self._mission
        world = self._world
        if m is None or world is None:
            raise RuntimeError(f"{NAME}: call reset() before render()")
        from swarmex.viz.foraging import animation_frames

        p = self.params
        rows = m.trajectory().tolist()
        agents = [
            {
                "trajectory": [[t, int(r[a][0]), int(r[a][1])] for t, r in enumerate(rows)],
                "jobs": [list(j) for j in m.jobs[a]],
            }
            for a in range(m.n)
        ]
        record = {
            "params": {
                "grid": p.grid,
                "nest": list(self.nest),
                "food": list(world.food),
                "food_units": p.food_units,
            },
            "agents": agents,
        }
        return animation_frames(record, max_frames=2)[-1]  # the last round drawn



raw_env = ForagingEnv


def parallel_env(**kwargs: Any) -> ForagingEnv:
    """The native Parallel environment: ``parallel_env(grid=16, agents=4,
    algorithm="sectors", food=(12, 3), food_units=3)``."""
    return ForagingEnv(**kwargs)


def env(**kwargs: Any) -> AECEnv[str, dict[str, np.ndarray], int | None]:
    """The AEC form (PettingZoo's ``parallel_to_aec``, order-enforcing)."""
    return parallel_to_aec(ForagingEnv(**kwargs))


def baseline_policy(
    environment: ParallelEnv[str, Any, Any] | AECEnv[str, Any, Any],
) -> Callable[[Mapping[str, Any], Mapping[str, Any]], dict[str, int]]:
    """The params' ``algorithm`` and ``transport`` as a policy ``(observations, infos) ->
    actions`` for the parallel env: each robot makes the move the seed's rules make this
    round (its pattern's timetable while exploring, its communication or transport move
    afterwards; :meth:`ForagingEnv.baseline_actions`)."""
    base = environment.unwrapped
    if not isinstance(base, ForagingEnv):
        raise TypeError(f"baseline_policy needs a {NAME} environment, got {base!r}")
    index = {a: i for i, a in enumerate(base.possible_agents)}

    def policy(observations: Mapping[str, Any], infos: Mapping[str, Any]) -> dict[str, int]:
        moves = base.baseline_actions()
        return {a: int(moves[index[a]]) for a in observations}

    return policy
