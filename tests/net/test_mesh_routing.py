"""AODV on the process mesh's wire: its frames round-trip and are checked, and a unicast
that the receiver drops as out of range comes back as a NACK that breaks the link.

The NACK test builds two robot processes' nodes in this process (their sockets on
127.0.0.1) and moves frames between them by hand, so every step is deterministic."""

from __future__ import annotations

import time

import numpy as np
import pytest

from swarmex.comm.aodv import Rerr, Routed, Rrep, Rreq
from swarmex.missions.exploration import ExplorationParams
from swarmex.missions.exploration.messages import ChangeGoal, MapMsg, NeedMap, ScanRecord
from swarmex.net import wire
from swarmex.net.mesh_frames import decode_control, decode_radio, encode_radio
from swarmex.net.mesh_robot import RobotProcess
from swarmex.net.mesh_scenario import MeshOptions, write_scenario
from swarmex.net.routing import LinkFeedback, wants_feedback
from swarmex.sensing.occupancy import rasterise
from swarmex.worlds.metric import empty_metric

pytestmark = pytest.mark.timeout(60)
SHAPE = (12, 12)


def _scan() -> ScanRecord:
    ranges = np.full(16, 3.0)
    angles = np.linspace(0.1, 6.2, 16)
    return ScanRecord(3, 4, 5, 5, rasterise(5, 5, ranges, angles, 4.0, SHAPE))


AODV_MESSAGES = [
    Rreq(1, 0, 3, 7, 4, -1, 1),
    Rrep(2, 0, 4, 5, 2, 60.0),
    Rerr(2, ((4, 6), (3, -1))),
    Routed(1, 0, 4, 130, NeedMap(0, ((0, 0, 9),)), 2),
    Routed(2, 3, 0, 131.5, MapMsg(3, (_scan(),)), 3),
    Routed(10_000, 7, 2, 90, ChangeGoal(7, (4, 4), 6.0), 2),
]


@pytest.mark.parametrize("msg", AODV_MESSAGES, ids=lambda m: type(m).__name__)
def test_aodv_messages_cross_the_wire_unchanged(msg):
    src, pos, back = decode_radio(encode_radio(msg.src, (2, 3), msg, link=5), SHAPE)
    assert (src, pos, type(back)) == (msg.src, (2, 3), type(msg))
    assert back.to_dict() == msg.to_dict() and back.nbytes == msg.nbytes
    if isinstance(msg, Routed):
        assert back.kind == msg.payload.kind and type(back.payload) is type(msg.payload)


def _with(msg, **changes) -> bytes:
    d = msg.to_dict()
    d.update(changes)
    return wire.pack(["R", msg.src, 1, 1, d])


@pytest.mark.parametrize("frame", [
    _with(AODV_MESSAGES[0], hops=-1),
    _with(AODV_MESSAGES[0], dest=10_001),
    _with(AODV_MESSAGES[1], life=-3.0),
    _with(AODV_MESSAGES[2], dests=[]),
    _with(AODV_MESSAGES[2], dests=[[4]]),
    _with(AODV_MESSAGES[3], payload={"type": "NEED_MAP", "src": 5, "have": []}),  # not orig
    _with(AODV_MESSAGES[3], payload={"type": "SCAN", "src": 0, "scans": []}),  # a flood
    _with(AODV_MESSAGES[3], payload={"type": "NEED_MAP", "src": 0, "have": [[1, 2]]}),
    _with(AODV_MESSAGES[3], hops=0),
    _with(AODV_MESSAGES[5], payload={"type": "CHANGE_GOAL", "src": 7, "goal": [40, 4],
                                     "priority": 1.0}),  # a goal off the map
    wire.pack(["R", 1, 1, 1, AODV_MESSAGES[0].to_dict(), 0]),  # link seq 0
    wire.pack(["R", 1, 1, 1, AODV_MESSAGES[0].to_dict(), 1, 2]),
], ids=lambda f: str(len(f)))
def test_malformed_aodv_frames_are_wire_errors(frame):
    with pytest.raises(wire.WireError):
        decode_radio(frame, SHAPE)


def test_nack_frames_are_checked():
    assert decode_control(wire.pack(["NACK", 10_000, 3])) == ["NACK", 10_000, 3]
    for bad in (["NACK", 1], ["NACK", -1, 3], ["NACK", 1, 0], ["NACK", 1, "x"]):
        with pytest.raises(wire.WireError):
            decode_control(wire.pack(bad))


def test_link_feedback_returns_only_what_went_to_the_refuser():
    link = LinkFeedback(keep=5)
    a = link.stamp(3, "m1", 0)
    b = link.stamp(4, "m2", 1)
    assert link.refused(4, a) is None  # a went to 3, not 4: a forged NACK is ignored
    assert link.refused(3, a) == "m1" and link.refused(3, a) is None  # once only
    link.prune(7)  # b is 6 ticks old: forgotten
    assert link.refused(4, b) is None and link.refusals == 1
    assert wants_feedback(NeedMap(0, ())) and wants_feedback(AODV_MESSAGES[1])
    assert wants_feedback(AODV_MESSAGES[4]) and not wants_feedback(AODV_MESSAGES[0])


def _pump(node, seconds: float = 2.0) -> list[bytes]:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if node.pull.poll(50):
            return node.recv_all()
    return []


def test_out_of_range_unicast_is_refused_and_requeued_by_aodv(tmp_path):
    """Robot 1 sends robot 0 a NEED_MAP over a route it believes in; robot 0 has moved out
    of range and drops the frame, answering NACK; robot 1's AODV then breaks the link,
    keeps the NEED_MAP in its queue and starts a route discovery (the simulator's
    send-failure path)."""
    grid = empty_metric(3, 3)  # 60 x 60 cells of 5 cm
    params = ExplorationParams(robots=2, laser_range=0.5, comm_range=1.0, seed=1,
                               starts=((5, 5), (10, 5)))
    write_scenario(tmp_path, grid, params, MeshOptions(), None)
    r0, r1 = RobotProcess(tmp_path, 0), RobotProcess(tmp_path, 1)
    try:
        for r in (r0, r1):  # both hear each other once: a valid one-hop route each way
            other = r1 if r is r0 else r0
            r.robot.mesh.hear(other.id, 0)
            r.robot.aodv.hello(other.id, 0)
        r0.robot.belief.pos = (50, 50)  # robot 0 has left: 2.2 m away, the radio reaches 1 m
        r1.send_out(r1.robot.unicast(0, NeedMap(1, ()), 0))
        assert len(r1.link.sent) == 1
        frames = _pump(r0)
        assert len(frames) == 1
        r0.on_frame(frames[0])
        assert r0.traffic.out_of_range == 1 and r0.robot.aodv.stats.delivered == 0
        nack = _pump(r1)
        assert len(nack) == 1 and decode_control(nack[0])[0] == "NACK"
        r1.on_frame(nack[0])
        a1 = r1.robot.aodv
        assert r1.link.refusals == 1 and not r1.link.sent
        assert a1.stats.link_breaks == 1 and a1.route(0, 0) is None
        assert [p.payload.kind for p in a1.queue] == ["NEED_MAP"]  # kept for a new route
        assert a1.stats.discoveries == 1
    finally:
        r0.close()
        r1.close()
