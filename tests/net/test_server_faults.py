"""The server's handling of faulty agents, driven frame by frame (no agent processes).

A :class:`Harness` feeds frames to :meth:`TraversalServer._on_frame` with a clock of its own
and records what the server sends each connection, so a test can stand for an agent that
dies, is restarted, or sends a well-formed frame the mission cannot contain.
"""

from __future__ import annotations

import signal
import threading
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from swarmex.missions.traversal import uniform_agents
from swarmex.net import wire
from swarmex.net.server import TraversalServer
from swarmex.net.traversal import Mission, check_broadcast
from swarmex.worlds import GridWorld

pytestmark = pytest.mark.timeout(60)


def _mission(agents: int = 2, heartbeat: float = 0.25) -> Mission:
    return Mission(GridWorld(np.ones((4, 4), dtype=bool)),
                   uniform_agents([0] * agents, 1.0, 1.0), heartbeat=heartbeat)


class Harness:
    def __init__(self, agents: int = 2, dead_after: float = 2.0, heartbeat: float = 0.25,
                 init_timeout: float = 60.0) -> None:
        self.said: list[str] = []
        self.server = TraversalServer(_mission(agents, heartbeat), "tcp://127.0.0.1:*",
                                      dead_after=dead_after, init_timeout=init_timeout,
                                      say=self.said.append)
        self.sent: list[tuple[bytes, list]] = []
        self.server._send = lambda peer, frame: self.sent.append(  # type: ignore[method-assign]
            (peer.ident, wire.decode_message(frame)))
        self.t0 = time.monotonic()

    def frame(self, ident: bytes, obj: list, at: float) -> None:
        self.server._on_frame(ident, wire.pack(obj), self.t0 + at)

    def broadcast(self, ident: bytes, b: wire.Broadcast, at: float) -> None:
        self.server._on_frame(ident, b.frame(), self.t0 + at)

    def to(self, ident: bytes) -> list[list]:
        return [m for i, m in self.sent if i == ident]

    def arm(self, ident: bytes, want: int, at: float) -> int:
        """C00 .. C03 for one connection, all at ``at``: the id it got."""
        self.frame(ident, ["C00", want], at)
        got = self.to(ident)[-1]
        assert got[0] == "ID", got
        a = int(got[1])
        self.frame(ident, ["C22", a], at)
        self.frame(ident, ["C01", a, 0], at)
        self.frame(ident, ["C02", a], at)
        self.frame(ident, ["C03", a], at)
        return a

    def close(self) -> None:
        self.server.sock.close(0)
        self.server.ctx.term()


@pytest.fixture
def harness():
    made: list[Harness] = []

    def make(**kw) -> Harness:
        made.append(Harness(**kw))
        return made[-1]

    yield make
    for h in made:
        h.close()


def _started(make) -> Harness:
    h = make()
    h.arm(b"a1", 0, 0.0)
    h.arm(b"a2", 0, 0.0)
    assert h.server.started
    return h


# ---------------------------------------------------------------- finding 2: bad moves


def test_a_move_to_a_node_not_next_to_the_agent_is_dropped_before_the_relay(harness):
    """A well-formed C05 to node 15 from the nest (node 0) crashed ``serve`` in the recorder
    (``KeyError: no edge between 0 and 15``, no record), after it had been relayed."""
    h = _started(harness)
    h.broadcast(b"a1", wire.Broadcast("C04", 1, 0, t=0.1, eta=0.1), 0.2)
    relayed = h.server.counters.relayed
    h.broadcast(b"a1", wire.Broadcast("C05", 1, 15, t=0.1, eta=5.0), 0.3)
    h.broadcast(b"a1", wire.Broadcast("C05", 1, 0, t=0.1, eta=5.0), 0.3)  # to where it is
    h.broadcast(b"a1", wire.Broadcast("C07", 1, 10, job=1, t=0.1, eta=5.0), 0.3)  # teleport
    h.broadcast(b"a1", wire.Broadcast("C04", 1, 5, t=0.1, eta=0.1), 0.3)  # not its nest
    assert h.server.counters.dropped_content == 4
    assert h.server.counters.relayed == relayed
    assert not any(m[0] == "C05" for m in h.to(b"a2"))
    # a legal move still goes through, and the record can be written
    h.broadcast(b"a1", wire.Broadcast("C05", 1, 1, t=0.1, eta=1.1), 0.4)
    assert h.server.counters.relayed == relayed + 1
    assert h.server.build_record()["agents"][0]["metrics"]["nodes_traveled"] == 1
    assert not any("could not apply" in s for s in h.said)


# ---------------------------------------------------------------- finding 3: node -1


@pytest.mark.parametrize("cmd", ["C04", "C05", "C07", "C08"])
def test_node_minus_one_is_refused_where_the_protocol_has_no_use_for_it(cmd):
    with pytest.raises(wire.EncodingError):
        check_broadcast(wire.Broadcast(cmd, 1, -1, job=1), _mission())
    check_broadcast(wire.Broadcast("C09", 1, -1), _mission())  # a finish may have no node


def test_a_job_at_node_minus_one_marks_no_vertex_done(harness):
    """A C07 job at -1 passed the checks, and numpy's negative index marked the last vertex
    (3,3) done in the record and in every agent's belief: the record said complete with a
    vertex nobody visited."""
    h = _started(harness)
    h.broadcast(b"a1", wire.Broadcast("C04", 1, 0, t=0.1, eta=0.1), 0.2)
    h.broadcast(b"a1", wire.Broadcast("C07", 1, -1, job=1, t=0.1, eta=5.0), 0.3)
    h.broadcast(b"a1", wire.Broadcast("C08", 1, 3, job=0, t=0.1, eta=5.0), 0.3)  # no job there
    rec = h.server.recorder
    assert rec.job_count.tolist() == [0] * 16 and rec.done_by.tolist() == [0] * 16
    assert h.server.counters.dropped_content == 2
    assert not any(m[0] in ("C07", "C08") for m in h.to(b"a2"))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.sampled_from(wire.BROADCAST_COMMANDS), st.integers(1, 2),
                          st.integers(-1, 16), st.integers(0, 1),
                          st.floats(0, 1e4), st.floats(0, 1e4)), max_size=12))
def test_well_formed_broadcasts_from_registered_agents_never_break_the_server(items):
    """The fuzz tests fed frames from a connection holding no id (all dropped as
    impersonation), so the path a registered agent's broadcast takes was never fuzzed."""
    h = Harness()
    try:
        h.arm(b"a1", 0, 0.0)
        h.arm(b"a2", 0, 0.0)
        for k, (cmd, a, node, job, t, eta) in enumerate(items):
            h.broadcast(b"a%d" % a, wire.Broadcast(cmd, a, node, job=job, t=t, eta=eta),
                        0.1 + k * 0.01)
        assert not any("could not apply" in s for s in h.said), h.said
        rec = h.server.recorder
        assert (rec.job_count >= 0).all()
        h.server.build_record()
    finally:
        h.close()


# ---------------------------------------------------------------- finding 5: told it is gone


def test_an_agent_declared_gone_is_told(harness):
    """LEFT went to every holder but the agent declared gone (forgotten first), so it flew
    on until its server timeout and status 5 ("declared gone") could never happen."""
    h = _started(harness)
    h.frame(b"a2", ["HB", 2], 3.0)
    h.server._check_liveness(h.t0 + 3.0)  # a1 silent for 3 s, --dead-after 2
    assert h.server.state[1] == "left"
    assert h.to(b"a1")[-1][:2] == ["LEFT", 1]
    assert h.to(b"a2")[-1][:2] == ["LEFT", 1]
    # it speaks again (it was paused): told again, its frames dropped
    n = len(h.to(b"a1"))
    h.broadcast(b"a1", wire.Broadcast("C04", 1, 0, t=0.1, eta=0.1), 3.5)
    assert h.to(b"a1")[n:][0][:2] == ["LEFT", 1]
    assert h.server.counters.relayed == 0
    # and again while it keeps talking, at most once a heartbeat (0.25 s here): the ghost
    # was told only once, its peer being known after the first frame
    h.frame(b"a1", ["HB", 1], 3.6)
    assert len(h.to(b"a1")) == n + 1
    h.frame(b"a1", ["HB", 1], 3.8)
    assert len(h.to(b"a1")) == n + 2 and h.to(b"a1")[-1][:2] == ["LEFT", 1]


# ---------------------------------------------------------------- finding 6: before GO


def test_an_armed_agent_that_died_is_not_ready_and_loses_its_id(harness):
    """An armed agent that died before GO kept its id for a hard-coded 60 s: it counted as
    ready for GO and refused its own restart with the same --id ("id 1 is taken")."""
    h = harness(dead_after=2.0)
    h.arm(b"a1", 1, 0.0)
    h.arm(b"a2", 2, 1.5)  # a1 has not beaten for 1.5 s: no GO for a silent id
    assert not h.server.started
    assert not any(m[0] == "GO" for _i, m in h.sent)
    # the restart with the same --id, once a1 has been silent past --dead-after
    h.frame(b"a1-again", ["C00", 1], 2.5)
    assert h.to(b"a1-again")[-1] == ["ID", 1]
    assert h.to(b"a1")[-1][:2] == ["LEFT", 1]
    h.frame(b"a2", ["HB", 2], 2.6)
    h.arm(b"a1-again", 1, 2.7)
    assert h.server.started


def test_a_fixed_id_still_taken_is_asked_for_again_until_the_connect_timeout():
    """A restart with the same --id used to exit 4 at the first "id 1 is taken", before the
    server could notice that the old holder had died."""
    import zmq

    from swarmex.net.agent import EXIT_REFUSED, AgentClient

    said: list[str] = []
    client = AgentClient(zmq.Context.instance(), "tcp://127.0.0.1:9", want_id=1,
                         connect_timeout=5.0, say=said.append)
    try:
        t = client.started_at
        client.on_frame(wire.pack(["REF", "id 1 is taken"]), t + 0.1)
        assert client.exit_code is None and client.retry_at == pytest.approx(t + 0.3)
        # it sleeps until the next ask: with no id (so no heartbeat) it polled with a zero
        # timeout, a whole core while it waited (a --spare for the whole mission; found by
        # the review of the fix)
        assert client.tick(t + 0.15) == pytest.approx(0.15)
        assert client.tick(t + 0.3) > 0.0  # asked again: the next ask is 0.2 s away
        assert any("id 1 is taken; asking again" in s for s in said), said
        client.tick(t + 5.5)
        assert client.exit_code == EXIT_REFUSED
        assert said[-1].endswith("refused: id 1 is taken"), said
    finally:
        client.sock.close(0)


def test_an_armed_agent_that_stalls_before_the_start_keeps_its_id(harness):
    """Declared gone after --dead-after before GO, an armed agent that merely stalled (a
    loaded machine) cost the whole run: nobody took its id, and the server waited out
    --timeout (found by the review of the fix). It keeps the init timeout; GO waits until it
    is heard again; past the init timeout its id is open to a spare."""
    h = harness(dead_after=2.0)
    h.arm(b"a1", 1, 0.0)
    h.frame(b"a2", ["C00", 2], 0.0)  # still being initialised
    h.server._check_liveness(h.t0 + 2.5)
    assert h.server.state[1] == "ready" and h.server.state[2] == "init"
    h.frame(b"a2", ["C22", 2], 2.5)
    h.frame(b"a2", ["C01", 2, 0], 2.5)
    h.frame(b"a2", ["C02", 2], 2.5)
    h.frame(b"a2", ["C03", 2], 2.5)
    assert not h.server.started  # a1 not heard lately: no GO yet
    h.server._maybe_go(h.t0 + 2.55)  # the loop's pass: still no GO
    assert not h.server.started
    h.frame(b"a1", ["HB", 1], 2.6)  # the stall ends
    h.frame(b"a2", ["HB", 2], 2.6)
    h.server._maybe_go(h.t0 + 2.6)
    assert h.server.started and not any(m[0] == "LEFT" for _i, m in h.sent)
    # past the init timeout an armed agent is gone, and a spare may take its id
    h2 = harness(dead_after=2.0)
    h2.arm(b"a1", 1, 0.0)
    h2.server._check_liveness(h2.t0 + h2.server.init_timeout + 0.5)
    assert h2.server.state[1] == "left"
    h2.frame(b"spare", ["C00", -1], h2.server.init_timeout + 0.6)
    assert h2.to(b"spare")[-1] == ["ID", 1]


def test_an_agent_compiling_past_the_init_timeout_is_told_what_to_raise(harness):
    """A first start on a slow or loaded machine compiles kernels longer than the default
    60 s (measured: 17 s of CPU for madgta-s alone on a cold cache; eight agent processes
    on two cores take four times that). The server keeps its id for ``init_timeout`` and
    then says which option gives it longer."""
    h = harness(dead_after=2.0, init_timeout=30.0)
    h.frame(b"a1", ["C00", 1], 0.0)
    h.frame(b"a1", ["C22", 1], 0.0)  # mission data sent: the agent now compiles, silent
    h.server._check_liveness(h.t0 + 29.0)
    assert h.server.state[1] == "init"
    h.server._check_liveness(h.t0 + 30.5)
    assert h.server.state[1] == "left"
    assert "--init-timeout (30 s)" in h.said[-1] and "raise --init-timeout" in h.said[-1]
    # never shorter than --dead-after, which an armed agent already gets
    h2 = harness(dead_after=5.0, init_timeout=1.0)
    h2.frame(b"a1", ["C00", 1], 0.0)
    h2.server._check_liveness(h2.t0 + 4.0)
    assert h2.server.state[1] == "init"


# ---------------------------------------------------------------- finding 4: waiting spares


def test_a_waiting_spare_keeps_the_mission_open_for_the_last_agents_id(harness):
    """With --spare-wait 0 the end came in the pass that declared the last agent gone: the
    spare waiting for an id heard END ("without needing a spare"), the mission incomplete."""
    h = harness(agents=1, dead_after=2.0)
    h.arm(b"a1", 1, 0.0)
    assert h.server.started
    h.frame(b"spare", ["C00", -1], 0.5)
    assert h.to(b"spare")[-1] == ["REF", "no vacant id"]
    h.frame(b"spare", ["C00", -1], 2.9)
    h.server._check_liveness(h.t0 + 3.0)
    assert h.server.state[1] == "left"
    assert h.server._end_code(h.t0 + 3.0) is None  # the spare asks again within 0.2 s
    h.frame(b"spare", ["C00", -1], 3.1)
    assert h.to(b"spare")[-1] == ["ID", 1]
    # a spare that stopped asking does not hold the end back
    h2 = harness(agents=1, dead_after=2.0)
    h2.arm(b"a1", 1, 0.0)
    h2.frame(b"spare", ["C00", -1], 0.5)
    h2.server._check_liveness(h2.t0 + 3.0)
    assert h2.server._end_code(h2.t0 + 3.0) == 1


# ---------------------------------------------------------------- finding 9: heartbeats


def test_ctrl_c_is_seen_promptly_with_a_long_heartbeat():
    """The loop polled for a whole heartbeat: with --heartbeat 8 a Ctrl-C waited 7.6 s."""
    said: list[str] = []
    server = TraversalServer(_mission(heartbeat=8.0), "tcp://127.0.0.1:*", dead_after=20.0,
                             say=said.append)
    result: list[int] = []
    thread = threading.Thread(target=lambda: result.append(server.run()), daemon=True)
    thread.start()
    end = time.monotonic() + 10
    while not any("listening" in s for s in said) and time.monotonic() < end:
        time.sleep(0.02)
    time.sleep(0.5)  # into the first long poll
    asked = time.monotonic()
    server.stop.request(signal.SIGINT)
    thread.join(10)
    assert result == [130], said
    assert time.monotonic() - asked < 2.0


def test_an_agent_waits_for_a_server_that_beats_slower_than_its_timeout():
    """serve --heartbeat 12: an agent with the default 10 s --server-timeout declared the live
    server gone between two beats."""
    import zmq

    from swarmex.net.agent import AgentClient

    client = AgentClient(zmq.Context.instance(), "tcp://127.0.0.1:9", server_timeout=10.0,
                         say=lambda _s: None)
    try:
        now = client.last_server
        assert client._server_silent(now + 11)  # no mission data yet: its own timeout
        client.mission = _mission(heartbeat=12.0)
        assert not client._server_silent(now + 11)
        assert not client._server_silent(now + 30)
        assert client._server_silent(now + 37)
    finally:
        client.sock.close(0)
