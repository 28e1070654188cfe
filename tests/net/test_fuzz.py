"""Fuzzing every decoder: random bytes, truncated and damaged frames, and well-checksummed
nonsense must raise :class:`~swarmex.net.wire.WireError` (or decode), never anything else."""

from __future__ import annotations

import contextlib
from collections.abc import Callable

import msgpack
import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from swarmex.net import wire
from swarmex.net.traversal import Mission

DECODERS = [wire.unpack, wire.decode_broadcast, wire.decode_message]

_valid = [
    wire.Broadcast("C05", 1, 3, 0, 1, np.array([0, 3]), np.array([1, 1]), (2,), 1.0, 3.22,
                   wire.rng_state(np.random.default_rng(1))).frame(),
    wire.Broadcast("C05", 1, 3, t=1.0, eta=3.22,  # a madgta-s decision with its team plan
                   plan=(0.5, np.array([0, 2, 1]), np.array([4, 5, 9]))).frame(),
    wire.pack(["C00", 0]),
    wire.pack(["JOIN", 2, 30.5, 17]),
    wire.pack(["MIS", {"world": {}}, [b"x"]]),
]

scalars = (st.none() | st.booleans() | st.integers(-(2**64), 2**64 - 1) | st.floats()
           | st.text(max_size=8) | st.binary(max_size=40))
msgpack_values = scalars | st.lists(scalars, max_size=4) | st.dictionaries(
    st.text(max_size=6), scalars, max_size=4)


def _truncated_and_flipped(
    frame: bytes, cut: int, bit: int, check: Callable[[bytes], None]
) -> None:
    """``check`` ``frame`` cut to its first ``cut`` bytes (modulo its length + 1), then
    ``frame`` whole with bit ``bit`` of byte ``cut`` (modulo its length) flipped."""
    check(frame[: cut % (len(frame) + 1)])
    damaged = bytearray(frame)
    damaged[cut % len(frame)] ^= 1 << bit
    check(bytes(damaged))


def _only_wire_errors(frame: bytes) -> None:
    for decode in DECODERS:
        with contextlib.suppress(wire.WireError):
            decode(frame)
    try:
        obj = wire.unpack(frame)
        if isinstance(obj, list) and obj and obj[0] == "MIS" and len(obj) == 3:
            Mission.from_wire(obj[1])
    except wire.WireError:
        pass


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=300))
def test_random_bytes(data):
    _only_wire_errors(data)
    _only_wire_errors(data + wire.pack(0)[-4:])


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(_valid), st.integers(0, 400), st.integers(0, 7))
def test_truncated_and_flipped_frames(frame, cut, bit):
    _truncated_and_flipped(frame, cut, bit, _only_wire_errors)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(msgpack_values)
def test_checksummed_nonsense(value):
    try:
        frame = wire.pack(value)
    except (OverflowError, ValueError, TypeError):
        return
    _only_wire_errors(frame)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(wire.BROADCAST_COMMANDS + wire.CONTROL_COMMANDS),
       st.lists(msgpack_values, max_size=12))
def test_known_commands_with_random_fields(cmd, fields):
    try:
        frame = wire.pack([cmd, *fields])
    except (OverflowError, ValueError, TypeError):
        return
    _only_wire_errors(frame)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(st.sampled_from(["world", "agents", "algorithm", "seed", "rng_mode",
                                        "time_scale", "start_interval", "heartbeat"]),
                       msgpack_values, max_size=8))
def test_mission_data_decoder(d):
    try:
        raw = msgpack.unpackb(msgpack.packb(d, use_bin_type=True), raw=False,
                              strict_map_key=False)
    except (OverflowError, ValueError, TypeError):
        return
    with contextlib.suppress(wire.WireError):
        Mission.from_wire(raw)


# ---------------------------------------------------------------- the receivers themselves

def _mission() -> Mission:
    from swarmex.missions.traversal import uniform_agents
    from swarmex.worlds import GridWorld

    return Mission(GridWorld(np.ones((3, 4), dtype=bool)), uniform_agents([0, 0], 1.0, 1.0))


broadcast_like = st.builds(
    lambda cmd, i, node, job, bit, nodes, doers, obs, t, eta: [
        cmd, i, node, job, bit, wire.pack_nodes(nodes), wire.pack_nodes(doers),
        wire.pack_nodes(obs), t, eta, None],
    st.sampled_from(wire.BROADCAST_COMMANDS), st.integers(-2, 5), st.integers(-3, 20),
    st.integers(0, 1), st.integers(0, 1), st.lists(st.integers(0, 30), max_size=5),
    st.lists(st.integers(0, 30), max_size=5), st.lists(st.integers(0, 30), max_size=3),
    st.floats(-10, 1e6), st.floats(-10, 1e6),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(broadcast_like | st.binary(max_size=60) | msgpack_values, max_size=6))
def test_server_and_agent_survive_any_frames(items):
    """Frames straight into the server's and an agent's receive paths: dropped and counted,
    never an exception, never relayed."""
    import zmq

    from swarmex.net.agent import AgentClient
    from swarmex.net.server import TraversalServer

    server = TraversalServer(_mission(), "tcp://127.0.0.1:*", say=lambda _s: None)
    client = AgentClient(zmq.Context.instance(), "tcp://127.0.0.1:9", say=lambda _s: None)
    client.mission = _mission()
    from swarmex.net.traversal import AgentCore, Replica

    client.core, client.replica, client.id = AgentCore(client.mission, 1), Replica(
        client.mission), 1
    try:
        for item in items:
            try:
                frame = item if isinstance(item, bytes) else wire.pack(item)
            except (OverflowError, ValueError, TypeError):
                continue
            server._on_frame(b"peer", frame, 0.0)
            server._on_frame(b"peer", frame[: len(frame) // 2], 0.0)
            client.on_frame(frame, 0.0)
        assert server.counters.relayed == 0
    finally:
        server.sock.close(0)
        client.sock.close(0)


def test_server_events_need_a_place():
    """A C04 or C07 at node -1 passes the wire checks but has no place: no move or job event
    for it (a null x, y breaks the monitor's schema and ``swarmex watch``), only messages."""
    from swarmex.net.server import TraversalServer

    server = TraversalServer(_mission(), "tcp://127.0.0.1:*", say=lambda _s: None)
    try:
        server._events_for(wire.Broadcast("C04", 1, -1), True)
        server._events_for(wire.Broadcast("C07", 1, -1, job=1), True)
        server._events_for(wire.Broadcast("C04", 1, 5), True)
        events = server.pending_events
        assert [e["type"] for e in events] == ["message", "message", "move", "message"]
        assert (events[2]["x"], events[2]["y"]) == (1.0, 1.0)
    finally:
        server.sock.close(0)


# ---------------------------------------------------------------- the exploration mesh


def _radio_frames() -> list[bytes]:
    from swarmex.comm.aodv import Rerr, Routed, Rreq
    from swarmex.missions.exploration.messages import (
        ChangeGoal,
        Goal,
        Heartbeat,
        NeedMap,
        ScanMsg,
        ScanRecord,
    )
    from swarmex.net.mesh_frames import encode_radio
    from swarmex.sensing.occupancy import rasterise

    ranges = np.full(16, 3.0)
    angles = np.linspace(0.1, 6.2, 16)
    rec = ScanRecord(0, 4, 5, 5, rasterise(5, 5, ranges, angles, 4.0, (12, 12)))
    return [
        encode_radio(0, (5, 5), ScanMsg(0, (rec,))),
        encode_radio(1, (2, 3), Heartbeat(1, 2, 3)),
        encode_radio(1, (2, 3), NeedMap(1, ((0, 0, 4),))),
        encode_radio(2, (1, 1), Goal(2, (4, 4), 6.0, 1, 1)),
        encode_radio(2, (1, 1), ChangeGoal(2, (4, 4), 6.0)),
        encode_radio(1, (2, 3), Rreq(1, 0, 3, 7, 4, -1, 1)),
        encode_radio(2, (1, 1), Rerr(2, ((4, 6),))),
        encode_radio(1, (2, 3), Routed(1, 0, 4, 130, NeedMap(0, ((0, 0, 9),)), 2), link=3),
    ]


RADIO = _radio_frames()


def _mesh_decoders(frame: bytes) -> None:
    from swarmex.net.mesh_frames import (
        decode_control,
        decode_radio,
        report_fields,
        status_fields,
    )

    def control(f: bytes) -> None:  # what the display reads of a STATUS or REPORT too
        obj = decode_control(f)
        if obj[0] == "STATUS":
            status_fields(obj[2], (12, 12))
        elif obj[0] == "REPORT":
            report_fields(obj[2], (12, 12))

    for decode in (lambda f: decode_radio(f, (12, 12)), control):
        with contextlib.suppress(wire.WireError):
            decode(frame)


def test_mesh_frames_decode():
    from swarmex.net.mesh_frames import decode_radio

    kinds = [decode_radio(f, (12, 12))[2].kind for f in RADIO]
    assert kinds == ["SCAN", "HEARTBEAT", "NEED_MAP", "GOAL", "CHANGE_GOAL", "RREQ", "RERR",
                     "NEED_MAP"]  # a routed envelope's kind is its payload's


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(RADIO), st.integers(0, 4000), st.integers(0, 7))
def test_mesh_truncated_and_flipped_frames(frame, cut, bit):
    _truncated_and_flipped(frame, cut, bit, _mesh_decoders)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["SCAN", "MAP", "HEARTBEAT", "NEED_MAP", "GOAL", "CHANGE_GOAL", "X",
                        "RREQ", "RREP", "RERR", "DATA"]),
       st.dictionaries(st.sampled_from(["src", "x", "y", "goal", "priority", "have", "scans",
                                        "box", "o", "s", "free", "occ", "orig", "dest",
                                        "oseq", "dseq", "id", "hops", "life", "dests", "exp",
                                        "payload"]),
                       msgpack_values | st.lists(st.dictionaries(
                           st.sampled_from(["o", "s", "x", "y", "box", "free", "occ"]),
                           msgpack_values, max_size=7), max_size=2), max_size=8),
       st.integers(-2, 20), st.integers(-2, 20))
def test_mesh_checksummed_nonsense(kind, body, x, y):
    try:
        frame = wire.pack(["R", 0, x, y, {"type": kind, **body}])
    except (OverflowError, ValueError, TypeError):
        return
    _mesh_decoders(frame)
    _mesh_decoders(wire.pack(["STATUS", x, body]))
    _mesh_decoders(wire.pack(["REPORT", x, body]))


@settings(max_examples=150, deadline=None)
@given(st.binary(max_size=200))
def test_mesh_random_bytes(data):
    _mesh_decoders(data)
    _mesh_decoders(data + wire.pack(0)[-4:])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["NEED_MAP", "MAP", "CHANGE_GOAL", "SCAN", "RREQ", "DATA"]),
       st.dictionaries(st.sampled_from(["src", "goal", "priority", "have", "scans", "orig",
                                        "payload"]), msgpack_values, max_size=5),
       st.integers(-3, 3), st.floats(allow_nan=True))
def test_mesh_routed_payload_nonsense(kind, body, src, exp):
    """A well-formed DATA envelope around a nonsense payload: a WireError or a message."""
    env = {"type": "DATA", "src": 1, "orig": 0, "dest": 2, "exp": exp, "hops": 2,
           "payload": {"type": kind, "src": src, **body}}
    try:
        frame = wire.pack(["R", 1, 3, 3, env])
    except (OverflowError, ValueError, TypeError):
        return
    _mesh_decoders(frame)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(st.sampled_from(["t", "finished", "stopped", "x", "y", "moves",
                                        "steps", "free", "trajectory", "traffic",
                                        "plan_ticks", "unicasts", "replan_reasons"]),
                       msgpack_values | st.lists(st.lists(scalars, max_size=4), max_size=3),
                       max_size=8))
def test_mesh_status_and_report_nonsense(body):
    """The display's checks of a robot's telemetry raise only WireError (an ``inf`` move
    time raised OverflowError in the display and lost the run's record)."""
    try:
        frames = [wire.pack([cmd, 0, body]) for cmd in ("STATUS", "REPORT")]
    except (OverflowError, ValueError, TypeError):
        return
    for frame in frames:
        _mesh_decoders(frame)
