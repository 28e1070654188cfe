"""Seed 003's exploration as OS processes on a brokerless ZeroMQ mesh (thesis ch. 2–3).

One process per robot plus one display process. Each binds its own PULL socket and sends
with one PUSH socket per peer, every send with a timeout: the thesis's nanomsg PIPELINE,
chosen there (§3.4) because a REQ-ROUTER sender blocks forever on a dead peer; a PUSH that
cannot deliver within ``send_timeout`` drops the message and counts it, so a killed robot
never stalls the others. Every frame is the wire format of :mod:`swarmex.net.wire`
(msgpack + CRC32); bad frames are dropped and counted.

The robots run the very :class:`~swarmex.missions.exploration.robot.ExplorerRobot` objects
the simulator drives, through the same calls (observe, housekeeping, on_message,
maybe_plan, next_step, moved). What the simulator owned — the truth, the lasers, the radio —
is split the way the real system splits it:

* **the truth and the laser** live in each robot process (the robot's own sensor reading
  the world file; the policy never sees it), and every step is checked against it;
* **the radio** is emulated: every radio frame carries the sender's cell, and the
  *receiver* drops it when the two are farther apart than the radio range (the disc model
  of the simulator, from true positions), or with the injected loss probability. Heartbeats
  (1 s) go to every node in the *air* — the run directory where each node publishes its
  PULL endpoint — so discovery works as the thesis's UDP heartbeats do: whoever is in range
  hears them; everything else goes to neighbour-table entries only. Multi-hop delivery is
  the robots' own ``SCAN`` flooding with de-duplication and, for the unicasts (``NEED_MAP``,
  ``MAP``, ``CHANGE_GOAL``), the simulator's AODV (:mod:`swarmex.net.routing`: its frames,
  and the ``NACK`` by which a receiver out of range refuses a unicast, the link-layer
  feedback the simulator gives at once);
* **the clock**: each robot ticks every ``0.1 × time_scale`` wall seconds (the thesis's
  100 ms movement period, scaled) on its own, asynchronously, as the thesis's processes did.

The display process (thesis §3.2: "the router, but it does not carry out the exploration")
joins the mesh: it heartbeats, relays floods, routes AODV unicasts, asks new neighbours for
their maps and keeps its own map of every scan it hears. Beside the radio there is a
**control link** that is not part of the robots' world — the experiment's harness: robots
say HELLO to the display, the display starts them together (GO), robots send STATUS
telemetry (position, moves, finished) and, after STOP, their REPORT (statistics and final
map). The display ends the run when every live robot has reported *finished* for a settling
time, writes the result record (the schema of ``swarmex explore``) and serves live monitor
events.

Faults: a robot that stops sending STATUS for ``dead_after`` seconds is dead to the display
(the others' neighbour tables time it out by themselves); ``inject_kill`` makes a robot exit
abruptly at a given tick; ``loss`` drops that share of radio frames at the receivers.
"""

from __future__ import annotations

import contextlib
import math
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import zmq

from swarmex.comm.aodv import CONTROL_KINDS, AodvMessage, Routed
from swarmex.comm.mesh import Fanout
from swarmex.comm.message import PackedMessage
from swarmex.net import events as ev
from swarmex.net import wire
from swarmex.net.routing import (
    AODV_WIRE_KINDS,
    ROUTED_PAYLOADS,
    LinkFeedback,
    check_aodv,
    unicast_counts,
    wants_feedback,
)

if TYPE_CHECKING:  # imported where used: each process loads only what it needs
    from swarmex.missions.exploration.messages import Message
    from swarmex.missions.exploration.params import ExplorationParams
    from swarmex.worlds.metric import MetricGrid

CONTROL = ("HELLO", "GO", "BEAT", "STATUS", "STOP", "REPORT", "NACK")
RADIO_KIND = "R"
STATUS_EVERY = 5  # ticks between STATUS frames (at most; and at least every STATUS_WALL s)
STATUS_WALL = 0.25  # wall seconds: liveness must not depend on the time scale
BEAT_WALL = 0.5  # the display's keep-alive on the control link
DISPLAY = 10_000  # the display's node id (robots are 0..n-1)


# ---------------------------------------------------------------------------- scenario


@dataclass
class MeshOptions:
    """The network's own options (the mission's are :class:`ExplorationParams`)."""

    time_scale: float = 1.0  # wall seconds per mission second (a tick is 0.1 s)
    loss: float = 0.0  # share of radio frames dropped at the receiver (fault injection)
    send_timeout_ms: int = 20
    dead_after: float = 4.0  # wall seconds without STATUS before the display drops a robot
    settle_ticks: int = 20  # all live robots finished for this many ticks → stop
    start_timeout: float = 60.0  # wall seconds to wait for every robot's HELLO
    timeout: float = 600.0  # wall seconds for the whole run
    inject_kill: dict[int, int] = field(default_factory=dict)  # robot id -> tick to die at
    display_cell: tuple[int, int] | None = None  # default: the first robot's start

    def to_wire(self) -> dict[str, Any]:
        return {
            "time_scale": self.time_scale, "loss": self.loss,
            "send_timeout_ms": self.send_timeout_ms, "dead_after": self.dead_after,
            "settle_ticks": self.settle_ticks, "start_timeout": self.start_timeout,
            "timeout": self.timeout,
            "inject_kill": [[int(k), int(v)] for k, v in self.inject_kill.items()],
            "display_cell": None if self.display_cell is None else list(self.display_cell),
        }

    @classmethod
    def from_wire(cls, d: dict[str, Any]) -> MeshOptions:
        cell = d.get("display_cell")
        return cls(
            float(d["time_scale"]), float(d["loss"]), int(d["send_timeout_ms"]),
            float(d["dead_after"]), int(d["settle_ticks"]), float(d["start_timeout"]),
            float(d["timeout"]), {int(k): int(v) for k, v in d.get("inject_kill") or []},
            None if cell is None else (int(cell[0]), int(cell[1])),
        )


def write_scenario(run_dir: Path, grid: MetricGrid, params: ExplorationParams,
                   options: MeshOptions, json_path: Path | None) -> None:
    from swarmex.missions.exploration.params import default_starts

    starts = params.starts or default_starts(grid, params.robots, params.robot_radius)
    p = params.as_dict()
    p["starts"] = [list(s) for s in starts]
    data = {
        "grid": {
            "width": grid.world.width, "height": grid.world.height, "cell": grid.cell,
            "free": np.packbits(grid.free.ravel()).tobytes(), "source": grid.world.source,
        },
        "params": p,
        "options": options.to_wire(),
        "json": None if json_path is None else str(json_path),
    }
    tmp = run_dir / "scenario.tmp"
    tmp.write_bytes(wire.pack(data))
    tmp.rename(run_dir / "scenario.msgpack")


def read_scenario(
    run_dir: Path,
) -> tuple[MetricGrid, ExplorationParams, MeshOptions, str | None]:
    """(grid, params, options, json path) of a run directory."""
    from swarmex.missions.exploration.params import ExplorationParams
    from swarmex.worlds import GridWorld
    from swarmex.worlds.metric import MetricGrid

    d = wire.unpack((run_dir / "scenario.msgpack").read_bytes())
    g = d["grid"]
    w, h = int(g["width"]), int(g["height"])
    free = np.unpackbits(np.frombuffer(g["free"], np.uint8), count=w * h).astype(bool)
    grid = MetricGrid(GridWorld(free.reshape(h, w), source=str(g["source"])), float(g["cell"]))
    p = dict(d["params"])
    p["starts"] = tuple((int(x), int(y)) for x, y in p["starts"])
    p["comm_range"] = math.inf if p["comm_range"] is None else float(p["comm_range"])
    params = ExplorationParams(**p)
    return grid, params, MeshOptions.from_wire(d["options"]), d.get("json")


# ---------------------------------------------------------------------------- radio frames


def encode_radio(src: int, pos: tuple[int, int], msg: PackedMessage | Routed,
                 link: int | None = None) -> bytes:
    """A radio frame ``[R, src, x, y, body]``, plus the link sequence number of a unicast
    whose refusal the sender wants to hear of (:mod:`swarmex.net.routing`)."""
    frame = [RADIO_KIND, src, int(pos[0]), int(pos[1]), msg.to_dict()]
    if link is not None:
        frame.append(int(link))
    return wire.pack(frame)


def radio_link(obj: list[Any]) -> int | None:
    """The link sequence number of a checked radio frame (None: no feedback wanted)."""
    return int(obj[5]) if len(obj) == 6 else None


def _cell(v: Any, shape: tuple[int, int], what: str) -> tuple[int, int]:
    if not isinstance(v, list) or len(v) != 2:
        raise wire.EncodingError(f"{what}: expected [x, y]")
    x, y = wire._int(v[0], what), wire._int(v[1], what)
    if not (0 <= x < shape[1] and 0 <= y < shape[0]):
        raise wire.EncodingError(f"{what}: ({x},{y}) is outside the map")
    return x, y


def _check_scans(scans: Any, shape: tuple[int, int]) -> None:
    if not isinstance(scans, list) or not scans or len(scans) > 1_000_000:
        raise wire.EncodingError("scans: expected a non-empty list")
    h, w = shape
    for s in scans:
        if not isinstance(s, dict):
            raise wire.EncodingError("scan: expected a map")
        wire._int(s.get("o"), "scan origin", 0, DISPLAY)
        wire._int(s.get("s"), "scan seq", 0, 2**40)
        _cell([s.get("x"), s.get("y")], shape, "scan cell")
        box = s.get("box")
        if not isinstance(box, list) or len(box) != 4:
            raise wire.EncodingError("scan box: expected [x0, y0, w, h]")
        x0, y0, bw, bh = (wire._int(v, "scan box", 0, 1 << 30) for v in box)
        if x0 + bw > w or y0 + bh > h:
            raise wire.EncodingError("scan box outside the map")
        nbytes = (bw * bh + 7) // 8
        for key in ("free", "occ"):
            b = s.get(key)
            if not isinstance(b, bytes) or len(b) != nbytes:
                raise wire.EncodingError(f"scan {key}: expected {nbytes} bytes")


def decode_radio(
    frame: bytes, shape: tuple[int, int]
) -> tuple[int, tuple[int, int], Message | AodvMessage | Routed]:
    """``(src, (x, y), message)`` of a radio frame (an exploration message, or AODV's when
    routing is on), fully checked against the map's shape;
    :class:`~swarmex.net.wire.WireError` for anything malformed."""
    return radio_message(wire.unpack(frame), shape)


def radio_message(
    obj: Any, shape: tuple[int, int]
) -> tuple[int, tuple[int, int], Message | AodvMessage | Routed]:
    """:func:`decode_radio` after the unpacking."""
    from swarmex.comm import aodv
    from swarmex.missions.exploration.messages import from_dict

    if not isinstance(obj, list) or len(obj) not in (5, 6) or obj[0] != RADIO_KIND:
        raise wire.EncodingError("not a radio frame")
    src = wire._int(obj[1], "radio src", 0, DISPLAY)
    pos = _cell([obj[2], obj[3]], shape, "sender cell")
    if len(obj) == 6:
        wire._int(obj[5], "link seq", 1)
    d = obj[4]
    if not isinstance(d, dict) or not isinstance(d.get("type"), str):
        raise wire.EncodingError("radio body: expected a typed map")
    kind = d["type"]
    if wire._int(d.get("src"), "message src", 0, DISPLAY) != src:
        raise wire.EncodingError("message src differs from the frame's sender")
    try:
        if kind in AODV_WIRE_KINDS:
            check_aodv(d, DISPLAY, lambda k, p: _check_body(k, p, shape))
            return src, pos, aodv.from_dict(d, from_dict)
        _check_body(kind, d, shape)
        return src, pos, from_dict(d)
    except wire.WireError:
        raise
    except (KeyError, TypeError, ValueError, IndexError, OverflowError) as exc:
        raise wire.EncodingError(f"radio body: {type(exc).__name__}") from None


def _check_body(kind: str, d: dict[str, Any], shape: tuple[int, int]) -> None:
    """Check an exploration message's fields against the map's shape."""
    if kind in ("SCAN", "MAP"):
        _check_scans(d.get("scans"), shape)
    elif kind == "HEARTBEAT":
        _cell([d.get("x"), d.get("y")], shape, "heartbeat cell")
    elif kind == "NEED_MAP":
        have = d.get("have")
        if not isinstance(have, list) or len(have) > 1_000_000:
            raise wire.EncodingError("NEED_MAP: expected a list of runs")
        for r in have:
            if not isinstance(r, list) or len(r) != 3:
                raise wire.EncodingError("NEED_MAP run: expected [origin, lo, hi]")
            for v in r:
                wire._int(v, "NEED_MAP run", 0, 2**40)
    elif kind == "GOAL":
        if d.get("goal") is not None:
            _cell(d.get("goal"), shape, "goal")
        wire._float(d.get("priority"), "priority")
        _cell([d.get("x"), d.get("y")], shape, "goal sender cell")
    elif kind == "CHANGE_GOAL":
        _cell(d.get("goal"), shape, "goal")
        wire._float(d.get("priority"), "priority")
    else:
        raise wire.EncodingError(f"unknown radio message {kind!r:.20}")


def decode_control(frame: bytes) -> list[Any]:
    """A control-link frame (HELLO, GO, STATUS, STOP, REPORT), shape-checked."""
    return control_message(wire.unpack(frame))


def control_message(obj: Any) -> list[Any]:
    """:func:`decode_control` after the unpacking."""
    if not isinstance(obj, list) or not obj or obj[0] not in CONTROL:
        raise wire.EncodingError("not a control frame")
    cmd = obj[0]
    arity = {"HELLO": 3, "GO": 1, "BEAT": 1, "STATUS": 3, "STOP": 1, "REPORT": 3,
             "NACK": 3}[cmd]
    if len(obj) != arity:
        raise wire.EncodingError(f"{cmd}: expected {arity - 1} fields")
    if cmd in ("HELLO", "STATUS", "REPORT"):
        wire._int(obj[1], f"{cmd} id", 0, DISPLAY - 1)
    if cmd == "HELLO":
        wire._str(obj[2], "HELLO endpoint", 200)
    if cmd == "NACK":  # [NACK, refusing node, link seq]
        wire._int(obj[1], "NACK id", 0, DISPLAY)
        wire._int(obj[2], "NACK seq", 1)
    if cmd in ("STATUS", "REPORT") and not isinstance(obj[2], dict):
        raise wire.EncodingError(f"{cmd}: expected a map")
    return obj


# ---------------------------------------------------------------------------- nodes


def _by_origin(scans: dict) -> dict[str, int]:
    """How many archived scans came from each robot (who heard whom, through any hops)."""
    out: dict[str, int] = {}
    for origin, _seq in scans:
        out[str(origin)] = out.get(str(origin), 0) + 1
    return dict(sorted(out.items()))


@dataclass
class Traffic:
    frames_out: int = 0
    bytes_out: int = 0
    send_timeouts: int = 0  # PUSH sends that timed out: dropped (the thesis's nanomsg rule)
    frames_in: int = 0
    bytes_in: int = 0
    out_of_range: int = 0
    lost_injected: int = 0
    bad_frames: int = 0
    by_kind: dict[str, list[int]] = field(default_factory=dict)

    def count_out(self, kind: str, nbytes: int) -> None:
        self.frames_out += 1
        self.bytes_out += nbytes
        row = self.by_kind.setdefault(kind, [0, 0])
        row[0] += 1
        row[1] += nbytes

    def to_dict(self) -> dict[str, Any]:
        return {
            "frames_out": self.frames_out, "bytes_out": self.bytes_out,
            "send_timeouts": self.send_timeouts, "frames_in": self.frames_in,
            "bytes_in": self.bytes_in, "out_of_range": self.out_of_range,
            "lost_injected": self.lost_injected, "bad_frames": self.bad_frames,
            "by_kind": {k: {"messages": m, "bytes": b} for k, (m, b) in
                        sorted(self.by_kind.items())},
        }


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

    def send_frame(self, nid: int, frame: bytes, kind: str) -> bool:
        sock = self._socket_to(nid)
        if sock is None:
            return False
        try:
            sock.send(frame)
        except zmq.Again:  # the send timeout: the peer is gone or stuck; drop it
            self.traffic.send_timeouts += 1
            return False
        self.traffic.count_out(kind, len(frame))
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

    def unicast_frame(self, dst: int, msg: PackedMessage | Routed, pos: tuple[int, int],
                      t: int) -> bool:
        """Send a unicast that AODV wants feedback on (stamped with a link sequence
        number); False if the send itself failed (the peer is gone: the send timeout)."""
        seq = self.link.stamp(dst, msg, t)
        if self.send_frame(dst, encode_radio(self.id, pos, msg, seq), msg.kind):
            return True
        self.link.sent.pop(seq, None)
        return False

    def refuse(self, obj: list[Any], src: int) -> None:
        """An out-of-range frame was dropped: if its sender asked for feedback, NACK it."""
        seq = radio_link(obj)
        if seq is not None:
            self.send_frame(src, wire.pack(["NACK", self.id, seq]), "NACK")

    def arrived(self, msg: Any) -> None:
        """Count a routed payload that ends here (the wire's own view of multi-hop delivery)."""
        if isinstance(msg, Routed) and msg.dest == self.id:
            self.multihop_in[msg.kind] = self.multihop_in.get(msg.kind, 0) + 1

    def close(self) -> None:
        for s in self.push.values():
            s.close()  # each socket's own linger (0, or longer for a last report)
        self.pull.close(0)


class RobotProcess(Node):
    """One robot: its :class:`ExplorerRobot`, its laser on the truth, its radio."""

    def __init__(self, run_dir: Path, rid: int) -> None:
        from swarmex.missions.exploration.sim import build_robots, legal_step
        from swarmex.sensing.laser import Laser

        grid, params, options, _ = read_scenario(run_dir)
        super().__init__(rid, run_dir, options, params.seed)
        self.grid = grid
        self.params = params
        rng = np.random.default_rng(params.seed)  # the simulator's phases, robot by robot
        robots, starts, laser = build_robots(grid, params, rng, routing=params.aodv)
        self.robot = robots[rid]
        self.laser: Laser = laser
        self.legal_step = legal_step
        self.truth = grid.free
        self.trajectory: list[list[int]] = [[0, *starts[rid]]]
        self.unsent_moves: list[list[int]] = [[0, *starts[rid]]]
        self.t = 0
        self.stop = False
        self.go = False
        self.last_control = time.monotonic()
        self.status_at = 0.0
        from swarmex.missions.exploration.params import max_ticks_for

        self.max_ticks = params.max_ticks or max_ticks_for(grid, params.laser_range)

    def pos(self) -> tuple[int, int]:
        return self.robot.pos

    def send_out(self, out: Iterable[tuple[int | Fanout, PackedMessage | Routed]]) -> None:
        """Put the robot's messages on the air. With AODV, a unicast (application unicast,
        routed hop, RREP) that cannot be sent is a broken link: the robot re-queues it and
        rediscovers (:meth:`ExplorerRobot.link_failed`), as in the simulator. A
        :class:`Fanout` (one message to several neighbours) goes out as a frame each."""
        from swarmex.missions.exploration.robot import RADIO

        routed = self.robot.aodv is not None
        for dst, msg in out:
            if routed and dst != RADIO and wants_feedback(msg):
                for nid in dst if isinstance(dst, Fanout) else (dst,):  # a unicast each
                    if not self.unicast_frame(nid, msg, self.pos(), self.t):
                        self.send_out(self.robot.link_failed(nid, msg, self.t))
                continue
            frame = encode_radio(self.id, self.pos(), msg)
            if isinstance(dst, Fanout):  # one message to several neighbours: a frame each
                for nid in dst:
                    self.send_frame(nid, frame, msg.kind)
            elif dst == RADIO:  # heartbeat: to everyone in the air; range decides who hears
                for nid in sorted(self.scan_air()):
                    self.send_frame(nid, frame, msg.kind)
            else:
                self.send_frame(dst, frame, msg.kind)

    def control(self, obj: list[Any]) -> None:
        frame = wire.pack(obj)
        self.send_frame(DISPLAY, frame, obj[0])

    def on_frame(self, frame: bytes) -> None:
        from swarmex.missions.exploration.messages import Heartbeat

        try:
            obj = wire.unpack(frame)
            if isinstance(obj, list) and obj and obj[0] == RADIO_KIND:
                src, where, msg = radio_message(obj, self.grid.shape)
            else:
                cmd = control_message(obj)
                if cmd[0] == "NACK":  # a unicast of ours was out of the receiver's range
                    self._refused(int(cmd[1]), int(cmd[2]))
                    return
                self.last_control = time.monotonic()
                if cmd[0] == "STOP":
                    self.stop = True
                elif cmd[0] == "GO":
                    self.go = True
                return
        except wire.WireError:
            self.traffic.bad_frames += 1
            return
        if src == self.id:
            return
        if not self.in_range(self.pos(), where, self.grid.cell, self.params.comm_range):
            self.traffic.out_of_range += 1
            self.refuse(obj, src)
            return
        if self.lost():
            self.traffic.lost_injected += 1
            return
        if src == DISPLAY and isinstance(msg, Heartbeat):
            self.robot.mesh.hear(DISPLAY, self.t)  # the display is a router, not a teammate
            if self.robot.aodv is not None:  # ... and one AODV may route through
                self.send_out(self.robot.aodv.hello(DISPLAY, self.t))
            return
        self.arrived(msg)
        self.send_out(self.robot.on_message(src, msg, self.t))  # type: ignore[arg-type]

    def _refused(self, by: int, seq: int) -> None:
        msg = self.link.refused(by, seq)
        if msg is not None:
            self.send_out(self.robot.link_failed(by, msg, self.t))

    def tick(self) -> None:
        r = self.robot
        t = self.t
        moved = t == 0
        if t > 0:
            step = r.next_step()
            if step is not None:
                if not self.legal_step(self.truth, r.pos, step):
                    raise RuntimeError(f"robot {self.id} asked for an illegal step")
                r.moved(step)
                moved = True
                self.trajectory.append([t, step[0], step[1]])
                self.unsent_moves.append([t, step[0], step[1]])
        if moved:
            self.send_out(r.observe(self.laser.cast(self.truth, *r.pos), t))
        self.send_out(r.housekeeping(t))
        self.send_out(r.maybe_plan(t))
        self.link.prune(t)
        if t % STATUS_EVERY == 0:
            self.status()

    def status(self) -> None:
        self.status_at = time.monotonic()
        r = self.robot
        self.control(["STATUS", self.id, {
            "t": self.t, "x": r.pos[0], "y": r.pos[1], "finished": r.finished,
            "stopped": self.t > self.max_ticks,
            "goal": None if r.goal is None else list(r.goal), "moves": self.unsent_moves,
        }])
        self.unsent_moves = []

    def report(self) -> dict[str, Any]:
        r = self.robot
        s = r.stats
        free = r.belief.grid.logodds < 0
        return {
            "steps": s.finished_at if s.finished_at is not None else self.t,
            "finished_at": s.finished_at,
            "ticks": self.t,
            "moves": s.moves, "plans": s.plans, "replans": s.replans,
            "replan_reasons": dict(sorted(s.reasons.items())),
            "plan_ticks": list(s.plan_ticks), "scans": s.scans,
            "archive": len(r.belief.archive), "conflicts": s.conflicts,
            "scans_by_origin": _by_origin(r.belief.archive.scans),
            "change_goals_sent": s.change_goals_sent,
            "blacklisted_regions": s.blacklisted_regions,
            "trajectory": self.trajectory,
            "free": np.packbits(free.ravel()).tobytes(),
            "traffic": self.traffic.to_dict(),
            "unicasts": unicast_counts(r.aodv, s.gap_requests),
            "multihop_in": dict(sorted(self.multihop_in.items())),
            "link_refusals": self.link.refusals,
        }

    def warm_up(self) -> None:
        """A first tick on a scratch copy of this robot, before saying HELLO: loading the
        compiled kernels (laser, maps, planning) can take seconds on a busy machine, long
        enough to look dead to the display."""
        from swarmex.missions.exploration.sim import build_robots

        robots, _, laser = build_robots(self.grid, self.params,
                                        np.random.default_rng(self.params.seed),
                                        routing=self.params.aodv)
        r = robots[self.id]
        r.observe(laser.cast(self.truth, *r.pos), 0)
        r.housekeeping(0)
        r.maybe_plan(0)

    def run(self) -> int:
        opts = self.options
        tick_wall = 0.1 * opts.time_scale
        self.warm_up()
        self.last_control = time.monotonic()
        deadline = time.monotonic() + opts.timeout
        hello_at = 0.0
        # HELLO until GO: the display may come up after us
        while not self.go and not self.stop:
            now = time.monotonic()
            if now > deadline or now - self.last_control > opts.start_timeout + 5:
                return 3
            if now >= hello_at:
                self.control(["HELLO", self.id, self.endpoint])
                hello_at = now + 0.5
            if self.pull.poll(100):
                for f in self.recv_all():
                    self.on_frame(f)
        next_tick = time.monotonic()
        kill_at = opts.inject_kill.get(self.id)
        max_ticks = self.max_ticks
        while not self.stop:
            now = time.monotonic()
            if now > deadline or now - self.last_control > max(10.0, 4 * opts.dead_after):
                return 3  # the display (the experiment) is gone
            if now >= next_tick:
                if kill_at is not None and self.t >= kill_at:
                    os._exit(137)  # fault injection: no goodbye, sockets left as they are
                if self.t <= max_ticks:
                    self.tick()
                    self.t += 1
                next_tick += tick_wall
                if next_tick < now - 1.0:  # far behind (a slow machine): do not burst
                    next_tick = now
            if time.monotonic() - self.status_at >= STATUS_WALL:
                self.status()  # telemetry is also the display's proof of life
            wait = max(0.0, min(next_tick, self.status_at + STATUS_WALL) - time.monotonic())
            if self.pull.poll(int(wait * 1000)):
                for f in self.recv_all():
                    self.on_frame(f)
                    if self.stop:
                        break
        self.status()
        self.control(["REPORT", self.id, self.report()])
        sock = self.push.get(DISPLAY)
        if sock is not None:  # let the report leave before the sockets close
            sock.setsockopt(zmq.LINGER, 3000)
        return 0


class DisplayProcess(Node):
    """The display application: a non-exploring mesh router that watches and records."""

    def __init__(self, run_dir: Path, view_bind: str = "tcp://127.0.0.1:*",
                 monitor_url: str | None = None) -> None:
        from swarmex.comm.aodv import AodvNode, AodvTiming
        from swarmex.comm.mesh import MeshNode
        from swarmex.missions.exploration.belief import ExplorationBelief
        from swarmex.missions.exploration.robot import RobotConfig
        from swarmex.missions.exploration.sim import reachable_free

        grid, params, options, json_path = read_scenario(run_dir)
        super().__init__(DISPLAY, run_dir, options, params.seed)
        self.grid = grid
        self.params = params
        self.json_path = None if json_path is None else Path(json_path)
        assert params.starts is not None  # a scenario's starts are always filled in
        self.starts = params.starts
        self.cell = options.display_cell or self.starts[0]
        self.belief = ExplorationBelief(grid.shape, self.cell)
        self.mesh = MeshNode(DISPLAY, params.heartbeat_period, params.neighbour_timeout)
        # the thesis's display is "the router": with AODV on, it routes unicasts too
        self.aodv = AodvNode(
            DISPLAY, self.mesh.relay_targets,
            AodvTiming.for_mesh(params.heartbeat_period, params.neighbour_timeout),
        ) if params.aodv else None
        self.lifetime = RobotConfig.unicast_lifetime  # what a robot's NEED_MAP / MAP gets
        self.reachable = reachable_free(grid.free, self.starts)
        self.robots: dict[int, dict[str, Any]] = {}
        self.reports: dict[int, dict] = {}
        self.t = 0
        self.view = self.ctx.socket(zmq.ROUTER)
        self.view.setsockopt(zmq.LINGER, 0)
        self.view.bind(view_bind)
        self.view_endpoint = self.view.getsockopt_string(zmq.LAST_ENDPOINT)
        self.viewers: set[bytes] = set()
        self.viewer_beat = 0.0
        self.events: list[dict] = []
        self.pending: list[dict] = []
        self.forwarder = ev.IngestForwarder(monitor_url) if monitor_url else None
        self.record: dict[str, Any] | None = None

    # ---- radio
    def on_radio(self, obj: list[Any]) -> None:
        from swarmex.missions.exploration.messages import Heartbeat, NeedMap

        try:
            src, where, msg = radio_message(obj, self.grid.shape)
        except wire.WireError:
            self.traffic.bad_frames += 1
            return
        if not self.in_range(self.cell, where, self.grid.cell, self.params.comm_range):
            self.traffic.out_of_range += 1
            self.refuse(obj, src)
            return
        if self.lost():
            self.traffic.lost_injected += 1
            return
        aodv = self.aodv
        if isinstance(msg, Heartbeat):
            new = self.mesh.hear(src, self.t)
            if aodv is not None:
                self.send_out(aodv.hello(src, self.t))
            if new:
                self.unicast(src, NeedMap(DISPLAY, self.belief.archive.summary()))
            return
        if self.mesh.hear(src, self.t) and aodv is not None:  # the reverse connection
            self.send_out(aodv.hello(src, self.t))
        if aodv is not None and isinstance(msg, (AodvMessage, Routed)):
            self.arrived(msg)
            sent, delivered = aodv.receive(src, msg, self.t)
            self.send_out(sent)
            for orig, payload in delivered:  # a multi-hop unicast for the display
                self._application(orig, None, payload)
            return
        if aodv is not None and msg.kind in ROUTED_PAYLOADS:
            aodv.delivered_direct()
        self._application(src, src, msg)  # type: ignore[arg-type]

    def _application(self, sender: int, via: int | None, msg: Message) -> None:
        """An exploration message from ``sender`` (through neighbour ``via``; None: over
        several hops), handled as a router that keeps a map and explores nothing."""
        from swarmex.missions.exploration.messages import Goal, MapMsg, NeedMap, ScanMsg

        if isinstance(msg, ScanMsg):  # SCAN and MAP: integrate, relay as a router does
            new = tuple(r for r in msg.scans if self.mesh.first_time(r.key))
            for r in new:
                self.belief.integrate(r)
            if new:
                fwd = ScanMsg(DISPLAY, new)
                for n in self.mesh.relay_targets(via):
                    self.radio(n, fwd)
        elif isinstance(msg, NeedMap):
            missing = self.belief.archive.missing_for(msg.have)
            if missing:
                self.unicast(sender, MapMsg(DISPLAY, tuple(missing)))
        elif isinstance(msg, Goal) and sender in self.robots:
            self.robots[sender]["goal"] = msg.goal

    def radio(self, dst: int, msg: PackedMessage) -> None:
        self.send_frame(dst, encode_radio(DISPLAY, self.cell, msg), msg.kind)

    def unicast(self, dst: int, msg: Message) -> None:
        """The display's own unicast (``NEED_MAP``, ``MAP``): by AODV when routing is on."""
        if self.aodv is None:
            self.radio(dst, msg)
        else:
            self.send_out(self.aodv.send(dst, msg, self.t, self.lifetime))

    def send_out(self, out: Iterable[tuple[int, Any]]) -> None:
        """AODV's transmissions; a unicast that cannot be sent breaks the link (as a robot's)."""
        assert self.aodv is not None
        for dst, msg in out:
            if not wants_feedback(msg):
                self.radio(dst, msg)
            elif not self.unicast_frame(dst, msg, self.cell, self.t):
                self._failed(dst, msg)

    def _failed(self, dst: int, msg: Any) -> None:
        assert self.aodv is not None
        self.send_out(self.aodv.send_failed(dst, msg, self.t, self.lifetime))

    def heartbeat(self) -> None:
        from swarmex.missions.exploration.messages import Heartbeat

        frame = encode_radio(DISPLAY, self.cell, Heartbeat(DISPLAY, *self.cell))
        for nid in sorted(self.scan_air()):
            self.send_frame(nid, frame, "HEARTBEAT")
        for gone in self.mesh.expire(self.t):
            if self.aodv is not None:
                self.send_out(self.aodv.link_broken(gone, self.t))

    def route_tick(self) -> None:
        """AODV's queue (expiries, discovery retries) and the link feedback's memory."""
        if self.aodv is not None:
            self.send_out(self.aodv.tick(self.t))
        self.link.prune(self.t)

    # ---- control
    def on_control(self, obj: list[Any], now: float) -> None:
        cmd, rid = obj[0], int(obj[1])
        if rid >= self.params.robots:
            self.traffic.bad_frames += 1
            return
        info = self.robots.setdefault(rid, {"seen": now, "finished": False, "t": 0,
                                            "pos": tuple(self.starts[rid]),
                                            "trajectory": [], "goal": None,
                                            "alive": True})
        info["seen"] = now
        if cmd == "HELLO":
            self.air[rid] = str(obj[2])
        elif cmd == "STATUS":
            d = obj[2]
            try:
                info["t"] = int(d["t"])
                info["finished"] = bool(d["finished"])
                info["stopped"] = bool(d.get("stopped"))
                info["pos"] = (int(d["x"]), int(d["y"]))
                moves = [[int(t), int(x), int(y)] for t, x, y in d["moves"]]
            except (KeyError, TypeError, ValueError):
                self.traffic.bad_frames += 1
                return
            info["trajectory"].extend(moves)
            for t, x, y in moves:
                self._emit(ev.move(float(t), rid, float(x), float(y)))
        elif cmd == "REPORT":
            self.reports[rid] = obj[2]

    def broadcast_control(self, obj: list[Any]) -> None:
        frame = wire.pack(obj)
        for rid in sorted(self.robots):
            self.send_frame(rid, frame, obj[0])

    # ---- events
    def _emit(self, *events: ev.Event) -> None:
        self.pending.extend(events)

    def _flush(self) -> None:
        for _ in range(1000):
            try:
                ident, frame = self.view.recv_multipart(flags=zmq.NOBLOCK)[:2]
            except (zmq.Again, ValueError):
                break
            try:
                msg = wire.unpack(frame)
            except wire.WireError:
                continue
            if msg == ["MON"] and ident not in self.viewers:
                self.viewers.add(ident)
                if self.events:
                    self.view.send_multipart([ident, wire.pack(["EV", ev.dumps(self.events)])])
        now = time.monotonic()
        if now >= self.viewer_beat and self.viewers:  # viewers time out on silence
            self.viewer_beat = now + 1.0
            beat = wire.pack(["HB", float(self.t)])
            for ident in self.viewers:
                with contextlib.suppress(zmq.ZMQError):
                    self.view.send_multipart([ident, beat], flags=zmq.NOBLOCK)
        if not self.pending:
            return
        batch, self.pending = self.pending, []
        batch.sort(key=lambda e: e.get("t", -1.0))
        self.events.extend(batch)
        text = wire.pack(["EV", ev.dumps(batch)])
        for ident in self.viewers:
            with contextlib.suppress(zmq.ZMQError):
                self.view.send_multipart([ident, text], flags=zmq.NOBLOCK)
        if self.forwarder is not None:
            self.forwarder.send(batch)

    # ---- run
    def run(self, say: Callable[[str], object] = print) -> int:
        opts = self.options
        n = self.params.robots
        say(f"swarmex mesh display: view on {self.view_endpoint}, waiting for {n} robots")
        start = time.monotonic()
        deadline = start + opts.timeout
        w = self.grid.world
        self._emit(
            ev.hello("exploration", self.params.strategy, list(range(n)),
                     f"exploration · {self.params.strategy} · {w.source} · processes",
                     None, "step"),
            ev.world(w.free, w.width, w.height, w.source),
        )
        # start barrier: every robot said HELLO (or the start timeout passed)
        while len(self.robots) < n and time.monotonic() - start < opts.start_timeout:
            self._pump(time.monotonic())
        self.broadcast_control(["GO"])
        say(f"swarmex mesh display: {len(self.robots)} robots started")
        t0 = time.monotonic()
        tick_wall = 0.1 * opts.time_scale
        finished_since: float | None = None
        next_tick = t0
        next_beat = t0
        code = 0
        while True:
            now = time.monotonic()
            if now > deadline:
                say("swarmex mesh display: timeout")
                code = 3
                break
            if now >= next_beat:  # robots leave when the experiment is gone
                self.broadcast_control(["BEAT"])
                next_beat = now + BEAT_WALL
            if now >= next_tick:
                if self.mesh.heartbeat_due(self.t):
                    self.heartbeat()
                self.route_tick()
                self.t += 1
                next_tick += tick_wall
                if next_tick < now - 1.0:
                    next_tick = now
            for rid, info in self.robots.items():
                if info["alive"] and now - info["seen"] > opts.dead_after:
                    info["alive"] = False
                    self._emit(ev.message(float(info["t"]), rid, "left"))
                    say(f"swarmex mesh display: robot {rid} fell silent; the others go on")
            live = [i for i in self.robots.values() if i["alive"]]
            if live and all(i["finished"] or i.get("stopped") for i in live):
                if finished_since is None:
                    finished_since = now
                if now - finished_since >= opts.settle_ticks * tick_wall:
                    break
            else:
                finished_since = None
            if not live and self.robots:
                say("swarmex mesh display: no robot left")
                code = 1
                break
            self._pump(now, max(0.0, next_tick - time.monotonic()))
        # stop everyone and collect the reports
        self.broadcast_control(["STOP"])
        wait_until = time.monotonic() + max(3.0, 2 * opts.dead_after)
        live_ids = {r for r, i in self.robots.items() if i["alive"]}
        while set(self.reports) < live_ids and time.monotonic() < wait_until:
            self._pump(time.monotonic(), 0.05)
        self.record = self.build_record(time.monotonic() - t0, code == 0)
        self._emit(ev.end(self.record, self.events + self.pending))
        self._flush()
        if self.json_path is not None:
            from swarmex.engine.record import write_json_atomic

            write_json_atomic(self.record, self.json_path)
        with contextlib.suppress(OSError):
            (self.run_dir / "record.json").write_text(ev.dumps([self.record]))
        if self.forwarder is not None:
            self.forwarder.close()
        return code

    def _pump(self, now: float, wait: float = 0.05) -> None:
        self._flush()
        if self.pull.poll(int(min(wait, 0.05) * 1000)):
            for frame in self.recv_all():
                try:
                    obj = wire.unpack(frame)
                    if isinstance(obj, list) and obj and obj[0] == RADIO_KIND:
                        self.on_radio(obj)
                        continue
                    obj = control_message(obj)
                except wire.WireError:
                    self.traffic.bad_frames += 1
                    continue
                if obj[0] == "NACK":  # a unicast of ours was out of the receiver's range
                    msg = self.link.refused(int(obj[1]), int(obj[2]))
                    if msg is not None and self.aodv is not None:
                        self._failed(int(obj[1]), msg)
                elif obj[0] in ("HELLO", "STATUS", "REPORT"):
                    self.on_control(obj, now)

    def build_record(self, wall: float, ended: bool) -> dict[str, Any]:
        from swarmex import __version__
        from swarmex.engine.record import plain
        from swarmex.missions.exploration.params import TICK_SECONDS
        from swarmex.missions.exploration.record import average_robot, intervals

        params = self.params
        reach = self.reachable
        n_reach = max(1, int(reach.sum()))
        team_free = np.zeros(self.grid.shape, dtype=bool)
        agents = []
        totals: dict[str, Any] = {"moves": 0, "plans": 0, "replans": 0, "conflicts": 0,
                                  "change_goals_sent": 0, "blacklisted_regions": 0}
        reasons: dict[str, int] = {}
        by_kind: dict[str, list[int]] = {}
        unicasts = unicast_counts(None, 0)
        multihop_in = dict(self.multihop_in)
        sent = sent_bytes = lost = 0
        steps = []
        plan_series = []
        for rid in range(params.robots):
            info = self.robots.get(rid, {"trajectory": [], "alive": False, "t": 0})
            rep = self.reports.get(rid)
            metrics: dict[str, Any] = {"alive": bool(info.get("alive")),
                                       "reported": rep is not None}
            traj = info["trajectory"] or [[0, *self.starts[rid]]]
            if rep is not None:
                try:
                    free = np.unpackbits(np.frombuffer(rep["free"], np.uint8),
                                         count=reach.size).astype(bool).reshape(reach.shape)
                    team_free |= free
                    tr = rep["traffic"]
                    metrics.update({k: rep[k] for k in (
                        "steps", "moves", "plans", "replans", "replan_reasons", "scans",
                        "archive", "conflicts", "change_goals_sent", "blacklisted_regions")})
                    metrics["plan_intervals"] = intervals(rep["plan_ticks"])
                    metrics["scans_by_origin"] = rep.get("scans_by_origin", {})
                    metrics["messages_sent"] = tr["frames_out"]
                    metrics["bytes_sent"] = tr["bytes_out"]
                    metrics["explored_fraction_own"] = float((free & reach).sum()) / n_reach
                    metrics["traffic"] = tr
                    metrics["unicasts"] = rep["unicasts"]
                    metrics["multihop_in"] = rep["multihop_in"]
                    metrics["link_refusals"] = int(rep["link_refusals"])
                    for k, v in rep["unicasts"].items():
                        unicasts[k] += int(v)
                    for k, v in rep["multihop_in"].items():
                        multihop_in[k] = multihop_in.get(k, 0) + int(v)
                    traj = rep["trajectory"]
                    steps.append(int(rep["steps"]))
                    plan_series.append(metrics["plan_intervals"])
                    for k in totals:
                        totals[k] += int(rep[k])
                    for k, v in rep["replan_reasons"].items():
                        reasons[k] = reasons.get(k, 0) + int(v)
                    sent += tr["frames_out"]
                    sent_bytes += tr["bytes_out"]
                    lost += tr["send_timeouts"] + tr["out_of_range"] + tr["lost_injected"]
                    for k, row in tr["by_kind"].items():
                        acc = by_kind.setdefault(k, [0, 0])
                        acc[0] += row["messages"]
                        acc[1] += row["bytes"]
                except (KeyError, TypeError, ValueError):
                    metrics["reported"] = False
            agents.append({"id": rid, "metrics": metrics,
                           "trajectory": [[int(t), int(x), int(y)] for t, x, y in traj],
                           "jobs": []})
        explored = float((team_free & reach).sum()) / n_reach
        live = [i for i in self.robots.values() if i.get("alive")]
        complete = ended and bool(live) and all(i["finished"] for i in live)
        makespan = max(steps) if steps else 0
        p = params.as_dict()
        p["starts"] = [list(s) for s in self.starts]
        p["cell"] = self.grid.cell
        p["processes"] = self.options.to_wire()
        record = {
            "swarmex_version": __version__,
            "mission": "exploration",
            "algorithm": params.strategy,
            "params": p,
            "seed": params.seed,
            "world": self.grid.describe(),
            "complete": complete,
            "makespan": float(makespan),
            "time_unit": "step",
            "metrics": {
                "explored_fraction": explored,
                "reachable_free_cells": int(reach.sum()),
                "steps": steps,
                "mean_steps": float(np.mean(steps)) if steps else None,
                "makespan_seconds": makespan * TICK_SECONDS,
                **totals,
                "replan_reasons": dict(sorted(reasons.items())),
                "messages_sent": sent,
                "bytes_sent": sent_bytes,
                "messages_lost": lost,
                "messages_by_kind": {k: {"messages": m, "bytes": b}
                                     for k, (m, b) in sorted(by_kind.items())},
                "aodv_messages": sum(by_kind[k][0] for k in CONTROL_KINDS if k in by_kind),
                "aodv_bytes": sum(by_kind[k][1] for k in CONTROL_KINDS if k in by_kind),
                # the robots' AODV statistics, summed (as the simulator's record), and what
                # the receivers saw arrive in routed envelopes (robots and display, by kind)
                "unicasts": unicasts,
                "multihop_in_by_kind": dict(sorted(multihop_in.items())),
                "display_unicasts": unicast_counts(self.aodv, 0),
                "plan_intervals_avg": average_robot(plan_series),
                "finished_robots": int(sum(1 for i in live if i["finished"])),
                "robots_lost": int(sum(1 for i in self.robots.values() if not i["alive"])),
                "display_scans_by_origin": _by_origin(self.belief.archive.scans),
                "display_map_fraction": float(
                    ((self.belief.grid.logodds < 0) & reach).sum()) / n_reach,
                "display_traffic": self.traffic.to_dict(),
            },
            "agents": agents,
            "wall_seconds": wall,
            "tick_seconds": TICK_SECONDS,
        }
        return plain(record)


# ---------------------------------------------------------------------------- launcher


#: what the fork server imports once, so each robot process starts in milliseconds instead
#: of re-importing numpy, scipy and numba (seconds each, on a busy machine)
PRELOAD = ["swarmex.net.mesh", "swarmex.missions.exploration.sim",
           "swarmex.missions.exploration.robot", "swarmex.missions.exploration.record",
           "swarmex.engine.record", "zmq"]


def _robot_entry(run_dir: str, rid: int, log_path: str) -> None:
    """A robot process's body (started by the fork server): output to its log file."""
    log = os.open(log_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(log, 1)
    os.dup2(log, 2)
    code = main(["robot", run_dir, str(rid)])
    # a multiprocessing child ends with os._exit, which would kill ZeroMQ's I/O thread with
    # the REPORT still queued: terminating the context waits for each socket's linger
    zmq.Context.instance().term()
    sys.exit(code)


def _display_entry(run_dir: str, monitor_url: str | None, conn: Any) -> None:
    """The display process's body: its lines go back to the launcher through ``conn``."""
    node = DisplayProcess(Path(run_dir), monitor_url=monitor_url)
    try:
        code = node.run(conn.send)
    finally:
        node.close()
        node.view.close(1000)  # let the last event batch reach the viewers
        zmq.Context.instance().term()  # (see _robot_entry)
        conn.send(None)
        conn.close()
    sys.exit(code)


def run_processes(grid: MetricGrid, params: ExplorationParams, options: MeshOptions,
                  json_path: Path | None = None, monitor_url: str | None = None,
                  say: Callable[[str], object] = print) -> dict[str, Any]:
    """``swarmex explore --processes``: a display and one OS process per robot; the record.

    Processes come from a multiprocessing *fork server* that has imported the mission code
    once (each child is still its own process with its own sockets, started from a clean
    single-threaded parent, so no lock or thread of the launcher leaks into it). Every child
    is killed (by its own pid) if it outlives the run; the run directory (the air) is
    removed at the end.
    """
    import multiprocessing

    from swarmex.missions.exploration.params import validate

    validate(params, grid)
    mp = multiprocessing.get_context("forkserver")
    mp.set_forkserver_preload(PRELOAD)
    run_dir = Path(tempfile.mkdtemp(prefix="swarmex-mesh-"))
    procs: list[Any] = []
    try:
        record_path = run_dir / "out.json"
        write_scenario(run_dir, grid, params, options, json_path or record_path)
        lines, child_end = mp.Pipe(duplex=False)
        display = mp.Process(target=_display_entry, args=(str(run_dir), monitor_url, child_end),
                             name="swarmex-display")
        # one robot, one computer: compiled kernels single-threaded. Set in the environment
        # the fork server starts with (asking numba at run time would start its thread pool,
        # whose lock a killed robot leaves behind)
        saved = os.environ.get("NUMBA_NUM_THREADS")
        os.environ["NUMBA_NUM_THREADS"] = "1"
        try:
            display.start()
        finally:
            if saved is None:
                os.environ.pop("NUMBA_NUM_THREADS", None)
            else:
                os.environ["NUMBA_NUM_THREADS"] = saved
        child_end.close()
        procs.append(display)
        for rid in range(params.robots):
            p = mp.Process(target=_robot_entry, name=f"swarmex-robot-{rid}",
                           args=(str(run_dir), rid, str(run_dir / f"robot-{rid}.log")))
            p.start()
            procs.append(p)
        deadline = time.monotonic() + options.timeout + 30
        while time.monotonic() < deadline:
            if lines.poll(0.5):
                try:
                    line = lines.recv()
                except EOFError:
                    break
                if line is None:
                    break
                say(str(line))
            elif not display.is_alive():
                break
        display.join(max(1.0, deadline - time.monotonic()))
        for p in procs[1:]:
            p.join(10)
        path = json_path or record_path
        if not path.exists():
            tails = [(run_dir / f"robot-{r}.log").read_text()[-300:]
                     for r in range(params.robots) if (run_dir / f"robot-{r}.log").exists()]
            raise RuntimeError(f"the display wrote no record (exit {display.exitcode});"
                               f" robot output: {[t for t in tails if t]}")
        import json

        return json.loads(path.read_text())
    finally:
        for p in procs:
            if p.is_alive():
                p.kill()
                p.join(5)
        shutil.rmtree(run_dir, ignore_errors=True)


def main(argv: list[str] | None = None) -> int:
    """``python -m swarmex.net.mesh robot RUN_DIR ID`` / ``display RUN_DIR [--monitor URL]``."""
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) >= 2 and args[0] == "robot":
        import numba

        # (numba's config sets its attributes from the environment: invisible to mypy)
        if numba.config.NUMBA_NUM_THREADS > 1:  # type: ignore[attr-defined]
            numba.set_num_threads(1)  # one robot, one computer
        robot = RobotProcess(Path(args[1]), int(args[2]))
        try:
            return robot.run()
        finally:
            robot.close()
    if len(args) >= 2 and args[0] == "display":
        url = args[args.index("--monitor") + 1] if "--monitor" in args else None
        display = DisplayProcess(Path(args[1]), monitor_url=url)
        try:
            return display.run(lambda s: print(s, flush=True))
        finally:
            display.close()
            display.view.close(1000)
    print("usage: python -m swarmex.net.mesh robot RUN_DIR ID | display RUN_DIR", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
