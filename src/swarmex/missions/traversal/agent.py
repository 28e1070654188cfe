"""One MADGTA agent (seed 000, Algorithm 1): the core the simulator and the network both drive.

:class:`TraversalAgent` is everything one agent does and knows, with no clock and no
transport: its belief (:class:`~swarmex.missions.traversal.belief.TraversalBelief`), its
LOOK (adjacency sensing, through the sensor it is given), its COMPUTE (the policy, which
sees only the belief), its MOVE bookkeeping (the thesis's PATH and the timed log), the
arrival rule, what it broadcasts and how a received broadcast changes its belief. The
discrete-event simulator (:mod:`swarmex.missions.traversal.sim`) and the networked agent
(:mod:`swarmex.net.traversal`) each keep only their clock and their transport, so a change
to the agent lands in both.

Driving it (the runtime owns the clock and the radio):

* three events, each run at its mission time ``t``: :meth:`TraversalAgent.start` (the
  agent is at its nest), :meth:`~TraversalAgent.arrive` (it reached the node it announced),
  :meth:`~TraversalAgent.end_job` (its job's time is up; the runtime says whether the job
  failed). Each hands its broadcasts, in order, to the ``send`` callable the agent was built
  with, *as it makes them* (a lossy channel draws from the run's generator, so the order of
  those draws and the policy's must stay what it is), and returns the agent's next event:
  a :class:`Next` of kind ``"arrive"``, ``"job_end"`` or ``"finish"``;
* :meth:`~TraversalAgent.receive` applies a rival's :class:`Message`;
  :meth:`~TraversalAgent.forget` drops a rival that left the mission.

Messages (§4.2): ``start`` (C04, at the nest) and ``pass`` (C07 without the job bit) give
the sender's position and release its reservation; ``job`` (C07 with the job bit) marks the
node conditionally accomplished; ``next`` (C05) reserves a vacant node for the sender;
``done`` / ``undone`` (C08 with / without the job bit) end a job, a failed one returning the
node to not-done. Every message may carry the obstacles the sender has just seen and, when
the agent is built with ``done_lists=True``, the sender's §4.1 done-nodes list
(:func:`encode_km`), which a receiver merges (:func:`merge_done_list`) before the message's
own update. Beyond §4.2: ``leave`` (:data:`LEAVE`, madgta-h and madgta-s) and ``plan``
(:data:`PLAN`, madgta-s), which a decision carrying a team plan sends after its own
message. The belief-level functions (:func:`apply_message`, :func:`merge_done_list`,
:func:`forget_rival`) are what the methods call; they take a bare belief so that a late
joiner can replay a stream into one.

Under a perfect broadcast the simulator applies a message to the whole team at once with
the compiled :func:`~swarmex.missions.traversal.belief.deliver`, the batched form of
:func:`apply_message` for the kinds it carries (no done list then);
``tests/missions/traversal/test_agent_core.py`` checks the two agree.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.belief import DONE_BY_UNKNOWN, TeamPlan, TraversalBelief
from swarmex.missions.traversal.policies import Madgta
from swarmex.worlds.nodegraph import NodeGraph

#: message kinds (see the module docstring); any other kind only carries obstacles and a list
START, PASS, JOB, NEXT, DONE, UNDONE = "start", "pass", "job", "next", "done", "undone"
KINDS = (START, PASS, JOB, NEXT, DONE, UNDONE)
#: ``leave``: an agent whose policy may stop while vacant vertices remain (its
#: ``announce_leave``: madgta-h, madgta-s) says so when it finishes, once; receivers drop it
#: as a rival (:func:`forget_rival`), so that nobody leaves a vertex to an agent that has
#: gone. Not one of the §4.2 kinds of :data:`KINDS` (the thesis's agents never stop early):
#: on the networked runtime's wire it is the job bit of the agent's C09
#: (:mod:`swarmex.net.traversal`).
LEAVE = "leave"
#: ``plan``: madgta-s's end-game team plan (:class:`~.belief.TeamPlan`), sent after the
#: decision it was made for; receivers keep the newest (:meth:`TraversalBelief.hear_plan`)
#: and start their own plan from it. Not a §4.2 kind either: on the networked runtime's wire
#: it rides in the frame of the decision it follows (:mod:`swarmex.net.wire`).
PLAN = "plan"

#: §4.1's done-nodes field: ``(bit, vertices, doers)``, optionally with a fourth array, the
#: sender's known obstacles (:func:`encode_km`)
DoneList = tuple[int, np.ndarray, np.ndarray] | tuple[int, np.ndarray, np.ndarray, np.ndarray]


@dataclass(frozen=True, slots=True)
class Message:
    """One broadcast of an agent, transport-free (the runtimes map it to their own form)."""

    kind: str
    sender: int
    node: int
    obstacles: tuple[int, ...] = ()
    eta: float = 0.0  # job: when the job ends; next: when the sender arrives
    t: float = 0.0  # mission time of the event
    done_list: DoneList | None = None
    plan: TeamPlan | None = None  # kind ``plan`` only


class Next(NamedTuple):
    """The agent's next event: ``"arrive"`` at ``node`` at ``time``, ``"job_end"`` of the job
    at ``node`` at ``time``, or ``"finish"`` (no vacant node left; ``time`` is now)."""

    kind: str
    node: int
    time: float


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


class AdjacencySensor:
    """The simulated sensor of seed 000 §1.3: the obstacles among a vertex's neighbours.

    It reads the true map, which is what a runtime gives it; the agent only ever sees what
    it reports for the vertex it stands on.
    """

    __slots__ = ("graph", "blocked")

    def __init__(self, graph: NodeGraph, blocked: np.ndarray) -> None:
        self.graph = graph
        self.blocked = blocked

    def __call__(self, node: int) -> np.ndarray:
        nbrs = self.graph.neighbors(node)
        return nbrs[self.blocked[nbrs]]


# ---------------------------------------------------------------------------- done lists


def encode_done_list(status: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
    """§4.1's done-nodes field: (bit, vertex list, doer ids).

    Bit 1: the list holds the done vertices (fewer than half are done). Bit 0: it holds the
    not-done vertices instead, which is shorter once half the graph is done.
    """
    done = status > 0
    if done.sum() * 2 < status.size:
        idx = np.nonzero(done)[0]
        return 1, idx, status[idx]
    return 0, np.nonzero(status == 0)[0], np.zeros(0, dtype=np.int32)


def encode_km(status: np.ndarray) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """What an agent's message carries: the thesis's KM, done ∪ known obstacles.

    §4.1 defines the list as KM, and KM includes the obstacles; the done / not-done list of
    :func:`encode_done_list` cannot tell a receiver which of its vertices are walls, so the
    sender's known obstacles ride along as a fourth field (4 bytes each). Without them an
    agent that missed the one message announcing a wall plans paths through it for the rest
    of the mission: under 30 % loss that cost up to 4x the travel on room maps
    (docs/traversal-variants.md).
    """
    bit, idx, doers = encode_done_list(status)
    return bit, idx, doers, np.nonzero(status == -1)[0]


def merge_done_list(b: TraversalBelief, done_list: DoneList) -> None:
    """Merge a received done-nodes field (with or without its KM obstacles) into ``b``.

    Obstacles first, so that the not-done form (everything not listed is done) does not mark
    a known wall as a done vertex. Only vertices ``b`` holds as not done change, and never
    one ``b`` reverted because the rival doing it left (:func:`forget_rival`): a list sent
    before its sender heard of the departure would otherwise mark it done again.
    """
    bit, idx, doers, *obstacles = done_list
    if obstacles:
        walls = obstacles[0]
        new = walls[b.status[walls] != -1]
        if new.size:
            b.see_obstacles(new.tolist())
    if bit:
        fresh = b.status[idx] == 0
        if b.orphaned:
            fresh &= ~np.isin(idx, list(b.orphaned))
        for v, k in zip(idx[fresh], doers[fresh], strict=True):
            b.mark_done(int(v), int(k))
    else:
        mask = np.ones(b.status.size, dtype=bool)
        mask[idx] = False
        if b.orphaned:
            mask[list(b.orphaned)] = False
        fresh = np.nonzero(mask & (b.status == 0))[0]
        for v in fresh:
            b.mark_done(int(v), int(DONE_BY_UNKNOWN))


# ---------------------------------------------------------------------------- receiving


def apply_message(b: TraversalBelief, msg: Message) -> None:
    """A rival's message applied to belief ``b``: its obstacles, its done list, then the
    kind's own update (position, conditionally accomplished node, reservation, failure)."""
    s, node, kind = msg.sender, msg.node, msg.kind
    if msg.obstacles:
        b.see_obstacles(msg.obstacles)
    if msg.done_list is not None:
        merge_done_list(b, msg.done_list)
    if kind in (START, PASS):
        b.loc[s] = node
        b.release(s)
    elif kind == JOB:  # C07
        b.loc[s] = node
        b.mark_done(node, s)
        b.orphaned.discard(node)
        b.next_loc[s] = node
        b.free_at[s] = msg.eta
    elif kind == NEXT:  # C05
        b.reserve(node, s)
        b.next_loc[s] = node
        b.free_at[s] = msg.eta
    elif kind == UNDONE:
        b.mark_not_done(node)
    elif kind == LEAVE:
        forget_rival(b, s, -1)
    elif kind == PLAN and msg.plan is not None:
        b.hear_plan(msg.plan)


def forget_rival(b: TraversalBelief, agent: int, open_node: int) -> None:
    """A departed rival: its unfinished job returns to not-done, it holds nothing, and it is
    no longer a rival (seed 000 §4.2: "conditionally accomplished" reverts on failure)."""
    if open_node >= 0 and b.status[open_node] == agent:
        b.mark_not_done(open_node)
        b.orphaned.add(int(open_node))
    b.release(agent)
    if 0 <= agent < b.loc.size:
        b.loc[agent] = -1
        b.next_loc[agent] = -1


def edge_length(graph: NodeGraph, u: int, v: int) -> float:
    """NodeGraph.edge_length (first matching edge) without its numpy set-up cost."""
    lo = int(graph.indptr[u])
    for k, x in enumerate(graph.indices[lo : graph.indptr[u + 1]].tolist()):
        if x == v:
            return float(graph.weights[lo + k])
    return graph.edge_length(u, v)  # raises KeyError naming the pair


# ---------------------------------------------------------------------------- the agent


class TraversalAgent:
    """One agent of Algorithm 1 (LOOK–COMPUTE–MOVE), driven by a runtime's clock.

    ``me`` is the 1-based id; ``sensor(node)`` reports the obstacles adjacent to ``node``;
    ``send(message)`` broadcasts; ``rng`` is where the policy's tie-breaks come from (the
    simulator gives every agent the run's one generator); ``done_lists`` makes every message
    carry the §4.1 done-nodes list (:func:`encode_km`).
    """

    def __init__(
        self,
        me: int,
        spec: AgentSpec,
        belief: TraversalBelief,
        policy: Madgta,
        rng: np.random.Generator,
        sensor: Callable[[int], Iterable[int]],
        send: Callable[[Message], None],
        done_lists: bool = False,
    ) -> None:
        self.me = me
        self.spec = spec
        self.belief = belief
        self.policy = policy
        self.rng = rng
        self.sensor = sensor
        self.send = send
        self.done_lists = done_lists
        self.log = AgentLog(me, spec)

    @property
    def graph(self) -> NodeGraph:
        return self.belief.graph

    # ---- receiving
    def receive(self, msg: Message) -> None:
        """Apply a rival's message (this agent's own ones change nothing)."""
        if msg.sender != self.me:
            apply_message(self.belief, msg)

    def forget(self, agent: int, open_node: int) -> None:
        """Drop a rival the mission lost (``open_node``: its unfinished job, or -1)."""
        if agent != self.me:
            forget_rival(self.belief, agent, open_node)

    def encode_done_list(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        """This agent's outgoing done-nodes list: its KM (done vertices and known walls)."""
        return encode_km(self.belief.status)

    def _say(self, kind: str, node: int, t: float, obstacles: Iterable[int] = (),
             eta: float = 0.0) -> None:
        done_list = self.encode_done_list() if self.done_lists else None
        self.send(Message(kind, self.me, int(node), tuple(obstacles), eta, t, done_list))

    def _say_plan(self, plan: TeamPlan | None, t: float) -> None:
        """Keep and broadcast the team plan a decision was made with (madgta-s), after the
        decision's own message."""
        if plan is not None:
            self.belief.hear_plan(plan)
            self.send(Message(PLAN, self.me, self.belief.here, t=t, plan=plan))

    # ---- LOOK
    def sense(self, node: int) -> list[int]:
        """The newly seen obstacles around ``node``, added to the belief."""
        status = self.belief.status
        new = [int(v) for v in self.sensor(node) if status[v] != -1]
        self.belief.see_obstacles(new)
        return new

    # ---- events
    def start(self, t: float) -> Next:
        """At the nest (after takeoff): look, announce the position, decide."""
        nest = self.spec.nest
        self.log.trajectory.append((t, nest))
        self.belief.loc[self.me] = nest
        seen = self.sense(nest)
        self._say(START, nest, t, seen)
        return self.decide(t)

    def arrive(self, node: int, t: float) -> Next:
        """At the announced node. Whoever first reaches a vertex does its job; an agent that
        announced the vertex itself does it unless it knows it is done
        (:meth:`TraversalBelief.job_on_arrival`); otherwise it only passes through."""
        log = self.log
        log.trajectory.append((t, node))
        b = self.belief
        b.loc[self.me] = node
        b.now = t
        seen = self.sense(node)
        do_job = b.job_on_arrival(node)
        b.intent = -1
        if do_job:
            return self._start_job(node, t, seen)
        log.path.append((node, False))
        b.release(self.me)
        self._say(PASS, node, t, seen)
        return self.decide(t)

    def end_job(self, node: int, t: float, failed: bool = False) -> Next:
        """The job at ``node`` is over; a failed one leaves the node not done (the agent,
        still there, sees it vacant and may retry)."""
        log = self.log
        log.job_time += self.spec.job_time
        if failed:
            log.failed_jobs += 1
            self.belief.mark_not_done(node)
            self._say(UNDONE, node, t)
        else:
            log.path[-1] = (node, True)
            if log.moves == 0:
                log.nest_job = True
            self._say(DONE, node, t)
        return self.decide(t)

    def decide(self, t: float) -> Next:
        """COMPUTE (the policy on the belief) and the start of MOVE."""
        b = self.belief
        b.now = t
        d = self.policy.decide(b, self.rng)
        log = self.log
        log.decisions_by_branch[d.branch] += 1
        if d.kind == "job":
            nxt = self._start_job(d.node, t)
            self._say_plan(d.plan, t)
            return nxt
        if d.kind == "move":
            here = b.here
            dt = edge_length(b.graph, here, d.node) * b.time_per_unit[self.me]
            b.announce_move(d.node)
            b.known.prefetch(d.node, here)  # its field, shifted in the background (if on)
            self._say(NEXT, d.node, t, eta=t + dt)
            self._say_plan(d.plan, t)
            log.moves += 1
            log.travel_time += dt
            return Next("arrive", d.node, t + dt)
        log.finished_at = t
        if getattr(self.policy, "announce_leave", False):
            self._say(LEAVE, log.node, t)
        return Next("finish", log.node, t)

    def _start_job(self, node: int, t: float, seen: Iterable[int] = ()) -> Next:
        log = self.log
        if not log.path or log.path[-1][0] != node:
            log.path.append((node, False))
        self.belief.mark_done(node, self.me)
        self.belief.orphaned.discard(node)
        log.jobs.append((t, node))
        end = t + self.spec.job_time
        self._say(JOB, node, t, seen, eta=end)
        return Next("job_end", node, end)


__all__ = [
    "KINDS",
    "LEAVE",
    "PLAN",
    "AdjacencySensor",
    "AgentLog",
    "DoneList",
    "Message",
    "Next",
    "TraversalAgent",
    "apply_message",
    "edge_length",
    "encode_done_list",
    "encode_km",
    "forget_rival",
    "merge_done_list",
]
