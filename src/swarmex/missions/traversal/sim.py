"""Discrete-event simulation of the traversal mission (seed 000, chapters 3–5).

Timing model (spec §6.7): each agent is a client that enters the mission
``start_interval`` seconds after the previous one (0.5 s in the thesis's simulations) plus
its own takeoff time, then loops LOOK–COMPUTE–MOVE. A move along an edge takes
``edge length × unit_length / travel_speed`` seconds, a job ``job_time`` seconds. Decisions
take no time. Messages follow §4.2 and are applied to the receivers' beliefs when they
arrive (instantly under the default perfect broadcast):

* C01 / position — an agent's current vertex, sent at start and at every arrival, with the
  obstacles it sees there (sensing is adjacency only) and the job bit;
* C05 — the next vertex, sent when a move is decided; a vacant one is reserved for the sender;
* C07 — arrival with the job bit set: the vertex is conditionally accomplished;
* C08 — job done; with ``job_failure`` > 0 a job may fail instead, and the vertex returns to
  not-done (the agent, still there, sees it vacant and retries);
* with an imperfect channel every message also carries the sender's done-nodes list of §4.1
  (done nodes while fewer than half are done, then the not-done nodes), which is what keeps
  beliefs convergent when messages are lost or out of range.

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
from swarmex.missions.base import StopRun
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.belief import (
    DONE_BY_UNKNOWN,
    JOB,
    NEXT,
    POS,
    UNDONE,
    BeliefTable,
    TraversalBelief,
    deliver,
)
from swarmex.missions.traversal.policies import Madgta, make_policy
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
        self._heap: list[tuple] = []
        self._seq = 0
        self.now = 0.0

    def schedule(self, time: float, kind: str, agent: int = -1, data=None) -> None:
        if time < self.now - 1e-12:
            raise ValueError(f"cannot schedule into the past ({time} < {self.now})")
        heapq.heappush(self._heap, (float(time), self._seq, kind, agent, data))
        self._seq += 1

    def pop(self) -> tuple:
        ev = heapq.heappop(self._heap)
        self.now = ev[0]
        return ev

    def __len__(self) -> int:
        return len(self._heap)

    def __bool__(self) -> bool:
        return bool(self._heap)


# kind -> deliver() code; 0: nothing for the receivers to do ("done" carries no state here)
_KIND_CODES = {"pos": POS, "job": JOB, "next": NEXT, "undone": UNDONE, "done": 0}


@dataclass
class AgentLog:
    """What one agent did: the thesis's PATH plus timed positions and jobs."""

    id: int
    spec: AgentSpec
    path: list[tuple[int, bool]] = field(default_factory=list)  # (vertex, job done there)
    trajectory: list[tuple[float, int]] = field(default_factory=list)  # (t, vertex)
    jobs: list[tuple[float, int]] = field(default_factory=list)  # (t job started, vertex)
    moves: int = 0
    travel_time: float = 0.0
    job_time: float = 0.0
    failed_jobs: int = 0
    nest_job: bool = False
    finished_at: float = float("nan")
    rtl_length: float = 0.0
    decisions_by_branch: list[int] = field(default_factory=lambda: [0, 0, 0, 0])

    @property
    def node(self) -> int:
        return self.trajectory[-1][1]


@dataclass(frozen=True)
class TraversalFrame:
    """One moment of a traversal run, for ``on_frame`` (a notebook's animation, a monitor):
    the event that just happened and where every started agent is (cells x, y)."""

    t: float  # seconds
    event: str  # "start" | "arrive" | "job_end"
    agent: int  # the agent the event happened to
    positions: tuple[tuple[int, float, float], ...]  # (agent id, x, y)
    jobs_done: int  # vertices with at least one job started


@dataclass
class TraversalRun:
    world: object
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
    field_cache: dict = field(default_factory=dict)

    @property
    def complete(self) -> bool:
        return bool(np.all(self.job_count[self.reachable] >= 1)) and not self.stopped_early

    def path_strings(self, label=None) -> list[str]:
        """PATH of each agent in the thesis's notation (``v`` and ``v*``)."""
        label = label or (lambda v: str(v))
        return [
            "-".join(f"{label(v)}-{label(v)}*" if job else label(v) for v, job in a.path)
            for a in self.agents
        ]


class _Sim:
    def __init__(
        self,
        world,
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
        self.policy = policy
        self.rng = rng
        self.channel = channel
        self.unit_length = unit_length
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
        self.beliefs = [None] + [
            TraversalBelief(
                i, m, shared or KnownGraph(self.graph, capacity=2 * m + 8), tpu, jt,
                table=self.table,
            )
            for i in range(1, m + 1)
        ]
        self.logs = [AgentLog(i, s) for i, s in enumerate(specs, start=1)]
        self.active = np.zeros(m + 1, dtype=bool)
        self.pos_xy = np.zeros((m + 1, 2))
        self.done_by = np.zeros(self.graph.n_nodes, dtype=np.int32)
        self.job_count = np.zeros(self.graph.n_nodes, dtype=np.int32)
        self.queue = _Clock()
        self._home_fields: dict[int, np.ndarray] = {}  # nest -> true distances (for RTL)
        self.messages = 0
        self.message_bytes = 0

    # ---------------------------------------------------------------- messaging
    def broadcast(self, sender: int, kind: str, node: int, obstacles=(), eta: float = 0.0):
        self.messages += 1
        belief = self.beliefs[sender]
        done_list = None
        # ID, node, job bit, done bit, checksum: 4 + 4 + 1 + 1 + 4 bytes, plus obstacle ids
        size = 14 + 4 * len(obstacles)
        if not self.channel.perfect:
            done_list = _encode_km(belief.status)
            size += 4 * (done_list[1].size + done_list[3].size)
        self.message_bytes += size
        if self.table is not None:  # perfect broadcast: every other belief, in one call
            code = _KIND_CODES[kind]
            if code or obstacles:
                belief.known.add_obstacles(obstacles)  # shared: a no-op, the sender saw them
                t = self.table
                deliver(code, sender, node, np.asarray(obstacles, dtype=np.int64), eta,
                        t.status, t.reserved, t.loc, t.reservation, t.next_loc, t.free_at)
            return
        msg = (kind, sender, node, tuple(obstacles), eta, done_list)
        if self.channel.perfect:
            for r in range(1, self.m + 1):
                if r != sender:
                    self.apply(self.beliefs[r], msg)
            return
        receivers = self.channel.receivers(sender - 1, self.pos_xy[1:], self.rng)
        for r in receivers + 1:
            if self.channel.delay > 0:
                self.queue.schedule(self.queue.now + self.channel.delay, "deliver", int(r), msg)
            else:
                self.apply(self.beliefs[r], msg)

    def apply(self, b: TraversalBelief, msg) -> None:
        kind, s, node, obstacles, eta, done_list = msg
        if obstacles:
            b.see_obstacles(obstacles)
        if done_list is not None:
            _merge_done_list(b, done_list)
        if kind == "pos":
            b.loc[s] = node
            b.release(s)
        elif kind == "job":  # C07
            b.loc[s] = node
            b.mark_done(node, s)
            b.next_loc[s] = node
            b.free_at[s] = eta
        elif kind == "next":  # C05
            b.reserve(node, s)
            b.next_loc[s] = node
            b.free_at[s] = eta
        elif kind == "undone":
            b.mark_not_done(node)

    # ---------------------------------------------------------------- agent steps
    def sense(self, a: int, node: int) -> list[int]:
        nbrs = self.graph.neighbors(node)
        seen = nbrs[self.truth_blocked[nbrs]]
        new = [int(v) for v in seen if self.beliefs[a].status[v] != -1]
        self.beliefs[a].see_obstacles(new)
        return new

    def arrive_at(self, a: int, node: int, t: float) -> None:
        log = self.logs[a - 1]
        log.trajectory.append((t, node))
        self.pos_xy[a] = self.graph.pos[node]
        b = self.beliefs[a]
        b.loc[a] = node
        b.now = t
        seen = self.sense(a, node)
        do_job = b.job_on_arrival(node)
        b.intent = -1
        if do_job:
            self.start_job(a, node, t, seen)
        else:
            log.path.append((node, False))
            b.release(a)
            self.broadcast(a, "pos", node, seen)
            self.decide(a, t)

    def start_job(self, a: int, node: int, t: float, seen=()) -> None:
        log = self.logs[a - 1]
        b = self.beliefs[a]
        if not log.path or log.path[-1][0] != node:
            log.path.append((node, False))
        b.mark_done(node, a)
        log.jobs.append((t, node))
        self.job_count[node] += 1
        if self.done_by[node] == 0:
            self.done_by[node] = a
        end = t + self.specs[a - 1].job_time
        self.broadcast(a, "job", node, seen, eta=end)
        self.queue.schedule(end, "job_end", a, node)

    def end_job(self, a: int, node: int, t: float) -> None:
        log = self.logs[a - 1]
        log.job_time += self.specs[a - 1].job_time
        if self.job_failure > 0 and self.rng.random() < self.job_failure:
            log.failed_jobs += 1
            self.job_count[node] -= 1
            if self.job_count[node] == 0:
                self.done_by[node] = 0
            self.beliefs[a].mark_not_done(node)
            self.broadcast(a, "undone", node)
        else:
            log.path[-1] = (node, True)
            if log.moves == 0:
                log.nest_job = True
            self.broadcast(a, "done", node)
        self.decide(a, t)

    def decide(self, a: int, t: float) -> None:
        b = self.beliefs[a]
        b.now = t
        d = self.policy.decide(b, self.rng)
        log = self.logs[a - 1]
        log.decisions_by_branch[d.branch] += 1
        if d.kind == "job":
            self.start_job(a, d.node, t)
        elif d.kind == "move":
            here = b.here
            dt = _edge_length(self.graph, here, d.node) * b.time_per_unit[a]
            b.announce_move(d.node)
            b.known.prefetch(d.node, here)  # its field, shifted in the background
            self.broadcast(a, "next", d.node, eta=t + dt)
            log.moves += 1
            log.travel_time += dt
            self.queue.schedule(t + dt, "arrive", a, d.node)
        else:
            self.finish(a, t)

    def finish(self, a: int, t: float) -> None:
        log = self.logs[a - 1]
        log.finished_at = t
        self.active[a] = False
        nest = self.specs[a - 1].nest
        home = self._home_fields.get(nest)
        if home is None:  # agents sharing a nest share the field
            home = self._home_fields[nest] = distance_field(self.graph, nest, self.truth_blocked)
        log.rtl_length = float(home[log.node])

    def field_cache_stats(self) -> dict:
        caches = {id(b.known): b.known for b in self.beliefs[1:]}.values()
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
        while self.queue:
            t, _, kind, a, data = self.queue.pop()
            handled += 1
            if handled > max_events:
                return False
            if kind == "arrive":
                self.arrive_at(a, data, t)
            elif kind == "job_end":
                self.end_job(a, data, t)
            elif kind == "start":
                self.active[a] = True
                nest = self.specs[a - 1].nest
                self.logs[a - 1].trajectory.append((t, nest))
                self.pos_xy[a] = self.graph.pos[nest]
                b = self.beliefs[a]
                b.loc[a] = nest
                seen = self.sense(a, nest)
                self.broadcast(a, "pos", nest, seen)
                self.decide(a, t)
            elif kind == "deliver":
                self.apply(self.beliefs[a], data)
                continue
            if on_frame is not None:
                try:
                    on_frame(self.frame(t, kind, a))
                except StopRun:
                    return False
        return True

    def frame(self, t: float, kind: str, agent: int) -> TraversalFrame:
        """What the run looks like at ``t``: each started agent's vertex and the jobs done."""
        pos = self.graph.pos
        where = tuple(
            (log.id, *(float(c) for c in pos[log.trajectory[-1][1]]))
            for log in self.logs
            if log.trajectory
        )
        return TraversalFrame(float(t), kind, int(agent), where, int((self.job_count > 0).sum()))


def _edge_length(graph, u: int, v: int) -> float:
    """NodeGraph.edge_length (first matching edge) without its numpy set-up cost."""
    lo = int(graph.indptr[u])
    for k, x in enumerate(graph.indices[lo : graph.indptr[u + 1]].tolist()):
        if x == v:
            return float(graph.weights[lo + k])
    return graph.edge_length(u, v)  # raises KeyError naming the pair


def _encode_done_list(status: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
    """§4.1's done-nodes field: (bit, vertex list, doer ids).

    Bit 1: the list holds the done vertices (fewer than half are done). Bit 0: it holds the
    not-done vertices instead, which is shorter once half the graph is done.
    """
    done = status > 0
    if done.sum() * 2 < status.size:
        idx = np.nonzero(done)[0]
        return 1, idx, status[idx]
    return 0, np.nonzero(status == 0)[0], np.zeros(0, dtype=np.int32)


def _encode_km(status: np.ndarray) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """What an imperfect channel's message carries: the thesis's KM, done ∪ known obstacles.

    §4.1 defines the list as KM, and KM includes the obstacles; the done / not-done list of
    :func:`_encode_done_list` cannot tell a receiver which of its vertices are walls, so the
    sender's known obstacles ride along as a fourth field (4 bytes each). Without them an
    agent that missed the one message announcing a wall plans paths through it for the rest
    of the mission: under 30 % loss that cost up to 4x the travel on room maps
    (docs/traversal-variants.md).
    """
    bit, idx, doers = _encode_done_list(status)
    return bit, idx, doers, np.nonzero(status == -1)[0]


def _merge_done_list(b: TraversalBelief, done_list) -> None:
    """Merge a received done-nodes field (with or without its KM obstacles) into ``b``.

    Obstacles first, so that the not-done form (everything not listed is done) does not mark
    a known wall as a done vertex.
    """
    bit, idx, doers, *obstacles = done_list
    if obstacles:
        walls = obstacles[0]
        new = walls[b.status[walls] != -1]
        if new.size:
            b.see_obstacles(new.tolist())
    if bit:
        fresh = b.status[idx] == 0
        for v, k in zip(idx[fresh], doers[fresh], strict=True):
            b.mark_done(int(v), int(k))
    else:
        mask = np.ones(b.status.size, dtype=bool)
        mask[idx] = False
        fresh = np.nonzero(mask & (b.status == 0))[0]
        for v in fresh:
            b.mark_done(int(v), int(DONE_BY_UNKNOWN))


def validate_nests(world, specs: list[AgentSpec], shared_nests: bool = True) -> None:
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
    world,
    agents: list[AgentSpec],
    algorithm: str = "madgta",
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
        agents=sim.logs,
        done_by=sim.done_by,
        job_count=sim.job_count,
        reachable=reach,
        algorithm=policy.name,
        seed=seed,
        messages=sim.messages,
        message_bytes=sim.message_bytes,
        wall_seconds=time.perf_counter() - wall,
        stopped_early=not finished,
        field_cache=sim.field_cache_stats(),
    )
