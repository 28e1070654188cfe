"""One mesh member's sockets and radio emulation, shared by the robot and display processes.

A :class:`Node` binds a PULL socket, publishes its endpoint in the *air* (the run directory)
and sends through one PUSH socket per peer with a send timeout, so a dead peer never stalls
it; it applies the receiver-side radio model (range and injected loss), the AODV link
feedback (NACK of an out-of-range unicast) and counts its :class:`Traffic`. The robot
(:mod:`swarmex.net.mesh_robot`) and the display (:mod:`swarmex.net.mesh_display`) add what
each does with the frames.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import zmq

from swarmex.comm.aodv import Routed
from swarmex.comm.message import PackedMessage
from swarmex.net import wire
from swarmex.net.mesh_frames import encode_radio, radio_link
from swarmex.net.mesh_scenario import MeshOptions
from swarmex.net.routing import LinkFeedback


@dataclass
class Traffic:
    """What one node sent and heard, counted two ways.

    *Messages* (``messages_out``, ``message_bytes_out``, ``by_kind``) are counted as the
    simulator counts them (:class:`swarmex.comm.mesh.DiscNetwork`), so that a record's
    ``messages_sent`` and ``bytes_sent`` mean the same in both runtimes: a broadcast (a
    heartbeat) is one message however many nodes the air holds, a unicast, relay or
    ``GOAL`` one message per copy (sent, whatever becomes of it), each of the message's own
    msgpack size (``nbytes``, without the radio frame's envelope and CRC). Until 30 Nov 2026
    the mesh counted socket frames: a heartbeat once per node in the air (the display
    included), and the harness's STATUS and HELLO as robots' messages.

    *Harness* frames (``harness_out``, ``harness_bytes_out``, ``harness_by_kind``) are the
    experiment's control link (HELLO, STATUS; the display's GO, BEAT, STOP) and the radio
    emulation's NACK (the link-layer feedback the simulator gives for free): traffic the
    simulator does not have, counted apart.

    *Frames* (``frames_out``, ``bytes_out``) are what the sockets carried: every frame sent,
    radio copies and harness alike, envelope and CRC included.
    """

    frames_out: int = 0
    bytes_out: int = 0
    send_timeouts: int = 0  # PUSH sends that timed out: dropped (the thesis's nanomsg rule)
    frames_in: int = 0
    bytes_in: int = 0
    out_of_range: int = 0  # copies of unicasts and relays heard out of range: lost
    # broadcast copies (heartbeats) out of range: unheard, as in the simulator, not lost
    unheard_broadcasts: int = 0
    lost_injected: int = 0
    bad_frames: int = 0
    messages_out: int = 0
    message_bytes_out: int = 0
    harness_out: int = 0
    harness_bytes_out: int = 0
    by_kind: dict[str, list[int]] = field(default_factory=dict)
    harness_by_kind: dict[str, list[int]] = field(default_factory=dict)

    def count_frame(self, nbytes: int) -> None:
        """A frame the sockets took."""
        self.frames_out += 1
        self.bytes_out += nbytes

    def count_message(self, kind: str, nbytes: int, copies: int = 1) -> None:
        """A radio message of ``nbytes`` (its own size) sent in ``copies`` copies (1 for a
        broadcast): the simulator's count."""
        self.messages_out += copies
        self.message_bytes_out += nbytes * copies
        row = self.by_kind.setdefault(kind, [0, 0])
        row[0] += copies
        row[1] += nbytes * copies

    def count_harness(self, kind: str, nbytes: int) -> None:
        """A control-link (or NACK) frame of ``nbytes`` sent."""
        self.harness_out += 1
        self.harness_bytes_out += nbytes
        row = self.harness_by_kind.setdefault(kind, [0, 0])
        row[0] += 1
        row[1] += nbytes

    def to_dict(self) -> dict[str, Any]:
        return {
            "messages_out": self.messages_out, "message_bytes_out": self.message_bytes_out,
            "harness_out": self.harness_out, "harness_bytes_out": self.harness_bytes_out,
            "frames_out": self.frames_out, "bytes_out": self.bytes_out,
            "send_timeouts": self.send_timeouts, "frames_in": self.frames_in,
            "bytes_in": self.bytes_in, "out_of_range": self.out_of_range,
            "unheard_broadcasts": self.unheard_broadcasts,
            "lost_injected": self.lost_injected, "bad_frames": self.bad_frames,
            "by_kind": {k: {"messages": m, "bytes": b} for k, (m, b) in
                        sorted(self.by_kind.items())},
            "harness_by_kind": {k: {"messages": m, "bytes": b} for k, (m, b) in
                                sorted(self.harness_by_kind.items())},
        }


def _is_broadcast(obj: list[Any]) -> bool:
    """Whether a checked radio frame is a broadcast (a heartbeat: the only one)."""
    return obj[4].get("type") == "HEARTBEAT"


class Node:
    """One mesh member: a PULL socket bound on loopback, PUSH sockets to peers on demand."""

    def __init__(self, node_id: int, run_dir: Path, options: MeshOptions, seed: int) -> None:
        self.id = node_id
        self.run_dir = run_dir
        self.options = options
        self.ctx: zmq.Context[zmq.Socket[bytes]] = zmq.Context.instance()
        self.pull = self.ctx.socket(zmq.PULL)
        self.pull.setsockopt(zmq.LINGER, 0)
        self.pull.bind("tcp://127.0.0.1:*")
        self.endpoint = self.pull.getsockopt_string(zmq.LAST_ENDPOINT)
        self.push: dict[int, zmq.Socket] = {}
        self.air: dict[int, str] = {}
        self.traffic = Traffic()
        self.loss_rng = np.random.default_rng([seed, node_id, 7])
        self.link = LinkFeedback()
        self.multihop_in: dict[str, int] = {}  # routed payloads delivered here, by kind
        self._publish()

    def _publish(self) -> None:
        """Announce this node's endpoint in the air (atomic: write, then rename)."""
        tmp = self.run_dir / f".node-{self.id}.tmp"
        tmp.write_text(self.endpoint)
        tmp.rename(self.run_dir / f"node-{self.id}.addr")

    def scan_air(self) -> dict[int, str]:
        for p in self.run_dir.glob("node-*.addr"):
            try:
                nid = int(p.stem.split("-", 1)[1])
                if nid != self.id and nid not in self.air:
                    self.air[nid] = p.read_text().strip()
            except (ValueError, OSError):
                continue
        return self.air

    def _socket_to(self, nid: int) -> zmq.Socket | None:
        sock = self.push.get(nid)
        if sock is None:
            addr = self.air.get(nid) or self.scan_air().get(nid)
            if addr is None:
                return None
            sock = self.ctx.socket(zmq.PUSH)
            sock.setsockopt(zmq.LINGER, 0)
            sock.setsockopt(zmq.SNDTIMEO, self.options.send_timeout_ms)
            sock.setsockopt(zmq.SNDHWM, 200)
            sock.connect(addr)
            self.push[nid] = sock
        return sock

    def send_frame(self, nid: int, frame: bytes) -> bool:
        """One frame to node ``nid`` (counted as a frame if the socket took it); False if
        it could not be sent (no address yet, or the send timeout)."""
        sock = self._socket_to(nid)
        if sock is None:
            return False
        try:
            sock.send(frame)
        except zmq.Again:  # the send timeout: the peer is gone or stuck; drop it
            self.traffic.send_timeouts += 1
            return False
        self.traffic.count_frame(len(frame))
        return True

    def transmit(self, dsts: Iterable[int], msg: PackedMessage | Routed, frame: bytes) -> None:
        """A radio message to each of ``dsts``: one message per copy, as the simulator
        counts a unicast or a relay (a copy the receiver drops is still sent)."""
        for nid in dsts:
            self.traffic.count_message(msg.kind, int(msg.nbytes))
            self.send_frame(nid, frame)

    def broadcast(self, msg: PackedMessage | Routed, frame: bytes) -> None:
        """A radio broadcast (a heartbeat): to every node in the air, range decides who
        hears it; one message, as the simulator counts a broadcast."""
        self.traffic.count_message(msg.kind, int(msg.nbytes))
        for nid in sorted(self.scan_air()):
            self.send_frame(nid, frame)

    def send_control(self, nid: int, obj: list[Any]) -> bool:
        """A harness frame (the control link's, or a NACK): counted apart from the radio's
        messages (:class:`Traffic`)."""
        frame = wire.pack(obj)
        if not self.send_frame(nid, frame):
            return False
        self.traffic.count_harness(str(obj[0]), len(frame))
        return True

    def recv_all(self, limit: int = 10_000) -> list[bytes]:
        frames = []
        for _ in range(limit):
            try:
                frames.append(self.pull.recv(flags=zmq.NOBLOCK))
            except zmq.Again:
                break
        for f in frames:
            self.traffic.frames_in += 1
            self.traffic.bytes_in += len(f)
        return frames

    def in_range(self, mine: tuple[int, int], theirs: tuple[int, int], cell: float,
                 comm_range: float) -> bool:
        if math.isinf(comm_range):
            return True
        dx = (mine[0] - theirs[0]) * cell
        dy = (mine[1] - theirs[1]) * cell
        return dx * dx + dy * dy <= comm_range * comm_range

    def lost(self) -> bool:
        return self.options.loss > 0 and self.loss_rng.random() < self.options.loss

    def admitted(self, obj: list[Any], src: int, mine: tuple[int, int],
                 theirs: tuple[int, int], cell: float, comm_range: float) -> bool:
        """Whether a radio frame from ``theirs`` reaches this node at ``mine``: out of range,
        it is counted and NACKed (:meth:`refuse`); in range, the injected loss may drop it
        (counted). The one admission rule of the robots' and the display's radios."""
        if not self.in_range(mine, theirs, cell, comm_range):
            if _is_broadcast(obj):  # a broadcast reaches whoever is in range: not lost
                self.traffic.unheard_broadcasts += 1
            else:
                self.traffic.out_of_range += 1
            self.refuse(obj, src)
            return False
        if self.lost():
            self.traffic.lost_injected += 1
            return False
        return True

    def unicast_frame(self, dst: int, msg: PackedMessage | Routed, pos: tuple[int, int],
                      t: int) -> bool:
        """Send a unicast that AODV wants feedback on (stamped with a link sequence
        number); False if the send itself failed (the peer is gone: the send timeout)."""
        seq = self.link.stamp(dst, msg, t)
        self.traffic.count_message(msg.kind, int(msg.nbytes))
        if self.send_frame(dst, encode_radio(self.id, pos, msg, seq)):
            return True
        self.link.sent.pop(seq, None)
        return False

    def refuse(self, obj: list[Any], src: int) -> None:
        """An out-of-range frame was dropped: if its sender asked for feedback, NACK it."""
        seq = radio_link(obj)
        if seq is not None:
            self.send_control(src, ["NACK", self.id, seq])

    def arrived(self, msg: Any) -> None:
        """Count a routed payload that ends here (the wire's own view of multi-hop delivery)."""
        if isinstance(msg, Routed) and msg.dest == self.id:
            self.multihop_in[msg.kind] = self.multihop_in.get(msg.kind, 0) + 1

    def close(self) -> None:
        for s in self.push.values():
            s.close()  # each socket's own linger (0, or longer for a last report)
        self.pull.close(0)
