"""Discrete-event simulation of the traversal mission (seed 000, chapters 3–5).

Timing model (spec §6.7): each agent is a client that enters the mission
``start_interval`` seconds after the previous one (0.5 s in the thesis's simulations) plus
its own takeoff time, then loops LOOK–COMPUTE–MOVE. A move along an edge takes
``edge length × unit_length / travel_speed`` seconds, a job ``job_time`` seconds. Decisions
take no time. Messages follow §4.2 and are applied to the receivers' beliefs when they
arrive (instantly under the default perfect broadcast):

* position — an agent's current vertex, sent at start (C04) and at every arrival (C07), with
  the obstacles it sees there (sensing is adjacency only) and the job bit (the thesis's C01,
  sent before takeoff, is not modelled: a rival counts from its takeoff);
* C05 — the next vertex, sent when a move is decided; a vacant one is reserved for the sender;
* C07 — arrival with the job bit set: the vertex is conditionally accomplished;
* C08 — job done; with ``job_failure`` > 0 a job may fail instead, and the vertex returns to
  not-done (the agent, still there, sees it vacant and retries);
* with an imperfect channel every message also carries the sender's done-nodes list of §4.1
  (done nodes while fewer than half are done, then the not-done nodes), which is what keeps
  beliefs convergent when messages are lost or out of range.

What an agent does and knows (sensing, the policy's decisions, the arrival rule, its
messages and how it applies its rivals') is
:class:`~swarmex.missions.traversal.agent.TraversalAgent`, the same core the networked
agent runs (:mod:`swarmex.net.traversal`); this module is only the clock and the radio
around it: it schedules each agent's next event, carries its messages over the
:class:`~swarmex.comm.channel.Channel`, draws job failures and keeps the true record (who
did what, the flight home).

At the end each agent flies back to its nest along the true shortest path and lands; those
times, with takeoff, are ``additional_time``.

Under a perfect broadcast the team shares one distance-field cache (every belief knows the
same obstacles at every instant) and one belief table, so a message reaches all receivers
in one compiled call; events are plain tuples on a heap. None of this changes a result:
``tests/missions/traversal/test_regression_fingerprint.py`` pins them, and
``bench/bench_traversal_den520d.py`` times the 16-agent run on den520d.map.
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from swarmex.comm.channel import Channel
from swarmex.errors import InputError
from swarmex.missions.base import StopRun, integer
from swarmex.missions.traversal.agent import (
    DONE,
    JOB,
    LEAVE,
    NEXT,
    PASS,
    PLAN,
    START,
    UNDONE,
    AdjacencySensor,
    AgentLog,
    Message,
    Next,
    TraversalAgent,
    forget_rival,
)
from swarmex.missions.traversal.agent import edge_length as _edge_length  # noqa: F401
from swarmex.missions.traversal.agent import encode_done_list as _encode_done_list  # noqa: F401
from swarmex.missions.traversal.agent import encode_km as _encode_km  # noqa: F401
from swarmex.missions.traversal.agent import merge_done_list as _merge_done_list  # noqa: F401
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.belief import JOB as JOB_CODE
from swarmex.missions.traversal.belief import NEXT as NEXT_CODE
from swarmex.missions.traversal.belief import POS as POS_CODE
from swarmex.missions.traversal.belief import UNDONE as UNDONE_CODE
from swarmex.missions.traversal.belief import BeliefTable, TraversalBelief, deliver
from swarmex.missions.traversal.policies import Madgta, canonical_algorithm, make_policy
from swarmex.planning.distance import distance_field
from swarmex.planning.fieldcache import KnownGraph

#: compute a moving agent's next field on a worker thread (KnownGraph.prefetch). Same
#: results either way; it pays only when a second core is idle, and costs a little when the
#: machine is busy (thread hand-offs), so it is off unless asked for.
PREFETCH_FIELDS = False


class _Clock:
    """:class:`swarmex.engine.events.EventQueue` with plain tuples ``(time, seq, kind,
    agent, data)``: the same order (time, then scheduling order), but heapq compares the
    tuples in C instead of calling a dataclass ``__lt__`` per comparison."""

    __slots__ = ("_heap", "_seq", "now")

    def __init__(self) -> None:
        self._heap: list[tuple[float, int, str, int, Any]] = []
        self._seq = 0
        self.now = 0.0

    def schedule(self, time: float, kind: str, agent: int = -1, data: Any = None) -> None:
        if time < self.now - 1e-12:
            raise ValueError(f"cannot schedule into the past ({time} < {self.now})")
        heapq.heappush(self._heap, (float(time), self._seq, kind, agent, data))
        self._seq += 1

    def pop(self) -> tuple[float, int, str, int, Any]:
        ev = heapq.heappop(self._heap)
        self.now = ev[0]
        return ev

    def __len__(self) -> int:
        return len(self._heap)

    def __bool__(self) -> bool:
        return bool(self._heap)


# message kind -> deliver() code; 0: nothing for the receivers to do ("done" carries no state)
_KIND_CODES = {
    START: POS_CODE, PASS: POS_CODE, JOB: JOB_CODE, NEXT: NEXT_CODE, UNDONE: UNDONE_CODE,
    DONE: 0, LEAVE: 0, PLAN: 0,
}


@dataclass(frozen=True)
class TraversalFrame:
    """One moment of a traversal run, for ``on_frame`` (a notebook's animation, a monitor):
    the event that just happened and where every started agent is (cells x, y)."""

    t: float  # seconds
    event: str  # "start" | "arrive" | "job_end"
    agent: int  # the agent the event happened to
    positions: tuple[tuple[int, float, float], ...]  # (agent id, x, y)
    jobs_done: int  # vertices with at least one job started
    job: bool = False  # ``agent`` began a job at its vertex at ``t`` (right after the event)
    # where ``agent`` announced it moves next (C05), if it set off at ``t``: (x, y)
    heading: tuple[float, float] | None = None


@dataclass
class TraversalRun:
    world: Any
    agents: list[AgentLog]
    done_by: np.ndarray  # first agent id to start a job at each vertex (0 = never)
    job_count: np.ndarray  # jobs started per vertex
    reachable: np.ndarray  # free vertices reachable from some nest
    algorithm: str
    seed: int
    messages: int
    message_bytes: int
    wall_seconds: float
    stopped_early: bool = False
    # distance-field cache counters, summed over the distinct caches (not part of the record)
    field_cache: dict[str, int] = field(default_factory=dict)

    @property
    def complete(self) -> bool:
        return bool(np.all(self.job_count[self.reachable] >= 1)) and not self.stopped_early

    def path_strings(self, label: Callable[[int], str] | None = None) -> list[str]:
        """PATH of each agent in the thesis's notation (``v`` and ``v*``)."""
        lab = label or (lambda v: str(v))
        return [
            "-".join(f"{lab(v)}-{lab(v)}*" if job else lab(v) for v, job in a.path)
            for a in self.agents
        ]


class _Sim:
    """The simulator's clock and radio around one :class:`TraversalAgent` per agent."""

    def __init__(
        self,
        world: Any,
        specs: list[AgentSpec],
        policy: Madgta,
        rng: np.random.Generator,
        channel: Channel,
        start_interval: float,
        unit_length: float,
        job_failure: float,
    ) -> None:
        self.world = world
        self.graph = world.graph
        self.truth_blocked = world.blocked
        self.specs = specs
        self.rng = rng
        self.channel = channel
        self.job_failure = job_failure
        self.start_interval = start_interval
        m = len(specs)
        self.m = m
        tpu = np.zeros(m + 1)
        jt = np.zeros(m + 1)
        for i, s in enumerate(specs, start=1):
            tpu[i] = unit_length / s.travel_speed
            jt[i] = s.job_time
        # Under a perfect instant broadcast every belief's obstacle set is identical at every
        # instant, so one KnownGraph (and its field cache) is shared: copy elision, not
        # shared memory between agents.
        shared = (
            KnownGraph(self.graph, capacity=2 * m + 8, prefetch=PREFETCH_FIELDS)
            if channel.perfect else None
        )
        # likewise the beliefs live in one team table, so a broadcast is one compiled call
        self.table = BeliefTable(m, self.graph.n_nodes) if channel.perfect else None
        sensor = AdjacencySensor(self.graph, self.truth_blocked)
        # every agent draws from the run's one generator; only an imperfect channel needs
        # the §4.1 done-nodes list on the messages
        self.agents: list[TraversalAgent] = [
            TraversalAgent(
                i, s,
                TraversalBelief(
                    i, m, shared or KnownGraph(self.graph, capacity=2 * m + 8), tpu, jt,
                    table=self.table,
                ),
                policy, rng, sensor, self.broadcast, done_lists=not channel.perfect,
            )
            for i, s in enumerate(specs, start=1)
        ]
        # where the radio hears each agent: its nest until it takes off (an agent waiting for
        # its start listens from the ground there; zeros put it at cell (0, 0) for the range)
        self.pos_xy = np.zeros((m + 1, 2))
        self.pos_xy[1:] = self.graph.pos[[s.nest for s in specs]]
        self.done_by = np.zeros(self.graph.n_nodes, dtype=np.int32)
        self.job_count = np.zeros(self.graph.n_nodes, dtype=np.int32)
        # vertices with a job started, kept as job_count changes: a frame used to count them
        # over the whole map, 40 % on top of a 256x256 run with an on_frame callback
        self.vertices_started = 0
        self.queue = _Clock()
        self._home_fields: dict[int, np.ndarray] = {}  # nest -> true distances (for RTL)
        self.messages = 0
        self.message_bytes = 0
        self.heading = np.full(m + 1, -1, dtype=np.int64)  # node each agent set off to (frames)

    def agent(self, a: int) -> TraversalAgent:
        return self.agents[a - 1]

    # ---------------------------------------------------------------- messaging
    def broadcast(self, msg: Message) -> None:
        """An agent's message on the simulated radio (called by the agent as it speaks)."""
        self.messages += 1
        sender, obstacles, done_list = msg.sender, msg.obstacles, msg.done_list
        # ID, node, job bit, done bit, checksum: 4 + 4 + 1 + 1 + 4 bytes, plus obstacle ids
        size = 14 + 4 * len(obstacles)
        if done_list is not None:  # the listed vertices and the known walls, 4 bytes each
            _, listed, _, *walls = done_list
            size += 4 * (listed.size + sum(w.size for w in walls))
        if msg.plan is not None:  # 4 bytes per planned vertex, 2 per route length
            size += 4 * int(msg.plan.lens.sum()) + 2 * msg.plan.lens.size
        self.message_bytes += size
        if self.table is not None:  # perfect broadcast: every other belief, in one call
            if msg.kind == LEAVE:  # rare (once per agent at most): the Python rule per belief
                for other in self.agents:
                    if other.me != sender:
                        forget_rival(other.belief, sender, -1)
                return
            if msg.plan is not None:  # the team plan: one reference, kept by every receiver
                for other in self.agents:
                    if other.me != sender:
                        other.belief.hear_plan(msg.plan)
                return
            code = _KIND_CODES[msg.kind]
            if code or obstacles:
                self.agent(sender).belief.known.add_obstacles(obstacles)  # shared: a no-op
                t = self.table
                deliver(code, sender, msg.node, np.asarray(obstacles, dtype=np.int64),
                        msg.eta, t.status, t.reserved, t.loc, t.reservation, t.next_loc,
                        t.free_at, t.revived)
            return
        receivers = self.channel.receivers(sender - 1, self.pos_xy[1:], self.rng)
        for r in receivers + 1:
            if self.channel.delay > 0:
                self.queue.schedule(self.queue.now + self.channel.delay, "deliver", int(r), msg)
            else:
                self.agent(int(r)).receive(msg)

    # ---------------------------------------------------------------- clock
    def follow(self, a: int, nxt: Next) -> None:
        """Schedule agent ``a``'s next event (the last thing of each of its steps)."""
        if nxt.kind == "job_end":
            node = nxt.node
            if self.job_count[node] == 0:
                self.vertices_started += 1
            self.job_count[node] += 1
            if self.done_by[node] == 0:
                self.done_by[node] = a
            self.queue.schedule(nxt.time, "job_end", a, node)
        elif nxt.kind == "arrive":
            self.queue.schedule(nxt.time, "arrive", a, nxt.node)
            self.heading[a] = nxt.node
        else:
            self.finish(a)

    def end_job(self, a: int, node: int, t: float) -> None:
        failed = self.job_failure > 0 and self.rng.random() < self.job_failure
        if failed:
            self.job_count[node] -= 1
            if self.job_count[node] == 0:
                self.done_by[node] = 0
                self.vertices_started -= 1
        self.follow(a, self.agent(a).end_job(node, t, failed))

    def finish(self, a: int) -> None:
        log = self.agent(a).log
        nest = self.specs[a - 1].nest
        home = self._home_fields.get(nest)
        if home is None:  # agents sharing a nest share the field
            home = self._home_fields[nest] = distance_field(self.graph, nest, self.truth_blocked)
        log.rtl_length = float(home[log.node])

    def field_cache_stats(self) -> dict[str, int]:
        caches = {id(r.belief.known): r.belief.known for r in self.agents}.values()
        keys = ("recomputed", "shifted", "repaired", "reused")
        return {k: int(sum(getattr(c, k, 0) for c in caches)) for k in keys}

    # ---------------------------------------------------------------- run loop
    def run(self, max_events: int, on_frame: Callable[[TraversalFrame], Any] | None = None) -> bool:
        """Handle events until none is left (True) or ``max_events`` or an ``on_frame``
        callback's :class:`StopRun` ends the run early (False)."""
        t0 = 0.0
        for i, s in enumerate(self.specs):
            self.queue.schedule(t0 + i * self.start_interval + s.takeoff_time, "start", i + 1)
        handled = 0
        pos = self.graph.pos
        while self.queue:
            t, _, kind, a, data = self.queue.pop()
            handled += 1
            if handled > max_events:
                return False
            jobs_before = len(self.agents[a - 1].log.jobs) if on_frame is not None else 0
            self.heading[a] = -1
            if kind == "arrive":
                self.pos_xy[a] = pos[data]
                self.follow(a, self.agent(a).arrive(data, t))
            elif kind == "job_end":
                self.end_job(a, data, t)
            elif kind == "start":
                self.pos_xy[a] = pos[self.specs[a - 1].nest]
                self.follow(a, self.agent(a).start(t))
            elif kind == "deliver":
                self.agent(a).receive(data)
                continue
            if on_frame is not None:
                job = len(self.agents[a - 1].log.jobs) > jobs_before
                try:
                    on_frame(self.frame(t, kind, a, job, int(self.heading[a])))
                except StopRun:
                    return False
        return True

    def frame(self, t: float, kind: str, agent: int, job: bool = False,
              heading: int = -1) -> TraversalFrame:
        """What the run looks like at ``t``: each started agent's vertex and the jobs done."""
        pos = self.graph.pos
        to = (float(pos[heading][0]), float(pos[heading][1])) if heading >= 0 else None
        where = tuple(
            (log.id, float(pos[log.trajectory[-1][1]][0]), float(pos[log.trajectory[-1][1]][1]))
            for log in (r.log for r in self.agents)
            if log.trajectory
        )
        return TraversalFrame(float(t), kind, int(agent), where, self.vertices_started, job, to)


def validate_nests(world: Any, specs: list[AgentSpec], shared_nests: bool = True) -> None:
    if not specs:
        raise InputError("at least one agent is needed (got 0)")
    n = world.graph.n_nodes
    if len(specs) > world.free_cells:
        raise InputError(
            f"{len(specs)} agents but the map has only {world.free_cells} free cells"
        )
    seen: set[int] = set()
    for s in specs:
        if not 0 <= s.nest < n:
            raise InputError(f"nest {s.nest} is outside the map")
        if world.blocked[s.nest]:
            raise InputError(f"nest {world.label(s.nest)} is on an obstacle")
        if not shared_nests and s.nest in seen:
            raise InputError(f"duplicate nest {world.label(s.nest)}")
        seen.add(s.nest)


def run_traversal(
    world: Any,
    agents: list[AgentSpec],
    algorithm: str | Madgta = "madgta",
    seed: int = 0,
    channel: Channel | None = None,
    start_interval: float = 0.5,
    unit_length: float = 1.0,
    job_failure: float = 0.0,
    max_events: int | None = None,
    on_frame: Callable[[TraversalFrame], Any] | None = None,
) -> TraversalRun:
    """Run one traversal mission; every random choice comes from ``seed``.

    ``on_frame`` is called after every start, arrival and job end with a
    :class:`TraversalFrame`; raising :class:`~swarmex.missions.base.StopRun` from it ends the
    run there (the run is then incomplete)."""
    validate_nests(world, agents)
    seed = integer(lo=0)(seed, "seed")  # numpy's own refusal named no parameter
    if start_interval < 0:
        raise InputError(f"start interval must be >= 0, got {start_interval}")
    if not 0.0 <= job_failure < 1.0:
        raise InputError(f"job failure probability must be in [0, 1), got {job_failure}")
    policy = make_policy(algorithm) if isinstance(algorithm, str) else algorithm
    channel = channel or Channel()
    rng = np.random.default_rng(seed)
    wall = time.perf_counter()
    sim = _Sim(world, agents, policy, rng, channel, start_interval, unit_length, job_failure)
    reach = np.isfinite(distance_field(world.graph, [s.nest for s in agents], world.blocked))
    reach &= ~world.blocked
    limit = max_events or 50 * (int(reach.sum()) + 10) * (len(agents) + 1) * 4
    finished = sim.run(limit, on_frame)
    return TraversalRun(
        world=world,
        agents=[r.log for r in sim.agents],
        done_by=sim.done_by,
        job_count=sim.job_count,
        reachable=reach,
        algorithm=canonical_algorithm(algorithm) if isinstance(algorithm, str) else policy.name,
        seed=seed,
        messages=sim.messages,
        message_bytes=sim.message_bytes,
        wall_seconds=time.perf_counter() - wall,
        stopped_early=not finished,
        field_cache=sim.field_cache_stats(),
    )
