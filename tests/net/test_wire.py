"""The wire codec: frames round-trip, checksums catch damage, decoders name what is wrong."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.net import wire
from swarmex.net.wire import Broadcast


def _broadcast(**kw) -> Broadcast:
    rng = np.random.default_rng(3)
    rng.integers(5)
    base = dict(cmd="C07", id=2, node=17, job=1, done_bit=1, nodes=np.array([1, 5, 17]),
                doers=np.array([1, 2, 2]), obstacles=(3, 4), t=12.5, eta=22.5,
                rng=wire.rng_state(rng))
    base.update(kw)
    return Broadcast(**base)


def test_broadcast_round_trip_keeps_every_field_of_fig_4_17():
    b = _broadcast()
    back = wire.decode_broadcast(b.frame())
    assert (back.cmd, back.id, back.node, back.job, back.done_bit) == ("C07", 2, 17, 1, 1)
    assert back.nodes.tolist() == [1, 5, 17] and back.doers.tolist() == [1, 2, 2]
    assert back.obstacles == (3, 4) and (back.t, back.eta) == (12.5, 22.5)
    assert back.rng == b.rng


def test_a_team_plan_rides_as_a_thirteenth_field():
    """madgta-s's plan: [t, route lengths, vertices], with or without a done-nodes list."""
    plan = (4.5, np.array([0, 2, 0, 1]), np.array([9, 8, 30]))
    for walls in (np.array([3, 4]), None):
        b = _broadcast(walls=walls, plan=plan)
        msg = wire.unpack(b.frame())
        assert len(msg) == 13 and (msg[11] is None) == (walls is None)
        back = wire.decode_broadcast(b.frame())
        assert back.plan[0] == 4.5
        assert back.plan[1].tolist() == [0, 2, 0, 1] and back.plan[2].tolist() == [9, 8, 30]
        assert (back.walls is None) == (walls is None)
    assert len(wire.unpack(_broadcast().frame())) == 11  # no plan, no list: Fig. 4.17's 11


@pytest.mark.parametrize(("field", "says"), [
    ([1.0, wire.pack_nodes([0, 2]), wire.pack_nodes([5])], "do not add up"),
    ([1.0, wire.pack_nodes([0, 1])], "expected [t, route lengths, vertices]"),
    ("plan", "expected [t, route lengths, vertices]"),
    ([float("nan"), wire.pack_nodes([0, 1]), wire.pack_nodes([5])], "plan t"),
    ([1.0, b"abc", wire.pack_nodes([5])], "uint32"),
])
def test_a_malformed_plan_is_an_encoding_error(field, says):
    """Each wrong shape of the 13th field is named; so is a nil ``walls`` without a plan."""
    nil_walls = _broadcast().to_wire() + [None]
    with pytest.raises(wire.EncodingError, match="walls"):
        wire.decode_broadcast(wire.pack(nil_walls))
    msg = _broadcast(walls=np.array([3])).to_wire() + [field]
    with pytest.raises(wire.EncodingError, match=says.replace("[", r"\[").replace("]", r"\]")):
        wire.decode_broadcast(wire.pack(msg))


def test_not_done_list_needs_no_doers():
    b = _broadcast(done_bit=0, nodes=np.array([7, 8]), doers=None, rng=None)
    back = wire.decode_broadcast(b.frame())
    assert back.done_bit == 0 and back.nodes.tolist() == [7, 8] and back.doers.size == 0


def test_frame_is_msgpack_plus_big_endian_crc32():
    import zlib

    import msgpack

    frame = wire.pack(["HB", 3])
    payload = msgpack.packb(["HB", 3], use_bin_type=True)
    assert frame == payload + zlib.crc32(payload).to_bytes(4, "big")


def test_every_single_bit_flip_is_caught():
    frame = _broadcast().frame()
    for i in range(len(frame)):
        for bit in range(8):
            bad = bytearray(frame)
            bad[i] ^= 1 << bit
            with pytest.raises(wire.ChecksumError):
                wire.unpack(bytes(bad))


@pytest.mark.parametrize("cut", [0, 1, 4, 5, 20])
def test_truncated_frames_are_rejected(cut):
    frame = _broadcast().frame()
    with pytest.raises(wire.WireError):
        wire.decode_broadcast(frame[:cut])


def test_valid_checksum_but_wrong_shape_is_an_encoding_error():
    for obj in (42, [], ["NOPE"], ["C07", 1], ["C07", 0, 1, 0, 1, b"", b"", b"", 0.0, 0.0, None],
                ["C07", 1, 1, 2, 1, b"", b"", b"", 0.0, 0.0, None],
                ["C07", 1, 1, 0, 1, b"abc", b"", b"", 0.0, 0.0, None],
                ["C07", 1, 1, 0, 1, b"", b"", b"", float("nan"), 0.0, None],
                ["C07", 1, 1, 0, 1, b"", b"", b"", 0.0, 0.0, b"short"]):
        with pytest.raises(wire.EncodingError):
            wire.decode_broadcast(wire.pack(obj))


def test_control_messages_are_checked():
    assert wire.decode_message(wire.pack(["C00", 0])) == ["C00", 0]
    assert wire.decode_message(wire.pack(["JOIN", 3, 12.0, 40]))[0] == "JOIN"
    for bad in (["C00"], ["C00", "x"], ["C22", -1], ["MIS", {}, [1]], ["LEFT", 0, 1.0],
                ["ST", 1, []], ["ACK", 5, 1]):
        with pytest.raises(wire.EncodingError):
            wire.decode_message(wire.pack(bad))


def test_rng_state_travels_exactly():
    a = np.random.default_rng(11)
    a.integers(0, 7, size=5)
    a.random()  # leaves has_uint32 / uinteger in use
    b = np.random.default_rng(0)
    wire.set_rng_state(b, wire.check_rng(wire.rng_state(a)))
    assert a.integers(0, 1000, size=20).tolist() == b.integers(0, 1000, size=20).tolist()
    assert a.random() == b.random()


def test_corrupt_makes_frames_the_receiver_rejects():
    rng = np.random.default_rng(0)
    frame = _broadcast().frame()
    for _ in range(200):
        with pytest.raises(wire.WireError):
            wire.decode_broadcast(wire.corrupt(frame, rng))


def test_c01_may_describe_the_vehicle_and_ret_hands_an_id_back():
    ok = ["C01", 3, 7, {"kind": "mavlink", "link": "udp:127.0.0.1:14550", "sysid": 1}]
    assert wire.decode_message(wire.pack(ok)) == ok
    assert wire.decode_message(wire.pack(["C01", 3, 7]))[0] == "C01"  # without: simulated
    assert wire.decode_message(wire.pack(["RET", 3, "low battery"])) == ["RET", 3, "low battery"]
    for bad in (["C01", 3, 7, {"link": "x"}], ["C01", 3, 7, {"kind": 1}],
                ["C01", 3, 7, {"kind": "x", "nested": [1]}], ["C01", 3, 7, "mavlink"],
                ["C01", 3, 7, {"kind": "x" * 201}], ["RET", 0, "x"], ["RET", 3],
                ["RET", 3, 5]):
        with pytest.raises(wire.EncodingError):
            wire.decode_message(wire.pack(bad))
