"""One traversal agent core for both runtimes (issue 12, item 3).

The simulator (``sim._Sim``) and the networked agent (``net.traversal.AgentCore``) both run
:class:`TraversalAgent`; a message reaches a belief through the same rule whichever way it
travels; the simulator's batched perfect-broadcast kernel agrees with that rule; and a
done-nodes list cannot resurrect the unfinished job of an agent that left.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.comm.channel import Channel
from swarmex.errors import InputError
from swarmex.missions.traversal import TraversalAgent, run_traversal, uniform_agents
from swarmex.missions.traversal import agent as agent_module
from swarmex.missions.traversal import sim as sim_module
from swarmex.missions.traversal.agent import (
    JOB,
    KINDS,
    NEXT,
    Message,
    Next,
    apply_message,
    encode_done_list,
    forget_rival,
)
from swarmex.missions.traversal.belief import (
    DONE_BY_UNKNOWN,
    BeliefTable,
    TraversalBelief,
    deliver,
)
from swarmex.net import traversal as net_traversal
from swarmex.net.traversal import (
    AgentCore,
    Mission,
    broadcast_of,
    catch_up,
    check_broadcast,
    message_of,
    run_inprocess,
)
from swarmex.net.wire import Broadcast, EncodingError, decode_broadcast
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import GridWorld, random_obstacles

TRAVEL, JOB_TIME = 2.0, 9.0
BELIEF_ARRAYS = ("status", "reserved", "loc", "reservation", "next_loc", "free_at", "revived")


def _scenario(seed: int = 3, size: int = 8, k: int = 3) -> tuple[GridWorld, list[int]]:
    world = random_obstacles(size, size, 0.2, seed=seed)
    free = np.nonzero(~world.blocked)[0]
    nests = np.random.default_rng(seed).choice(free, k, replace=False)
    return world, [int(v) for v in nests]


def _same_belief(a: TraversalBelief, b: TraversalBelief) -> None:
    for name in BELIEF_ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.orphaned == b.orphaned
    assert np.array_equal(a.known.blocked, b.known.blocked)


# ------------------------------------------------------------------ one class, two runtimes
def test_both_runtimes_instantiate_the_one_agent_class(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every agent either runtime builds is a TraversalAgent, and every decision of either
    run goes through TraversalAgent.decide — with the same outcomes, event for event."""
    built: dict[str, list[TraversalAgent]] = {"sim": [], "net": []}
    steps: dict[str, list[tuple[int, float, Next]]] = {"sim": [], "net": []}
    where = ["sim"]
    init, decide = TraversalAgent.__init__, TraversalAgent.decide

    def spy_init(self: TraversalAgent, *args: object, **kw: object) -> None:
        init(self, *args, **kw)  # type: ignore[arg-type]
        built[where[0]].append(self)

    def spy_decide(self: TraversalAgent, t: float) -> Next:
        nxt = decide(self, t)
        steps[where[0]].append((self.me, t, nxt))
        return nxt

    monkeypatch.setattr(TraversalAgent, "__init__", spy_init)
    monkeypatch.setattr(TraversalAgent, "decide", spy_decide)
    world, nests = _scenario()
    specs = uniform_agents(nests, TRAVEL, JOB_TIME)
    run = run_traversal(world, specs, "madgta", seed=3, job_failure=0.1)
    where[0] = "net"
    cores, _ = run_inprocess(Mission(world, specs, "madgta", 3, job_failure=0.1))

    assert len(built["sim"]) == len(built["net"]) == len(specs)
    assert {type(a) for a in built["sim"] + built["net"]} == {TraversalAgent}
    assert [c.agent for _, c in sorted(cores.items())] == built["net"]
    assert steps["sim"] and steps["sim"] == steps["net"]
    assert [a.log.jobs for a in built["sim"]] == [log.jobs for log in run.agents] == [
        c.log.jobs for _, c in sorted(cores.items())
    ]


def test_neither_runtime_keeps_its_own_copy_of_the_agent_rules() -> None:
    assert sim_module._merge_done_list is agent_module.merge_done_list
    assert sim_module._encode_km is agent_module.encode_km
    assert sim_module._encode_done_list is agent_module.encode_done_list
    assert sim_module.AgentLog is agent_module.AgentLog is net_traversal.AgentLog
    for module in (sim_module, net_traversal):
        own = {n for n, v in vars(module).items() if callable(v)
               and getattr(v, "__module__", "") == module.__name__}
        assert not own & {"sense", "apply", "arrive_at", "start_job", "decide", "_encode_km"}


# ------------------------------------------------------------------ one receive rule
def _recorded_sim_messages(monkeypatch: pytest.MonkeyPatch) -> tuple[Mission, list[Message]]:
    """Every message of a simulated run whose channel reaches everybody but is not
    "perfect", so each message carries the sender's done-nodes list."""
    said: list[Message] = []
    original = sim_module._Sim.broadcast

    def spy(self: sim_module._Sim, msg: Message) -> None:
        said.append(msg)
        original(self, msg)

    monkeypatch.setattr(sim_module._Sim, "broadcast", spy)
    world, nests = _scenario(seed=5, size=9, k=3)
    specs = uniform_agents(nests, TRAVEL, JOB_TIME)
    run = run_traversal(world, specs, "madgta", seed=5, channel=Channel(range=1e9))
    assert run.complete
    assert {m.kind for m in said} == set(KINDS) - {"undone"}
    assert all(m.done_list is not None and len(m.done_list) == 4 for m in said)
    # one more agent, who never spoke, listens (a sender's own walls are its own sensing)
    listener = uniform_agents([nests[0]], TRAVEL, JOB_TIME)
    return Mission(world, specs + listener, "madgta", 5), said


@pytest.mark.parametrize("drop_every", [0, 3, 2])
def test_a_message_sequence_gives_the_same_belief_by_either_path(
    monkeypatch: pytest.MonkeyPatch, drop_every: int
) -> None:
    """The simulator's messages applied as the simulator applies them and, through the wire
    (Fig. 4.17 frames, decoded), as the networked agent applies them: the same belief.
    With messages dropped (as a lossy channel would) the done-nodes lists fill the gaps by
    both paths alike — the networked receiver merges them now."""
    mission, said = _recorded_sim_messages(monkeypatch)
    me = mission.n_agents
    # drop any message, obstacles and all: the wire's list carries the sender's known walls
    # (the thesis's KM) as the simulator's does, so both paths learn a lost wall alike
    kept = [m for i, m in enumerate(said) if not (drop_every and i % drop_every == 0)]
    sim_side = AgentCore(mission, me).agent  # a TraversalAgent, fed Message objects
    net_side = AgentCore(mission, me)  # fed decoded broadcasts
    for m in kept:
        sim_side.receive(m)
        net_side.receive(decode_broadcast(broadcast_of(m).frame()))
    _same_belief(sim_side.belief, net_side.belief)
    if drop_every:
        # the lists did the work: without them the networked path would know less
        bare = AgentCore(mission, me)
        for m in kept:
            bare.agent.receive(Message(m.kind, m.sender, m.node, m.obstacles, m.eta, m.t))
        assert (net_side.belief.status > 0).sum() > (bare.belief.status > 0).sum()


def test_wire_round_trip_of_every_kind() -> None:
    status = np.array([0, 2, -1, 0, 1, 0], dtype=np.int32)
    dl = agent_module.encode_km(status)
    for kind in KINDS:
        m = Message(kind, 2, 3, (2,), 7.5, 4.0, dl)
        back = message_of(decode_broadcast(broadcast_of(m).frame()))
        assert (back.kind, back.sender, back.node, back.obstacles, back.eta, back.t) == (
            kind, 2, 3, (2,), 7.5, 4.0)
        assert back.done_list is not None
        assert [np.asarray(x).tolist() for x in back.done_list] == [
            np.asarray(x).tolist() for x in dl]  # the known walls (KM) included


# ------------------------------------------------------------------ the batched form
def test_the_perfect_broadcast_kernel_is_the_receive_rule_batched() -> None:
    world = GridWorld(np.ones((5, 5), dtype=bool))
    m, n = 4, world.n_nodes
    tpu, jt = np.ones(m + 1), np.ones(m + 1)
    table = BeliefTable(m, n)
    shared = KnownGraph(world.graph, capacity=8)
    batched = [TraversalBelief(i, m, shared, tpu, jt, table=table) for i in range(1, m + 1)]
    one_by_one = [
        TraversalBelief(i, m, KnownGraph(world.graph, capacity=8), tpu, jt)
        for i in range(1, m + 1)
    ]
    codes = sim_module._KIND_CODES
    rng = np.random.default_rng(0)
    for step in range(400):
        kind = KINDS[rng.integers(len(KINDS))]
        sender, node = int(rng.integers(1, m + 1)), int(rng.integers(n))
        obstacles = (int(rng.integers(n)),) if rng.random() < 0.05 else ()
        msg = Message(kind, sender, node, obstacles, eta=float(step))
        shared.add_obstacles(obstacles)
        deliver(codes[kind], sender, node, np.asarray(obstacles, dtype=np.int64), msg.eta,
                table.status, table.reserved, table.loc, table.reservation, table.next_loc,
                table.free_at, table.revived)
        for b in one_by_one:
            if b.me != sender:
                apply_message(b, msg)
    for a, b in zip(batched, one_by_one, strict=True):
        for name in BELIEF_ARRAYS:
            assert np.array_equal(getattr(a, name), getattr(b, name)), (a.me, name)


# ------------------------------------------------------------------ departures
def _belief(m: int = 3, n_side: int = 4) -> TraversalBelief:
    world = GridWorld(np.ones((n_side, n_side), dtype=bool))
    return TraversalBelief(1, m, KnownGraph(world.graph, capacity=8), np.ones(m + 1),
                           np.ones(m + 1))


@pytest.mark.parametrize("few_done", [True, False], ids=["done-form", "not-done-form"])
def test_a_stale_list_does_not_resurrect_a_departed_agents_job(few_done: bool) -> None:
    b = _belief()
    v = 5
    apply_message(b, Message(JOB, 3, v, eta=9.0))  # agent 3 starts the job at v (C07)
    # what agent 2 knew before it heard that 3 left: v done by 3 (and, in the not-done
    # form, most of the grid done too)
    sender = np.zeros(16, dtype=np.int32)
    sender[v] = 3
    if not few_done:
        sender[:12] = 2
        sender[v] = 3
    stale = encode_done_list(sender)
    assert stale[0] == (1 if few_done else 0)
    forget_rival(b, 3, v)  # LEFT: v is not done any more
    assert b.status[v] == 0 and b.orphaned == {v} and b.loc[3] == -1
    apply_message(b, Message(NEXT, 2, 6, done_list=stale))
    assert b.status[v] == 0  # the stale list did not mark it done again
    if not few_done:
        assert (b.status[[0, 1, 2]] == DONE_BY_UNKNOWN).all()  # the rest of it did count
    apply_message(b, Message(JOB, 2, v, eta=20.0))  # somebody really starts it: C07
    assert b.status[v] == 2 and not b.orphaned


def test_a_spare_replaying_the_stream_keeps_the_guard() -> None:
    world = GridWorld(np.ones((4, 4), dtype=bool))
    mission = Mission(world, uniform_agents([0, 5, 15], 1.0, 1.0), seed=0)
    sender = np.zeros(16, dtype=np.int32)
    sender[5] = 3
    bit, nodes, doers = encode_done_list(sender)
    frames = [
        ["C07", 3, 5, 1, 1, b"", b"", b"", 1.0, 2.0, None],
        ["LEFT", 3, 1.5],
        Broadcast("C05", 2, 6, 0, bit, nodes, doers, (), 1.6, 2.6).to_wire(),
    ]
    spare = AgentCore(mission, 3)
    replica = net_traversal.Replica(mission)
    for msg in frames:
        catch_up(spare.belief, replica, msg)
    assert spare.belief.status[5] == 0 and spare.belief.orphaned == {5}


def test_a_listed_doer_must_be_an_agent() -> None:
    world = GridWorld(np.ones((4, 4), dtype=bool))
    mission = Mission(world, uniform_agents([0, 5], 1.0, 1.0), seed=0)
    nodes = np.array([1, 2])
    ok = Broadcast("C05", 1, 3, 0, 1, nodes, np.array([2, int(DONE_BY_UNKNOWN)]))
    check_broadcast(decode_broadcast(ok.frame()), mission)
    for bad in (3, 0, 2**32 - 1):
        b = Broadcast("C05", 1, 3, 0, 1, nodes, np.array([1, bad]))
        with pytest.raises(EncodingError):
            check_broadcast(decode_broadcast(b.frame()), mission)


def test_adjacency_sensor_reports_only_the_blocked_neighbours() -> None:
    free = np.ones((3, 3), dtype=bool)
    free[0, 1] = False
    world = GridWorld(free)
    sensor = agent_module.AdjacencySensor(world.graph, world.blocked)
    assert sorted(sensor(0).tolist()) == [1]
    assert sensor(8).size == 0


def test_bad_inputs_still_fail_cleanly() -> None:
    world, nests = _scenario()
    with pytest.raises(InputError):
        run_traversal(world, uniform_agents(nests, TRAVEL, JOB_TIME), job_failure=1.0)
