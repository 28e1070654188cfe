"""The traversal mission as a protocol: what the server and every agent derive from the stream.

Seed 000 ran MADGTA as one TCP client per UAV and a server that relays every broadcast to
all agents and never tells one what to do (§4.1–4.3). swarmex does the same over ZeroMQ and
runs the very agent core the simulator runs,
:class:`~swarmex.missions.traversal.agent.TraversalAgent` (belief, policy, arrival rule,
messages, how a received one is applied); :class:`AgentCore` adds only this runtime's glue.
The point of the design below is that a networked run is *the same run* as ``swarmex
traverse`` with the same seed: same decisions, same times, same record (bar the wall clock
and the byte counts).

Why that needs more than relaying messages in real time: in the simulator two events at the
same mission time run in a fixed order (time, then scheduling order — see
:mod:`swarmex.engine.events`), each decision sees every message sent before it, and all
random tie-breaks come from *one* generator. Over a network, two agents whose events fall on
the same instant would decide concurrently, each blind to the other's C05, and each process
has its own generator. So the runtime is a conservative distributed discrete-event
execution, built only from what the agents broadcast anyway:

* Every agent's next event is public. C05 carries the arrival time (``eta``), C07 with the
  job bit the end of the job, C09 says there is none; the start events follow from the
  mission data. Each participant numbers events in stream order exactly as the simulator's
  queue numbers them (``seq``), so everybody knows everybody's next event key ``(t, seq)``.
* An agent processes its next event only when its key is the smallest of all active agents'
  keys (and, in real-time mode, when the scaled wall clock has reached it). Its last message
  of the step announces its next key; the server relays it to everyone *including the
  sender*, and keys change only when the relayed copy arrives, so the one stream order of
  the server is the order everybody applies.
* The run's generator travels with the step: the last message of a step carries the
  generator's state after the step's draws, and the next agent to act loads it. That is the
  simulator's single ``numpy.random.Generator`` shared by hand (``rng_mode="own"`` gives
  each agent its own generator instead: decentralised, but no longer the simulated run).

Mission times are therefore computed, not measured: a C05 at time ``t`` arrives at ``t +
edge × seconds per unit``, the same float operations as the simulator. Wall-clock jitter
cannot move them; it only delays when events are *executed*, which each agent measures and
reports as its lag (the record's ``network.lag_*``, in mission seconds). The makespan of a
networked run equals the simulated one's exactly (0 s timing noise) on 4-connected grids;
on 8-connected grids the float distance cache may differ in the last bits between the
simulator's shared cache and an agent's own (see :mod:`swarmex.planning.fieldcache`), which
could in principle flip a tie.

Faults: the server declares an agent gone when it falls silent (no heartbeat) and relays
``LEFT``: everybody drops its next event, reverts its conditionally accomplished node (a job
started with C07 and not finished with C08) to not-done, releases its reserved node and
stops counting it as a rival. A spare may then take the vacant id: it replays the stream so
far (the server keeps it) to rebuild the same belief and key table, and the server relays
``JOIN`` with its start time (no earlier than any event still to run, plus its takeoff), so
the order stays consistent.

Done-nodes lists (Fig. 4.17) are carried (``--no-done-lists`` drops them) with the sender's
known obstacles (the ``walls`` field: the list is the thesis's KM, as the simulator's agents
send it over an imperfect channel) and merged by every receiver exactly as in the simulator
(:func:`~swarmex.missions.traversal.agent.merge_done_list`). On the reliable, ordered relay a
list never tells a receiver anything new in a fault-free run (each sender has applied
everything before its step, and receivers have too), so it cannot move a run off the
simulated one. After a departure, a list sent before its sender heard ``LEFT`` still counts
the departed agent's unfinished node as done; the core never lets a list re-mark a node it
reverted that way (only a C07 for it does).

Lost messages (``serve --inject-loss P``, :class:`Loss`): the server draws, for every relayed
broadcast and every other agent, whether that agent's radio lost it, and then sends that
agent a ``LOST`` wrapper instead of the frame. A ``LOST`` frame still moves the receiver's
:class:`Replica` (the event keys, the shared generator: the harness's clock, as the
simulator's event queue runs whatever the radio loses) but never its belief, which is what
the simulator's lossy :class:`~swarmex.comm.channel.Channel` does to a receiver. That is
where the done-nodes lists earn their bytes: a receiver that missed a C07 learns the node is
done from the next list it hears instead of doing it again.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from swarmex.errors import InputError, check_number
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
    DoneList,
    Message,
    TraversalAgent,
    apply_message,
    forget_rival,
)
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.belief import (
    DONE_BY_UNKNOWN,
    TeamPlan,
    TraversalBelief,
    route_cells,
)
from swarmex.missions.traversal.policies import Madgta, make_policy
from swarmex.net.wire import (
    BROADCAST_COMMANDS,
    Broadcast,
    EncodingError,
    WireError,
    decode_broadcast,
    rng_state,
    set_rng_state,
)
from swarmex.planning.distance import distance_field
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import GridWorld
from swarmex.worlds.geo import GeoGrid

RNG_MODES = ("shared", "own")
#: the broadcasts of an agent's step, which change beliefs: the ones a lossy radio can lose
#: (``serve --inject-loss``); C06, C10 and C11 carry nothing a receiver applies
LOSSY = ("C04", "C05", "C07", "C08", "C09")
#: commands that end an agent's step: they announce its next event (or that there is none)
STEP_END = ("C05", "C07", "C09")


def ends_step(b: Broadcast) -> bool:
    """C05, C07 with the job bit, C09: the last message of an agent's step."""
    return b.cmd in STEP_END and (b.cmd != "C07" or bool(b.job))


# ---------------------------------------------------------------------------- mission data


def _edge_length(value: Any) -> float | None:
    if value is None:
        return None
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError("bad edge length")
    return v


@dataclass
class Mission:
    """Everything the server hands out with C22 (seed 000 §4.2), and the record's params."""

    world: GridWorld
    specs: list[AgentSpec]
    algorithm: str = "madgta"
    seed: int = 0
    start_interval: float = 0.5
    unit_length: float = 1.0
    job_failure: float = 0.0
    time_scale: float = 0.01  # wall seconds per mission second (0: as fast as possible)
    rng_mode: str = "shared"
    done_lists: bool = True  # Fig. 4.17's done-nodes field on every broadcast
    heartbeat: float = 0.25  # wall seconds between heartbeats
    params: dict = field(default_factory=dict)
    edge_length: float | None = None  # serve --edge-length: metres a real vehicle flies per edge

    def __post_init__(self) -> None:
        if self.rng_mode not in RNG_MODES:
            raise InputError(f"rng mode must be shared or own, got {self.rng_mode!r}")
        check_number(self.time_scale, "--time-scale", at_least=0)
        check_number(self.start_interval, "--start-interval", at_least=0)
        if not 0.0 <= self.job_failure < 1.0:
            raise InputError(f"--job-failure must be in [0, 1), got {self.job_failure}")
        make_policy(self.algorithm)  # fails now on an unknown name

    @property
    def n_agents(self) -> int:
        return len(self.specs)

    def start_key(self, agent: int) -> tuple[float, int]:
        """The start event of agent ``agent`` (1-based), as the simulator schedules it."""
        i = agent - 1
        t0 = 0.0
        return (t0 + i * self.start_interval + self.specs[i].takeoff_time, i)

    def to_wire(self) -> dict:
        w = self.world
        world: dict[str, Any] = {
            "width": w.width,
            "height": w.height,
            "free": np.packbits(w.free.ravel()).tobytes(),
            "connectivity": w.connectivity,
            "source": w.source,
        }
        if isinstance(w, GeoGrid):  # the GPS table (seed 000's graph table) and edge lengths
            world["geo"] = {
                "center": list(w.center),
                "radius": w.radius,
                "latlon": w.latlon_array.astype("<f8").tobytes(),
                "lengths": w.lengths().astype("<f8").tobytes(),
            }
        return {
            "world": world,
            "agents": [s.to_dict() for s in self.specs],
            "algorithm": self.algorithm,
            "seed": self.seed,
            "start_interval": self.start_interval,
            "unit_length": self.unit_length,
            "job_failure": self.job_failure,
            "time_scale": self.time_scale,
            "rng_mode": self.rng_mode,
            "done_lists": self.done_lists,
            "heartbeat": self.heartbeat,
            "edge_length": self.edge_length,
            "commands": ["C00", "C22", "C01", "C02", "C03", "C04", "C05", "C06", "C07",
                         "C08", "C09", "C10", "C11"],
            "params": self.params,
        }

    @classmethod
    def from_wire(cls, d: Any) -> Mission:
        """The mission of a MIS reply; :class:`EncodingError` if anything is malformed."""
        try:
            wd = d["world"]
            width, height = int(wd["width"]), int(wd["height"])
            if not (width > 0 and height > 0 and width * height <= 16_000_000):
                raise ValueError("bad grid size")
            bits = np.frombuffer(wd["free"], dtype=np.uint8)
            if bits.size != (width * height + 7) // 8:
                raise ValueError("free-cell bits do not fit the grid size")
            free = np.unpackbits(bits, count=width * height).astype(bool)
            world = _world_of(wd, free.reshape(height, width))
            specs = [
                AgentSpec(
                    int(a["nest"]), float(a["travel_speed"]), float(a["job_time"]),
                    float(a["altitude"]), float(a["up_speed"]), float(a["down_speed"]),
                )
                for a in d["agents"]
            ]
            if not specs or any(not 0 <= s.nest < world.n_nodes for s in specs):
                raise ValueError("bad agents")
            return cls(
                world,
                specs,
                str(d["algorithm"]),
                int(d["seed"]),
                float(d["start_interval"]),
                float(d["unit_length"]),
                float(d["job_failure"]),
                float(d["time_scale"]),
                str(d["rng_mode"]),
                bool(d["done_lists"]),
                float(d["heartbeat"]),
                dict(d.get("params") or {}),
                _edge_length(d.get("edge_length")),
            )
        except (KeyError, TypeError, ValueError, InputError, AttributeError) as exc:
            raise EncodingError(f"mission data: {exc}") from None

    def latlon(self, node: int) -> tuple[float, float] | None:
        """Where ``node`` is on the Earth (a GPS grid), else None."""
        w = self.world
        return w.latlon(node) if isinstance(w, GeoGrid) else None

    def time_per_unit(self) -> np.ndarray:
        """Seconds per length unit by id (slot 0 unused), computed as the simulator does."""
        tpu = np.zeros(self.n_agents + 1)
        for i, s in enumerate(self.specs, start=1):
            tpu[i] = self.unit_length / s.travel_speed
        return tpu

    def job_times(self) -> np.ndarray:
        jt = np.zeros(self.n_agents + 1)
        for i, s in enumerate(self.specs, start=1):
            jt[i] = s.job_time
        return jt


def _world_of(wd: Any, free: np.ndarray) -> GridWorld:
    """The grid of a MIS reply: plain, or a GPS grid with its positions and edge lengths
    (ValueError / InputError when they do not fit)."""
    connectivity, source = int(wd["connectivity"]), str(wd["source"])
    geo = wd.get("geo")
    if geo is None:
        return GridWorld(free, connectivity, source)
    n = free.size
    latlon = np.frombuffer(geo["latlon"], dtype="<f8")
    lengths = np.frombuffer(geo["lengths"], dtype="<f8")
    if latlon.size != 2 * n or not np.all(np.isfinite(latlon)):
        raise ValueError("GPS table does not fit the grid")
    if not (np.all(np.isfinite(lengths)) and np.all(lengths > 0)):
        raise ValueError("bad edge lengths")
    lat, lon = (float(v) for v in geo["center"])
    world = GeoGrid(free, connectivity, latlon.reshape(n, 2).astype(float), (lat, lon),
                    float(geo["radius"]), source, lengths.astype(float))
    u, _, _ = world.edge_arrays()
    if u.size != lengths.size:
        raise ValueError("edge lengths do not fit the grid")
    return world


# ---------------------------------------------------------------------------- shared view


class Replica:
    """The part of the mission state everybody derives from the stream in the same order:
    each active agent's next event key, the event counter, the shared generator's state, and
    each agent's conditionally accomplished node."""

    def __init__(self, mission: Mission) -> None:
        self.mission = mission
        self.pending: dict[int, tuple[float, int] | None] = {
            i: mission.start_key(i) for i in range(1, mission.n_agents + 1)
        }
        self.counter = mission.n_agents
        self.rng = rng_state(np.random.default_rng(mission.seed))
        self.open_job: dict[int, int] = {}
        self.last_t = 0.0  # time of the latest event seen (stream order is time order)

    def on_broadcast(self, b: Broadcast) -> None:
        if b.cmd in ("C05", "C07", "C08", "C04"):
            self.last_t = max(self.last_t, b.t)
        if b.cmd == "C05" or (b.cmd == "C07" and b.job):
            self.pending[b.id] = (b.eta, self.counter)
            self.counter += 1
        elif b.cmd == "C09":
            self.pending[b.id] = None
        if ends_step(b) and b.rng is not None:
            self.rng = b.rng
        if b.cmd == "C07" and b.job:
            self.open_job[b.id] = b.node
        elif b.cmd == "C08":
            self.open_job.pop(b.id, None)

    def on_left(self, agent: int) -> int:
        """Drop a departed agent; returns its unfinished job's node (or -1)."""
        self.pending.pop(agent, None)
        return self.open_job.pop(agent, -1)

    def on_join(self, agent: int, t: float, seq: int) -> None:
        self.pending[agent] = (t, seq)
        self.counter = max(self.counter, seq + 1)

    def next_agent(self) -> int | None:
        """The agent whose event comes first (None when nobody has one)."""
        best, key = None, None
        for a, k in self.pending.items():
            if k is not None and (key is None or k < key):
                best, key = a, k
        return best

    def min_time(self) -> float:
        times = [k[0] for k in self.pending.values() if k is not None]
        return min(times) if times else self.last_t


#: the one command whose node may be -1 (no node): a finish says where its agent is, and the
#: wire has always allowed -1 there; everywhere else -1 would be Python's last vertex
NODELESS = ("C09",)


def check_broadcast(b: Broadcast, mission: Mission, here: int | None = None) -> None:
    """Content checks a decoder cannot do without the mission (node and id ranges), and,
    given ``here`` (the sender's node, which the server knows from the stream), the moves:
    a C05 names a neighbour of ``here``, a C07 ``here`` or a neighbour.

    Why the server checks moves before it relays: a well-formed C05 to a node that is not
    adjacent used to pass, be relayed to every agent, and then crash ``serve`` in the
    recorder (``KeyError: no edge``) with no record written. And node -1 is refused in
    every command but C09: numpy's negative index made a C07 at -1 mark the last vertex
    done (in the record and in every agent's belief) though nobody went there."""
    n = mission.world.n_nodes
    if b.id > mission.n_agents:
        raise EncodingError(f"broadcast from unknown agent {b.id}")
    if not (-1 if b.cmd in NODELESS else 0) <= b.node < n:
        raise EncodingError(f"node {b.node} outside the map")
    if b.cmd == "C04" and b.node != mission.specs[b.id - 1].nest:
        raise EncodingError(f"C04: agent {b.id} starts at its nest, not node {b.node}")
    if (here is not None and (b.cmd == "C05" or (b.cmd == "C07" and b.node != here))
            and not bool(np.any(mission.world.graph.neighbors(here) == b.node))):
        raise EncodingError(f"{b.cmd}: node {b.node} is not next to node {here}")
    for arr in (b.nodes, b.doers if not b.done_bit else None):
        if arr is not None and arr.size and arr.max() >= n:
            raise EncodingError("listed node outside the map")
    if b.obstacles and max(b.obstacles) >= n:
        raise EncodingError("obstacle outside the map")
    if b.walls is not None and b.walls.size and b.walls.max() >= n:
        raise EncodingError("known obstacle outside the map")
    if b.plan is not None:
        _, lens, nodes = b.plan
        if lens.size != mission.n_agents + 1 or lens[0]:
            raise EncodingError("plan: one route per agent")
        if nodes.size > n:  # a plan holds a vertex once (and receivers size arrays by it)
            raise EncodingError("plan: more vertices than the map")
        if nodes.size and nodes.max() >= n:
            raise EncodingError("planned node outside the map")
    if b.done_bit and b.doers is not None and b.doers.size:
        ok = ((b.doers >= 1) & (b.doers <= mission.n_agents)) | (b.doers == DONE_BY_UNKNOWN)
        if not ok.all():  # receivers merge the list: a doer is an agent id
            raise EncodingError("listed doer is not an agent")


def message_of(b: Broadcast) -> Message:
    """A broadcast as the agent core's :class:`~swarmex.missions.traversal.agent.Message`:
    C04 is ``start``, C07 ``job`` or ``pass`` (job bit), C05 ``next``, C08 ``done`` or
    ``undone`` (job bit); C06 and C09–C11 change no belief but may carry obstacles and a
    done-nodes list. An empty done list (``--no-done-lists``) is no list."""
    cmd = b.cmd
    if cmd == "C07":
        kind = JOB if b.job else PASS
    elif cmd == "C08":
        kind = DONE if b.job else UNDONE
    elif cmd == "C09" and b.job:  # the finish of an agent that may stop early (its leave)
        kind = LEAVE
    else:
        kind = _KIND_OF.get(cmd, cmd)
    done_list: DoneList | None = None
    if b.nodes is not None and (b.nodes.size or not b.done_bit):
        doers = b.doers if b.doers is not None else np.zeros(0, dtype=np.int64)
        if b.walls is not None:
            done_list = (b.done_bit, b.nodes, doers, b.walls)
        else:
            done_list = (b.done_bit, b.nodes, doers)
    return Message(kind, b.id, b.node, b.obstacles, b.eta, b.t, done_list)


_KIND_OF = {"C04": START, "C05": NEXT}
_CMD_OF = {
    START: ("C04", 0), PASS: ("C07", 0), JOB: ("C07", 1), NEXT: ("C05", 0),
    DONE: ("C08", 1), UNDONE: ("C08", 0),
}


def plan_of(b: Broadcast) -> Message | None:
    """The ``plan`` message riding on a decision's broadcast (madgta-s), as the agent core
    sent it after the decision's own; ``None`` without a plan."""
    if b.plan is None:
        return None
    t, lens, nodes = b.plan
    routes = np.full((lens.size, int(lens.max(initial=0)) + 1), -1, dtype=np.int64)
    routes[route_cells(lens, routes.shape[1])] = nodes  # row by row: the wire's order
    return Message(PLAN, b.id, b.node, t=b.t, plan=TeamPlan(t, routes, lens.copy()))


def with_plan(b: Broadcast, plan: TeamPlan) -> Broadcast:
    """``b`` carrying a team plan (the inverse of :func:`plan_of`): a ``plan`` message goes
    in the frame of the decision it follows, so a step still ends with its C05 or C07."""
    lens = np.asarray(plan.lens, dtype=np.int64)
    nodes = plan.routes[route_cells(lens, plan.routes.shape[1])].astype(np.int64)
    return replace(b, plan=(float(plan.t), lens, nodes))


def broadcast_of(m: Message) -> Broadcast:
    """An agent core's message as the Fig. 4.17 broadcast (:func:`message_of` inverted): a
    done list with its fourth field, the sender's known obstacles, goes as ``walls``."""
    cmd, job = _CMD_OF[m.kind]
    bit, nodes, doers, walls = _km_fields(m.done_list)
    return Broadcast(cmd, m.sender, m.node, job, bit, nodes, doers, m.obstacles, float(m.t),
                     float(m.eta), walls=walls)


def _km_fields(
    done_list: DoneList | None,
) -> tuple[int, np.ndarray | None, np.ndarray | None, np.ndarray | None]:
    if done_list is None:
        return 1, None, None, None
    bit, nodes, doers, *walls = done_list
    return bit, nodes, doers, (walls[0] if walls else None)


class Loss:
    """Fault injection: which agents' radios lose a relayed broadcast (``serve
    --inject-loss``). One draw per other agent and broadcast, in id order, from a generator
    of its own seeded by the mission seed, so the same stream loses the same messages."""

    def __init__(self, n_agents: int, p: float, seed: int) -> None:
        if not 0.0 <= p < 1.0:
            raise InputError(f"--inject-loss must be in [0, 1), got {p}")
        self.n = n_agents
        self.p = p
        self.rng = np.random.default_rng([seed, 0x1055])
        self.lost = 0  # deliveries lost so far

    def draw(self, sender: int) -> np.ndarray:
        """Lost-or-not for every id (index id - 1); never for the sender, whose relayed
        copy is its acknowledgement."""
        if self.p <= 0:
            return np.zeros(self.n, dtype=bool)
        out = self.rng.random(self.n) < self.p
        out[sender - 1] = False
        self.lost += int(out.sum())
        return out


def messages_of(b: Broadcast) -> list[Message]:
    """A broadcast as the agent core's messages, in the order it sent them: the command's
    (:func:`message_of`), then the team plan riding on it, if any (:func:`plan_of`)."""
    plan = plan_of(b)
    return [message_of(b)] if plan is None else [message_of(b), plan]


def apply_to_belief(b: TraversalBelief, msg: Broadcast) -> None:
    """A broadcast applied to a belief by the agent core's rule
    (:func:`~swarmex.missions.traversal.agent.apply_message`), the simulator's: its
    obstacles, its done-nodes list merged, then the command's own update (and a plan it carries)."""
    for m in messages_of(msg):
        apply_message(b, m)


def forget_agent(b: TraversalBelief, agent: int, open_node: int) -> None:
    """A departed rival (``LEFT``): :func:`~swarmex.missions.traversal.agent.forget_rival`."""
    forget_rival(b, agent, open_node)


def catch_up(belief: TraversalBelief, replica: Replica, msg: list) -> None:
    """One message of the stream so far, applied as a late joiner applies it: every
    broadcast as a rival's (its predecessor's with the same id too: what it had done is
    done), ``LEFT`` and ``JOIN`` as everybody applied them."""
    if msg[0] in BROADCAST_COMMANDS:
        b = Broadcast.from_wire(msg)
        apply_to_belief(belief, b)
        replica.on_broadcast(b)
    elif msg[0] == "LEFT":
        a = int(msg[1])
        forget_agent(belief, a, replica.on_left(a))
    elif msg[0] == "JOIN":
        replica.on_join(int(msg[1]), float(msg[2]), int(msg[3]))


def new_belief(mission: Mission, me: int) -> TraversalBelief:
    m = mission.n_agents
    known = KnownGraph(mission.world.graph, capacity=2 * m + 8)
    return TraversalBelief(me, m, known, mission.time_per_unit(), mission.job_times())


# ---------------------------------------------------------------------------- agent steps


class AgentCore:
    """One networked agent: the mission's agent core
    (:class:`~swarmex.missions.traversal.agent.TraversalAgent`, :attr:`agent`: the very class
    the simulator runs) with this runtime's glue: which event is next, the shared
    generator's state loaded before a step, the job failure draw, the agent's messages
    turned into broadcasts (the last of a step carrying the generator's state), and the
    termination stage's C09.

    The policy sees only :attr:`belief`; the true map is used for what the simulator also
    takes from it: this agent's adjacency sensing and its flight home.
    """

    def __init__(self, mission: Mission, me: int, policy: Madgta | None = None) -> None:
        self.mission = mission
        self.me = me
        self.spec = mission.specs[me - 1]
        world = mission.world
        seed = mission.seed if mission.rng_mode == "shared" else [mission.seed, me]
        self._said: list[Message] = []
        self.agent = TraversalAgent(
            me, self.spec, new_belief(mission, me), policy or make_policy(mission.algorithm),
            np.random.default_rng(seed), AdjacencySensor(world.graph, world.blocked),
            self._said.append, done_lists=mission.done_lists,
        )
        self.next_kind = "start"
        self.next_node = self.spec.nest
        self.outbox: list[Broadcast] = []
        self.finished = False

    @property
    def belief(self) -> TraversalBelief:
        return self.agent.belief

    @property
    def log(self) -> AgentLog:
        return self.agent.log

    # ---- stream
    def receive(self, msg: Broadcast) -> None:
        for m in messages_of(msg):
            self.agent.receive(m)

    def forget(self, agent: int, open_node: int) -> None:
        self.agent.forget(agent, open_node)

    # ---- one event
    def step(self, t: float, rng: bytes | None) -> list[Broadcast]:
        """Run this agent's next event at time ``t``; returns the broadcasts, in order."""
        agent = self.agent
        self._said.clear()
        if rng is not None and self.mission.rng_mode == "shared":
            set_rng_state(agent.rng, rng)
        kind, node = self.next_kind, self.next_node
        if kind == "start":
            nxt = agent.start(t)
        elif kind == "arrive":
            nxt = agent.arrive(node, t)
        else:
            fail = self.mission.job_failure
            nxt = agent.end_job(node, t, fail > 0 and agent.rng.random() < fail)
        out: list[Broadcast] = []
        leaves = False
        for m in self._said:
            if m.kind == PLAN and m.plan is not None:  # rides on the decision it follows
                out[-1] = with_plan(out[-1], m.plan)
            elif m.kind == LEAVE:  # said as the agent finishes: the C09 below carries it
                leaves = True
            else:
                out.append(broadcast_of(m))
        if nxt.kind == "finish":
            out.append(self._finish(t, leaves))
        else:
            self.next_kind, self.next_node = nxt.kind, nxt.node
        out[-1] = replace(out[-1], rng=rng_state(agent.rng))  # the step's last message
        self.outbox = out
        return out

    def _finish(self, t: float, leaves: bool = False) -> Broadcast:
        """The termination stage's C09; with ``leaves`` (the agent core said ``leave``: a
        policy that may stop while vertices remain) its job bit is set, and receivers drop
        the agent as a rival, as the simulator's ``leave`` message makes them."""
        log = self.log
        world = self.mission.world
        log.rtl_length = float(distance_field(world.graph, self.spec.nest, world.blocked)[log.node])
        self.finished = True
        bit, nodes, doers, walls = 1, None, None, None
        if self.mission.done_lists:
            bit, nodes, doers, walls = _km_fields(self.agent.encode_done_list())
        return Broadcast("C09", self.me, log.node, int(leaves), bit, nodes, doers, (),
                         float(t), float(t + self.rtl_time()), walls=walls)

    def rtl_time(self) -> float:
        """Mission seconds of the flight home (C09 → C10)."""
        if not math.isfinite(self.log.rtl_length):
            return 0.0
        return self.log.rtl_length * self.mission.unit_length / self.spec.travel_speed

    def stats(self) -> dict:
        """The statistics uploaded after C11 (seed 000 §4.3: path, jobs, times)."""
        log = self.log
        return {
            "path": [[int(v), bool(j)] for v, j in log.path],
            "trajectory": [[float(t), int(v)] for t, v in log.trajectory],
            "jobs": [[float(t), int(v)] for t, v in log.jobs],
            "moves": log.moves,
            "travel_time": log.travel_time,
            "job_time": log.job_time,
            "failed_jobs": log.failed_jobs,
            "nest_job": log.nest_job,
            "finished_at": log.finished_at,
            "branches": list(log.decisions_by_branch),
        }


def run_inprocess(
    mission: Mission, loss: float = 0.0
) -> tuple[dict[int, AgentCore], Recorder]:
    """The protocol without sockets: every agent's core, replica and the server's recorder
    fed one stream, in the order the server would relay it. Equals the simulator's run
    (tests check it); the networked runtime adds only transport and wall-clock pacing.
    ``loss`` is ``serve --inject-loss``: the same draws, so the same messages are lost."""
    m = mission.n_agents
    cores = {i: AgentCore(mission, i) for i in range(1, m + 1)}
    replica = Replica(mission)
    recorder = Recorder(mission)
    lossy = Loss(m, loss, mission.seed)
    while (a := replica.next_agent()) is not None:  # (every step broadcast is in LOSSY)
        key = replica.pending[a]
        assert key is not None
        for b in cores[a].step(key[0], replica.rng):
            frame = b.frame()
            b = decode_broadcast(frame)
            replica.on_broadcast(b)
            recorder.on_broadcast(b, len(frame))
            lost = lossy.draw(b.id)
            for i, core in cores.items():
                if not lost[i - 1]:
                    core.receive(b)
    return cores, recorder


def warm_up() -> None:
    """A tiny mission in process, so the compiled kernels of every MADGTA branch are loaded
    before this process talks to anyone (a first call can take seconds, long enough to miss
    heartbeats; a UAV, too, does its pre-arm checks before it flies)."""
    from swarmex.missions.traversal.agents import uniform_agents

    free = np.ones((4, 4), dtype=bool)
    free[1, 1:3] = False
    world = GridWorld(free, 4, source="warm-up")
    run_inprocess(Mission(world, uniform_agents([0, 0, 15], 1.0, 1.0), seed=1))
    # and a team leaving one nest on an open grid: branch 3's far choice on the lattice
    # (its block tree), which the walled 4x4 never reaches; compiled at the first far
    # decision, it silenced every agent of a mission for ~3 s on a cold cache
    open_world = GridWorld(np.ones((6, 6), dtype=bool), 4, source="warm-up")
    run_inprocess(Mission(open_world, uniform_agents([0, 0, 0], 2.0, 9.0), seed=1))
    # and walls found late by agents from their own nests: the field cache's repair of a
    # tiled distance row (tests/net/test_warm_up.py checks that nothing is left to compile)
    run_inprocess(Mission(_walled_6x6(), uniform_agents([0, 5, 30], 2.0, 9.0), seed=1))


def _walled_6x6() -> GridWorld:
    """The warm-ups' small world with walls (three blocked cells)."""
    free = np.ones((6, 6), dtype=bool)
    free[[2, 3, 1], [2, 3, 4]] = False
    return GridWorld(free, 4, source="warm-up")


def has_own_kernels(algorithm: str) -> bool:
    """Whether a served algorithm has kernels :func:`warm_up` did not already load: every
    one but plain MADGTA, whose branches warm_up runs before the agent connects."""
    return algorithm != "madgta"


@functools.cache
def warm_policy(algorithm: str) -> None:
    """The kernels of a served algorithm other than MADGTA, compiled or loaded once per
    process. The agent calls it on a thread of its own (``net.agent.warm_in_background``)
    when the mission data names the algorithm, before it answers (C01), and keeps beating
    meanwhile. On a cold cache madgta-r compiled ~8 s of kernels at its first end-game
    decision and madgta-p ~5 s, on the agent's main thread, so the server declared the
    agents gone; compiling every algorithm's kernels before connecting instead doubled the
    first start of every agent (tests/net/test_warm_up.py checks both warm-ups).

    The walled 6x6 is all end game for the rollouts and team plans; the 10x10 with a wall
    reads hop rows through the field cache (not the lattice's closed form), where madgta+
    and nearest call kernels of their own, and gives madgta-k's sweep a turn before a short
    end game.
    """
    if not has_own_kernels(algorithm):
        return
    from swarmex.missions.traversal.agents import uniform_agents
    from swarmex.missions.traversal.partition import MadgtaK
    from swarmex.missions.traversal.policies import POLICIES, parse_algorithm
    from swarmex.missions.traversal.sim import run_traversal

    # warmed as the spec runs: an option may call other kernels (madgta-r@outside=madgta+)
    name, options = parse_algorithm(algorithm)

    team = uniform_agents([0, 0, 0], 2.0, 9.0)
    run_inprocess(Mission(_walled_6x6(), team, seed=1, algorithm=algorithm))
    big = np.ones((10, 10), dtype=bool)
    big[4, 2:8] = False
    world = GridWorld(big, 4, source="warm-up")
    if issubclass(POLICIES[name], MadgtaK):  # madgta-k and its followers (madgta-f)
        sweep = POLICIES[name](**{**options, "max_vacant": 20})
        run_traversal(world, team, algorithm=sweep, seed=1)
    elif name in ("madgta+", "nearest"):
        run_inprocess(Mission(world, team, seed=1, algorithm=algorithm))


# ---------------------------------------------------------------------------- server side


@dataclass
class Incarnation:
    """What the server saw of one agent process holding an id (a spare is a new one)."""

    log: AgentLog
    left_at: float | None = None
    abandoned_jobs: list[tuple[float, int]] = field(default_factory=list)
    stats: dict | None = None
    vehicle: dict | None = None  # what it flew (C01's description): hybrid missions


class Recorder:
    """Rebuilds every agent's log from the broadcasts, as the simulator keeps it, so the
    server can write the same record even for agents that never upload their statistics."""

    def __init__(self, mission: Mission) -> None:
        self.mission = mission
        self.world = mission.world
        self.graph = mission.world.graph
        self.tpu = mission.time_per_unit()
        n = self.graph.n_nodes
        self.done_by = np.zeros(n, dtype=np.int32)
        self.job_count = np.zeros(n, dtype=np.int32)
        self.current: dict[int, Incarnation] = {}
        self.departed: list[Incarnation] = []
        self.messages = 0  # the simulator's count: C04, C05, C07, C08
        self.message_bytes = 0

    def incarnation(self, agent: int) -> Incarnation:
        inc = self.current.get(agent)
        if inc is None:
            inc = Incarnation(AgentLog(agent, self.mission.specs[agent - 1]))
            self.current[agent] = inc
        return inc

    def position(self, agent: int) -> int:
        """Where ``agent`` is by the stream: its last arrival, else its nest (what a C05 of
        it must be next to: :func:`check_broadcast`'s ``here``)."""
        log = self.incarnation(agent).log
        return log.trajectory[-1][1] if log.trajectory else self.mission.specs[agent - 1].nest

    def on_join(self, agent: int) -> None:
        """A spare takes ``agent``'s id: the departed process's log is kept apart."""
        old = self.current.pop(agent, None)
        if old is not None:
            self.departed.append(old)

    def on_broadcast(self, b: Broadcast, nbytes: int) -> None:
        if b.cmd in ("C04", "C05", "C07", "C08") or (b.cmd == "C09" and b.job):
            # a plan is its own message, and so is a leave (C09's job bit), as simulated
            self.messages += 1 + (b.plan is not None)
            self.message_bytes += nbytes
        log = self.incarnation(b.id).log
        t, node = b.t, b.node
        if b.cmd == "C04":
            log.trajectory.append((t, node))
        elif b.cmd == "C07":
            arrival = not log.trajectory or log.trajectory[-1][1] != node
            if arrival:
                log.trajectory.append((t, node))
            if b.job:
                if not log.path or log.path[-1][0] != node:
                    log.path.append((node, False))
                log.jobs.append((t, node))
                self.job_count[node] += 1
                if self.done_by[node] == 0:
                    self.done_by[node] = b.id
            else:
                log.path.append((node, False))
        elif b.cmd == "C05":
            here = self.position(b.id)  # the server checked the move (check_broadcast)
            log.moves += 1
            log.travel_time += self.graph.edge_length(here, node) * self.tpu[b.id]
        elif b.cmd == "C08":
            log.job_time += self.mission.specs[b.id - 1].job_time
            if b.job:
                if log.path:
                    log.path[-1] = (node, True)
                if log.moves == 0:
                    log.nest_job = True
            else:
                log.failed_jobs += 1
                self._undo(node)
        elif b.cmd == "C09":
            log.finished_at = t
            nest = self.mission.specs[b.id - 1].nest
            here = log.trajectory[-1][1] if log.trajectory else nest
            log.rtl_length = float(distance_field(self.graph, nest, self.world.blocked)[here])

    def _undo(self, node: int) -> None:
        self.job_count[node] -= 1
        if self.job_count[node] == 0:
            self.done_by[node] = 0

    def on_left(self, agent: int, t: float, open_node: int) -> None:
        inc = self.current.get(agent)
        if inc is None:
            return
        inc.left_at = t
        if open_node >= 0 and inc.log.jobs and inc.log.jobs[-1][1] == open_node:
            inc.abandoned_jobs.append(inc.log.jobs.pop())
            self._undo(open_node)

    def reachable(self) -> np.ndarray:
        nests = [s.nest for s in self.mission.specs]
        reach = np.isfinite(distance_field(self.graph, nests, self.world.blocked))
        return reach & ~self.world.blocked


def check_stats(stats: Any, log: AgentLog) -> bool:
    """Whether an agent's uploaded statistics agree with what the server saw."""
    if not isinstance(stats, dict):
        return False
    try:
        same = (
            stats["moves"] == log.moves
            and stats["travel_time"] == log.travel_time
            and stats["job_time"] == log.job_time
            and [tuple(j) for j in stats["jobs"]] == [(t, v) for t, v in log.jobs]
            and [tuple(p) for p in stats["trajectory"]] == [(t, v) for t, v in log.trajectory]
        )
    except (KeyError, TypeError):
        return False
    return bool(same)


__all__ = [
    "LOSSY",
    "AgentCore",
    "Loss",
    "Mission",
    "Recorder",
    "Replica",
    "WireError",
    "apply_to_belief",
    "broadcast_of",
    "catch_up",
    "ends_step",
    "check_broadcast",
    "check_stats",
    "forget_agent",
    "has_own_kernels",
    "message_of",
    "run_inprocess",
    "warm_up",
]
