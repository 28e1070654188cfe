"""PettingZoo environment of the roadmap mission (seed 004: WMA-RRT coverage and goal search,
against the PRM baseline): agents choose the roadmap edge to follow at the nodes they reach.

Which form, and why AEC: the mission's run loop moves the agents one after another, in an
order drawn each step from the run's generator, and each move is a critical section on the
shared roadmap (an agent's choice depends on what the agents before it wrote in the same
step). So the native form is AEC: one agent decides at a time, when it stands at a roadmap
node and has a real choice. The run is :func:`swarmex.missions.roadmap.sim.run_roadmap`
itself, unchanged, in a worker thread (:class:`~swarmex.envs.broker.DecisionBroker`); its
``decide`` hook hands the deciding agent's question to this environment.

Decisions (the seed algorithms' own choices; moves with a single option are taken without
asking, as are the entry leg onto the roadmap, the goal leg, and following the ½ marks once
the goal is flagged):

* **WMA-RRT, inside a branch** (``wma-rrt``, ``wma-rrt-takeover``): at a node, any child
  edge the agent has not used since it entered the branch (dedicated weight 0), or its way
  back (the edge to the parent, dedicated weight 1) once no child edge is unexplored (global
  weight 0). That keeps the paper's bookkeeping whole (the weight-1 edges are the agent's
  path from the Main Root; a branch is left over its first edge) and its guarantee (a
  branch is COMPLETE only when every edge in it was travelled), whatever order a policy
  explores in and whichever explored sub-branch it leaves to the agents beneath it.
* **WMA-RRT, free at the Main Root**: the first edge of any branch that is not COMPLETE
  (entering it), or ``stay`` (wait at the Main Root for a step): the seed's "help the
  unfinished branch of least Weight, or wait".
* **PRM**: any edge at the walker's node (the baseline takes one of least weight).

Actions: ``Discrete(E + 1)`` where ``E`` is the roadmap's edge capacity (``nodes`` for the
WMA-RRT planners, whose trees have exactly K edges; ``8 * nodes`` for PRM and ``10 * nodes``
for OMPL's PRM, whose milestones join at most their 10 nearest, unless ``max_edges`` says
otherwise; a PRM with more edges is an error naming ``max_edges``):
action ``e < E`` follows edge ``e`` (its global id, the same index as the observation's edge
arrays), action ``E`` is ``stay``. ``observation["action_mask"]`` marks the open ones; any
other action raises :class:`~swarmex.errors.InputError` (a ValueError) naming the agent, the
action and why. ``illegal_reward=x`` (in :func:`env` / :func:`parallel_env`) instead ends the
episode with reward ``x`` for the offender, PettingZoo's ``TerminateIllegalWrapper``.

Observations are the agent's belief: the shared roadmap (its geometry and the seed's only
channel, the board: global edge weights, Sync and Weight per branch, the improved planner's
counters, the goal flag with the anchor and the goal the finder wrote) and its own memory
(its node, position, state, branch, dedicated weights). Never the world, the coverage or the
other agents' positions. See docs/envs.md for the table.

Rewards (the same to every agent, the team's): ``coverage_reward`` × the fraction of free
space first seen since the previous decision − ``time_cost`` × the simulation steps elapsed,
plus ``completion_bonus`` when the run ends complete. Termination: the mission's end
condition (every branch COMPLETE, every agent at the goal); truncation: the step budget
(``step_budget``, the mission's default otherwise), which is how PRM coverage always ends.

Exactness: the choices are the agents' own (``choice()`` of
:class:`~swarmex.missions.roadmap.wma_policy.WMAAgent` and
:class:`~swarmex.missions.roadmap.prm_policy.PRMWalker`, which also define what is legal). At
each decision the environment computes the built-in choice (``seed_choice``) on a snapshot
of the run's generator and restores it; the answer equal to it is carried out by the agent's
own ``decide`` (so the generator advances exactly as in ``swarmex.run``); another answer by
its ``carry_out`` from the restored state. :func:`baseline_policy` answers with the built-in
choice, so its episodes give ``swarmex.run``'s record (``record()``), ``wall_seconds`` aside.

Seeds: ``reset(seed=s)`` runs with seed ``s``; ``reset()`` runs the params' ``seed`` the first
time, then the next of :class:`~swarmex.envs.common.SeedChain`. A pickled environment
(SuperSuit copies them) is a fresh one: the run in progress lives in a thread and is not
carried over.
"""

from __future__ import annotations

import contextlib
import dataclasses
import numbers
import operator
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv, ParallelEnv
from pettingzoo.utils.wrappers import (
    OrderEnforcingWrapper,
    TerminateIllegalWrapper,
)

from swarmex.envs.broker import Ask, DecisionBroker
from swarmex.envs.common import SeedChain, TurnBasedParallel, check_finite, plain_int
from swarmex.errors import InputError
from swarmex.missions.base import integer, python_spelling
from swarmex.missions.registry import get
from swarmex.missions.roadmap.params import GRAPH_PLANNERS

if TYPE_CHECKING:
    from swarmex.engine.record import ResultRecord
    from swarmex.missions.roadmap.blackboard import PRMBoard, WMABoard
    from swarmex.missions.roadmap.mission import RoadmapWorld
    from swarmex.missions.roadmap.params import RoadmapParams
    from swarmex.missions.roadmap.sim import RoadmapFrame, RoadmapRun
    from swarmex.missions.roadmap.wma_policy import Move
    from swarmex.sensing.coverage_raster import CoverageRaster

__all__ = ["STATES", "baseline_policy", "env", "parallel_env", "raw_env"]

# every state an agent of either planner can be in (the observation's one-hot order)
STATES = ("entry", "explore", "free", "wait", "follow", "leg", "done", "at-goal", "walk", "stuck")
COUNT_HIGH = 1e9  # bound of counters (weights, steps) in the observation space
PRM_EDGES_PER_NODE = 8  # default edge capacity of a PRM: 8 K (measured: 3 K to 5 K)
OMPL_EDGES_PER_NODE = 10  # OMPL's PRM: each milestone joins at most its 10 nearest


@dataclass(frozen=True)
class Decision:
    """One question the run asks: ``agent`` (index) at step ``t`` chooses among ``mask``."""

    agent: int
    t: int
    kind: str  # "edge" (WMA-RRT in a branch) | "branch" (free at the Main Root) | "walk" (PRM)
    mask: np.ndarray  # (E + 1,) int8
    builtin: int  # the seed algorithm's choice (an action)


# ------------------------------------------------------------------------------- one run


class _Episode:
    """One run in its worker thread, and what the environment reads of it.

    Holds no reference to the environment, so an environment dropped without ``close()`` can
    be collected (its finalizer then abandons the run).
    """

    def __init__(
        self, params: RoadmapParams, prepared: RoadmapWorld, caps: tuple[int, int], track: bool
    ) -> None:
        from swarmex.sensing.coverage_raster import CoverageRaster

        self.params = params
        self.prepared = prepared
        self.e_cap, self.v_cap = caps
        self.stay = self.e_cap
        n = len(prepared.starts)
        self.agents: list[Any] = [None] * n
        self.board: WMABoard | PRMBoard | None = None
        self.raster: CoverageRaster = CoverageRaster(
            prepared.world, params.range_length, params.raster
        )
        self.track = track  # keep trajectories and first edge use (for render)
        self.trajectories = [[[0.0, float(p[0]), float(p[1])]] for p in prepared.starts]
        self.first_use: np.ndarray | None = None
        self.frame_step = 0
        self.static: dict[str, np.ndarray] = {}
        self.t = 0
        self.t0 = time.perf_counter()
        self.wall = 0.0
        self.broker = DecisionBroker(self._run, name="swarmex-roadmap-env")
        self._ask: Ask | None = None

    # ---------------------------------------------------------------- worker side
    def _run(self, ask: Ask) -> RoadmapRun:
        from swarmex.missions.roadmap.mission import simulate

        self._ask = ask
        return simulate(
            self.params,
            self.prepared,
            self._on_frame if self.track else None,
            raster=self.raster,
            decide=self._decide,
        )

    def _on_frame(self, frame: RoadmapFrame) -> None:
        self.frame_step = frame.step
        for i in frame.moved:
            x, y = frame.positions[i]
            self.trajectories[i].append([float(frame.step), float(x), float(y)])
        trav = frame.edge_traversals
        if self.first_use is None:
            self.first_use = np.full(len(trav), np.iinfo(np.int64).max, dtype=np.int64)
        self.first_use[(trav > 0) & (self.first_use > frame.step)] = frame.step

    def _see_board(self, board: WMABoard | PRMBoard) -> None:
        """First sight of the run's roadmap: check it fits the spaces, keep its geometry."""
        from swarmex.missions.roadmap.blackboard import WMABoard

        rm = board.rm
        if rm.n_edges > self.e_cap:
            raise InputError(
                f"the {rm.kind} roadmap has {rm.n_edges} edges, more than the environment's "
                f"max_edges={self.e_cap}: pass a larger max_edges"
            )
        if rm.n_nodes > self.v_cap:  # cannot happen: builders stop at K (+ the Main Root)
            raise InputError(f"the roadmap has {rm.n_nodes} nodes, more than {self.v_cap}")
        self.board = board
        xy = np.zeros((self.v_cap, 2), dtype=np.float32)
        xy[: rm.n_nodes] = rm.pos
        ends = np.full((self.e_cap, 2), -1, dtype=np.int64)
        ends[: rm.n_edges] = rm.edges
        branch = np.full(self.e_cap, -1, dtype=np.int64)
        if isinstance(board, WMABoard):
            branch[: rm.n_edges] = board.branch_of_edge
        for a in (xy, ends, branch):
            a.setflags(write=False)
        self.static = {"node_xy": xy, "edge_nodes": ends, "edge_branch": branch}

    def _decide(self, a: Any, t: int, rng: np.random.Generator) -> Move | None:
        """The run's decision hook: ask the environment when the agent has a choice."""
        from swarmex.missions.roadmap.wma_policy import WAIT

        if self.board is None:
            self._see_board(a.board)
        self.agents[a.id] = a
        self.t = t
        choice = a.choice()
        if choice is None:
            return a.decide(t, rng)  # nothing to choose: the agent's own step
        mask = np.zeros(self.e_cap + 1, dtype=np.int8)
        mask[[self.stay if o == WAIT else o for o in choice.options]] = 1
        snapshot = rng.bit_generator.state
        seed = a.seed_choice(choice, rng)
        rng.bit_generator.state = snapshot
        builtin = self.stay if seed == WAIT else seed
        assert self._ask is not None
        action = int(self._ask(Decision(int(a.id), t, choice.kind, mask, builtin)))
        if action == builtin:
            return a.decide(t, rng)  # the seed's own decision, drawing what it draws
        return a.carry_out(choice, WAIT if action == self.stay else action)

    # ---------------------------------------------------------------- caller side
    @property
    def pending(self) -> Decision | None:
        req = self.broker.pending
        return req if isinstance(req, Decision) else None

    @property
    def run(self) -> RoadmapRun | None:
        return self.broker.result if self.broker.finished else None

    def coverage(self) -> float:
        return float(self.raster.coverage())


def _abandon(broker: DecisionBroker) -> None:
    # RuntimeError: a collector running in the worker itself; it unwinds at its next ask
    with contextlib.suppress(RuntimeError):
        broker.close()


# ------------------------------------------------------------------------------- the env


class raw_env(AECEnv[str, dict[str, np.ndarray], int]):  # noqa: N801 - PettingZoo's name
    """The roadmap mission as an AEC environment (see the module docstring).

    Keyword arguments: the mission's parameters (the names and checks of
    ``swarmex.run("roadmap", ...)``: ``env``, ``agents``, ``nodes``, ``step``,
    ``sensor_range``, ``task``, ``planner``, ``goal``, ``starts``, ``seed``, ``step_budget``,
    ``raster``), plus ``render_mode`` (None or "rgb_array"), ``max_edges`` (the edge
    capacity of the action and observation spaces), ``coverage_reward``, ``time_cost`` and
    ``completion_bonus`` (the reward's terms).
    """

    metadata: dict[str, Any] = {
        "name": "roadmap_v0",
        "render_modes": ["rgb_array"],
        "render_fps": 8,
        "is_parallelizable": False,
    }

    def __init__(
        self,
        render_mode: str | None = None,
        max_edges: int | None = None,
        coverage_reward: float = 100.0,
        time_cost: float = 1.0,
        completion_bonus: float = 100.0,
        **params: Any,
    ) -> None:
        super().__init__()
        mission = get("roadmap")
        with python_spelling(mission.params_type):
            self.params: RoadmapParams = mission.params(params)
            self.prepared: RoadmapWorld = mission.prepare(self.params)
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise InputError(
                f"render_mode must be None or one of {self.metadata['render_modes']}, "
                f"got {render_mode!r}"
            )
        self.render_mode = render_mode
        check_finite(
            ("coverage_reward", coverage_reward),
            ("time_cost", time_cost),
            ("completion_bonus", completion_bonus),
        )
        self.coverage_reward = float(coverage_reward)
        self.time_cost = float(time_cost)
        self.completion_bonus = float(completion_bonus)
        k = self.params.nodes
        if max_edges is None:
            per_node = {"prm": PRM_EDGES_PER_NODE, "ompl-prm": OMPL_EDGES_PER_NODE}
            max_edges = per_node.get(self.params.planner, 1) * k
        elif (
            isinstance(max_edges, bool)
            or not isinstance(max_edges, int | np.integer)
            or (max_edges < 1)
        ):
            raise InputError(f"max_edges must be a positive integer, got {max_edges!r}")
        self.max_edges = int(max_edges)
        self.max_nodes = k + 1  # WMA-RRT: K nodes and the Main Root; PRM: K nodes
        self.stay_action = self.max_edges
        n = len(self.prepared.starts)
        self.possible_agents = [f"agent_{i}" for i in range(n)]
        self._index = {a: i for i, a in enumerate(self.possible_agents)}
        self._action_space = spaces.Discrete(self.max_edges + 1)
        self._observation_space = self._make_observation_space(n)
        self.action_spaces = dict.fromkeys(self.possible_agents, self._action_space)
        self.observation_spaces = dict.fromkeys(self.possible_agents, self._observation_space)
        self._episode: _Episode | None = None
        self._finalizer: weakref.finalize | None = None
        self._seeds = SeedChain(self.params.seed)
        self._seed: int | None = None
        self._record: ResultRecord | None = None
        self._figure: Any = None
        self.agents: list[str] = []

    # ---------------------------------------------------------------- spaces
    def _make_observation_space(self, n: int) -> spaces.Dict:
        xmin, ymin, xmax, ymax = self.prepared.world.bounds
        lo = np.minimum(np.array([xmin, ymin], dtype=np.float32), 0)
        hi = np.maximum(np.array([xmax, ymax], dtype=np.float32), 0)
        e, v = self.max_edges, self.max_nodes

        def box(low: float, high: float, shape: tuple[int, ...], dtype: Any) -> spaces.Box:
            return spaces.Box(low, high, shape, dtype=dtype)

        return spaces.Dict(
            {
                "action_mask": box(0, 1, (e + 1,), np.int8),
                "node": box(-1, v - 1, (1,), np.int64),
                "position": spaces.Box(lo, hi, dtype=np.float32),
                "state": box(0, 1, (len(STATES),), np.int8),
                "branch": box(-1, n - 1, (1,), np.int64),
                "step": box(0, COUNT_HIGH, (1,), np.float32),
                "node_xy": spaces.Box(np.tile(lo, (v, 1)), np.tile(hi, (v, 1)), dtype=np.float32),
                "edge_nodes": box(-1, v - 1, (e, 2), np.int64),
                "edge_branch": box(-1, n - 1, (e,), np.int64),
                "edge_weights": box(0, COUNT_HIGH, (e,), np.float32),
                "dedicated_weights": box(0, COUNT_HIGH, (e,), np.float32),
                "unexplored_below": box(0, e, (e,), np.float32),
                "agents_below": box(-n, n, (e,), np.float32),
                "sync": box(0, n, (n,), np.float32),
                "branch_weight": box(0, COUNT_HIGH, (n,), np.float32),
                "goal_found": box(0, 1, (1,), np.int8),
                "goal_xy": spaces.Box(lo, hi, dtype=np.float32),
                "anchor": box(-1, v - 1, (1,), np.int64),
            }
        )

    def observation_space(self, agent: str) -> spaces.Space[Any]:
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space[Any]:
        return self.action_spaces[agent]

    # ---------------------------------------------------------------- episode
    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> None:
        self._close_episode()
        if seed is not None:  # checked as the seed parameter is: numpy's refusal of a
            # negative seed came from deep in the run, without naming it; an integer type,
            # as Gymnasium and the other envs want (3.0 is not a seed)
            if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
                raise InputError(f"roadmap_v0: reset seed must be an integer, got {seed!r}")
            seed = integer(lo=0)(seed, "roadmap_v0: reset seed")
        self._seed = self._seeds.next(seed)
        params = dataclasses.replace(self.params, seed=self._seed)
        ep = _Episode(
            params,
            self.prepared,
            (self.max_edges, self.max_nodes),
            track=self.render_mode is not None,
        )
        self._episode = ep
        self._finalizer = weakref.finalize(self, _abandon, ep.broker)
        self._record = None
        self.agents = self.possible_agents[:]
        self.rewards = dict.fromkeys(self.agents, 0.0)
        self._cumulative_rewards = dict.fromkeys(self.agents, 0.0)
        self.terminations = dict.fromkeys(self.agents, False)
        self.truncations = dict.fromkeys(self.agents, False)
        self.infos: dict[str, dict[str, Any]] = {a: {} for a in self.agents}
        self._skip_agent_selection = None
        ep.broker.start()
        self._last_coverage = ep.coverage()
        self._last_t = ep.t
        self._advance(ep, first=True)

    def _advance(self, ep: _Episode, first: bool = False) -> None:
        """After the run moved on: who decides next, or the end (rewards, dones)."""
        req = ep.pending
        run = ep.run
        t = run.steps if run is not None else ep.t
        cov = ep.coverage()
        reward = self.coverage_reward * (cov - self._last_coverage) - self.time_cost * (
            t - self._last_t
        )
        self._last_coverage, self._last_t = cov, t
        if run is not None:
            ep.wall = time.perf_counter() - ep.t0
            if run.complete:
                reward += self.completion_bonus
            done = self.terminations if run.complete else self.truncations
            for a in self.agents:
                done[a] = True
        if first:
            reward = 0.0
        self.rewards = dict.fromkeys(self.agents, float(reward))
        self._accumulate_rewards()
        self.infos = {a: {} for a in self.agents}
        if req is not None:
            self.agent_selection = self.possible_agents[req.agent]
        else:
            self.agent_selection = self.agents[0]
            self._deads_step_first()

    def step(self, action: Any) -> None:
        agent = self.agent_selection
        if self.terminations[agent] or self.truncations[agent]:
            self._was_dead_step(action)
            return
        ep = self._episode
        req = None if ep is None else ep.pending
        if ep is None or req is None:  # closed mid-run (python -O drops asserts)
            raise RuntimeError("roadmap_v0: the episode has ended; call reset()")
        assert self.possible_agents[req.agent] == agent
        choice = self._check(agent, req, action)
        self._cumulative_rewards[agent] = 0.0
        ep.broker.answer(choice)
        self._advance(ep)

    def _check(self, agent: str, req: Decision, action: Any) -> int:
        """The action as an int, or an InputError naming the agent, the action and why."""
        a = self._as_action(agent, req, action)
        if req.mask[a]:
            return a
        valid = np.flatnonzero(req.mask).tolist()
        raise InputError(
            f"{agent}: action {a} is not open: {self._why(req, a)} (open actions: {valid})"
        )

    def _as_action(self, agent: str, req: Decision, action: Any) -> int:
        """An integer of the action space (open or not), or an InputError saying why not."""
        n = self.max_edges + 1
        if action is None:
            raise InputError(f"{agent}: no action (None) for its decision at step {req.t}")
        try:
            value = plain_int(action)  # a one-element array too, as the other envs take
            if isinstance(value, bool | np.bool_):
                raise TypeError
            a = operator.index(value)
        except TypeError:
            raise InputError(f"{agent}: action {action!r} is not an integer") from None
        if not 0 <= a < n:
            raise InputError(f"{agent}: action {a} is outside the action space Discrete({n})")
        return a

    def _why(self, req: Decision, a: int) -> str:
        ep = self._episode
        assert ep is not None and ep.board is not None
        me = ep.agents[req.agent]
        rm = ep.board.rm
        where = "at the Main Root" if req.kind == "branch" else f"at node {me.node}"
        if a == self.stay_action:
            return f"only a free WMA-RRT agent at the Main Root may stay; this agent is {where}"
        if a >= rm.n_edges:
            return f"the roadmap has {rm.n_edges} edges (ids 0..{rm.n_edges - 1})"
        u, v = (int(x) for x in rm.edges[a])
        if req.kind == "branch":
            return (
                f"a free agent at the Main Root enters a branch that is not COMPLETE by its "
                f"first edge, or stays; edge {a} ({u}-{v}) is not one"
            )
        if me.node not in (u, v):
            return f"edge {a} joins nodes {u} and {v}, and the agent is {where}"
        if a == me.node - 1:
            return (
                f"edge {a} is the way back, closed while a child edge of node {me.node} is "
                f"unexplored (global weight 0): a WMA-RRT agent leaves no edge behind"
            )
        return (
            f"the agent used edge {a} since it entered branch {me.branch} (dedicated weight "
            f"{me.w_d[a]:g}): inside a branch it takes an unused child edge or its way back"
        )

    # ---------------------------------------------------------------- observations
    def observe(self, agent: str) -> dict[str, np.ndarray]:
        from swarmex.missions.roadmap.blackboard import WMABoard

        ep = self._episode
        if ep is None:
            raise RuntimeError("call reset() before observe()")
        i = self._index[agent]
        e, v, n = self.max_edges, self.max_nodes, len(self.possible_agents)
        req = ep.pending
        mask = req.mask.copy() if req is not None and req.agent == i else np.zeros(e + 1, np.int8)
        state = np.zeros(len(STATES), dtype=np.int8)
        a = ep.agents[i]
        b = ep.board
        obs: dict[str, np.ndarray] = {"action_mask": mask}
        if a is None:  # not seen yet: where it starts
            obs["node"] = np.array([-1], dtype=np.int64)
            obs["position"] = self.prepared.starts[i].astype(np.float32)
            state[STATES.index("entry")] = 1
            graph = self.params.planner in GRAPH_PLANNERS
            obs["branch"] = np.array([-1 if graph else i], np.int64)
        else:
            obs["node"] = np.array([a.node], dtype=np.int64)
            obs["position"] = np.asarray(a.xy, dtype=np.float32)
            state[STATES.index(a.state)] = 1
            obs["branch"] = np.array([getattr(a, "branch", -1)], dtype=np.int64)
        obs["state"] = state
        obs["step"] = np.array([ep.t], dtype=np.float32)
        if b is None:
            static = {
                "node_xy": np.zeros((v, 2), np.float32),
                "edge_nodes": np.full((e, 2), -1, np.int64),
                "edge_branch": np.full(e, -1, np.int64),
            }
        else:
            static = ep.static
        obs.update(static)
        weights = np.zeros(e, np.float32)
        dedicated = np.zeros(e, np.float32)
        unexplored = np.zeros(e, np.float32)
        below = np.zeros(e, np.float32)
        sync = np.zeros(n, np.float32)
        branch_weight = np.zeros(n, np.float32)
        goal_xy = np.zeros(2, np.float32)
        found = b is not None and b.anchor is not None
        if b is not None:
            m = b.rm.n_edges
            weights[:m] = b.w_g
            if isinstance(b, WMABoard):
                unexplored[:m] = b.rem_sub
                below[:m] = b.busy
                sync[:] = b.sync
                branch_weight[:] = b.weight
                if a is not None:
                    dedicated[:m] = a.w_d
            if found:
                goal_xy[:] = b.leg[-1]
        obs.update(
            {
                "edge_weights": weights,
                "dedicated_weights": dedicated,
                "unexplored_below": unexplored,
                "agents_below": below,
                "sync": sync,
                "branch_weight": branch_weight,
                "goal_found": np.array([found], dtype=np.int8),
                "goal_xy": goal_xy,
                "anchor": np.array([b.anchor if b is not None and found else -1], np.int64),
            }
        )
        return obs

    # ---------------------------------------------------------------- baseline, record
    @property
    def pending_agent(self) -> str | None:
        """The agent whose decision the run waits for (None between episodes or at the end)."""
        req = self._episode.pending if self._episode is not None else None
        return None if req is None else self.possible_agents[req.agent]

    def baseline_action(self, agent: str) -> int:
        """The seed algorithm's choice for ``agent``'s pending decision (the planner in the
        params; computed from the agent's own belief and the run's generator)."""
        req = self._episode.pending if self._episode is not None else None
        if req is None or self.possible_agents[req.agent] != agent:
            raise InputError(f"{agent} has no decision pending")
        return req.builtin

    def record(self) -> ResultRecord:
        """The run's result record, the same as ``swarmex.run``'s for the same params and seed
        when every decision was the baseline's (``wall_seconds`` aside: here it is the
        episode's wall time, decisions included)."""
        from swarmex.missions.roadmap.mission import record_params
        from swarmex.missions.roadmap.record import build_record

        ep = self._episode
        run = ep.run if ep is not None else None
        if ep is None or run is None:
            raise RuntimeError("the episode has not ended: no record yet")
        if self._record is None:
            self._record = build_record(
                run, record_params(ep.params, self.prepared), ep.params.seed, ep.wall
            )
        return self._record

    # ---------------------------------------------------------------- render, close
    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            import gymnasium

            gymnasium.logger.warn(
                "render() called without a render_mode; pass render_mode='rgb_array'"
            )
            return None
        ep = self._episode
        if ep is None:
            raise RuntimeError("call reset() before render()")
        from swarmex.viz import roadmap_plot

        run = ep.run or self._live_run(ep)
        t = run.steps if ep.run is not None else ep.frame_step
        first = ep.first_use if ep.first_use is not None else np.zeros(0, dtype=np.int64)
        if len(first) != run.roadmap.n_edges:
            first = np.full(run.roadmap.n_edges, np.iinfo(np.int64).max, dtype=np.int64)
        if self._figure is None:
            import matplotlib.pyplot as plt

            w = self.prepared.world
            self._figure = plt.subplots(figsize=(6, 6 * w.height / w.width + 0.4), dpi=80)
        fig, ax = self._figure
        for artist in [*ax.images, *ax.lines, *ax.collections, *ax.patches]:
            artist.remove()
        roadmap_plot.draw(ax, run, t=t, first_use=first, title=roadmap_plot.summary_title(run, t))
        fig.canvas.draw()
        return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()

    def _live_run(self, ep: _Episode) -> RoadmapRun:
        """A RoadmapRun view of the run in progress, for the renderer (the state after the
        last completed step)."""
        from swarmex.missions.roadmap.sim import RoadmapRun

        p, n = ep.params, len(self.possible_agents)
        board = ep.board
        assert board is not None  # reset() runs the first step (every agent's entry leg)
        return RoadmapRun(
            world=self.prepared.world,
            roadmap=board.rm,
            task=p.task,
            planner=p.planner,
            sensor_range=p.range_length,
            goal=self.prepared.goal,
            raster=ep.raster,
            board=board,
            agents=ep.agents,
            trajectories=ep.trajectories,
            path_length=np.zeros(n),
            moves=np.zeros(n, dtype=np.int64),
            steps=ep.frame_step,
            complete=False,
            goal_found=board is not None and board.anchor is not None,
            goal_unreachable=False,
            all_at_goal_step=-1,
            step_budget=0,
            budget_exhausted=False,
            build_seconds=0.0,
            sim_seconds=0.0,
        )

    def _close_episode(self) -> None:
        if self._finalizer is not None:
            self._finalizer()  # abandons the run (once)
            self._finalizer = None
        self._episode = None

    def close(self) -> None:
        """Abandon a run in progress: the episode ends (no agents left; a ``step`` asks for
        ``reset()``). ``record()`` of a finished run still works."""
        ep = self._episode
        self._close_episode()
        self._episode = ep if ep is not None and ep.run is not None else None  # keep record()
        self.agents = []
        if self._figure is not None:
            import matplotlib.pyplot as plt

            plt.close(self._figure[0])
            self._figure = None

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state.update(_episode=None, _finalizer=None, _figure=None, _record=None, agents=[])
        return state

    def __str__(self) -> str:
        return "roadmap_v0"


# ------------------------------------------------------------------------------- PettingZoo


def env(illegal_reward: float | None = None, **kwargs: Any) -> AECEnv[str, Any, Any]:
    """The AEC environment, with PettingZoo's order checks (and, with ``illegal_reward``,
    its TerminateIllegalWrapper instead of an error for a masked-out action)."""
    if illegal_reward is not None:
        check_finite(("roadmap_v0: illegal_reward", illegal_reward))
    aec: AECEnv[str, Any, Any] = raw_env(**kwargs)
    if illegal_reward is not None:
        aec = _TerminateIllegal(aec, illegal_reward=illegal_reward)
    return OrderEnforcingWrapper(aec)


class _TerminateIllegal(TerminateIllegalWrapper):
    """PettingZoo's wrapper indexes the action mask with the action before the environment
    sees it, so an action outside the space or not an integer was an ``IndexError``; here it
    is the environment's own :class:`~swarmex.errors.InputError` first, and only an open
    action's masked-out twin ends the episode with the penalty."""

    def step(self, action: Any) -> None:
        raw = self.unwrapped
        agent = self.agent_selection
        if (action is not None and not (self.terminations.get(agent)
                                       or self.truncations.get(agent))):
            req = raw._episode.pending if raw._episode is not None else None
            if req is not None:
                raw._as_action(agent, req, action)  # a masked-out one is the wrapper's case
        super().step(action)


def parallel_env(illegal_reward: float | None = None, **kwargs: Any) -> ParallelEnv[str, Any, Any]:
    """The Parallel form: PettingZoo's turn-based conversion of :func:`env` (``TurnBasedParallel``).

    One agent acts per ``step`` (``env.unwrapped.pending_agent``, also ``infos[a]
    ["active_agent"]`` after a step); the actions given for the others are ignored.
    """
    return TurnBasedParallel(env(illegal_reward=illegal_reward, **kwargs))


def baseline_policy(
    env: AECEnv[str, Any, Any] | ParallelEnv[str, Any, Any],
) -> Callable[[dict[str, Any], dict[str, Any]], dict[str, int]]:
    """The seed algorithm (the env's ``planner``) as ``(observations, infos) -> actions``.

    The deciding agent gets the built-in choice (read from the environment, which computed it
    from that agent's belief); the other agents, whose actions the turn-based parallel form
    ignores, get ``stay``.
    """
    raw = env.unwrapped
    if not isinstance(raw, raw_env):
        raise InputError("baseline_policy needs a roadmap_v0 environment")

    def policy(observations: dict[str, Any], infos: dict[str, Any]) -> dict[str, int]:
        active = raw.pending_agent
        return {a: raw.baseline_action(a) if a == active else raw.stay_action for a in observations}

    return policy
