"""The display process of the mesh: a router that explores nothing, watches and records.

Thesis §3.2: "the router, but it does not carry out the exploration". It joins the radio
(heartbeats, relays floods, routes AODV unicasts, asks new neighbours for their maps and keeps
its own map), runs the experiment on the control link (start barrier, GO, liveness from
STATUS, STOP, the robots' REPORTs), serves live monitor events and writes the result record
(assembled by :mod:`swarmex.net.mesh_record`).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import zmq

from swarmex.comm.aodv import AodvMessage, Routed
from swarmex.comm.message import PackedMessage
from swarmex.net import events as ev
from swarmex.net import wire
from swarmex.net.interrupt import EXIT_INTERRUPTED, StopRequest
from swarmex.net.mesh_frames import (
    DISPLAY,
    RADIO_KIND,
    control_message,
    encode_radio,
    radio_message,
    report_fields,
    status_fields,
)
from swarmex.net.mesh_node import Node
from swarmex.net.mesh_record import build_record
from swarmex.net.mesh_scenario import read_scenario
from swarmex.net.routing import ROUTED_PAYLOADS, wants_feedback
from swarmex.worlds.mapfiles import source_name

if TYPE_CHECKING:  # imported where used: each process loads only what it needs
    from swarmex.missions.exploration.messages import Message

BEAT_WALL = 0.5  # the display's keep-alive on the control link
#: the display's status when an error of its own ended the run (the record is still written)
EXIT_DISPLAY_ERROR = 4
#: what a frame's handling may raise past the checks (a bug's usual suspects): the frame is
#: dropped and counted rather than the display killed with the run's record
FRAME_ERRORS = (KeyError, TypeError, ValueError, OverflowError, IndexError, AttributeError)


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
        self.say: Callable[[str], object] = print  # run() sets the launcher's
        # the forwarder's thread leaves its warnings here; the loop says them (the launcher's
        # pipe is not to be written from two threads)
        self.warnings: list[str] = []
        self.forwarder = (ev.IngestForwarder(monitor_url, warn=self.warnings.append)
                          if monitor_url else None)
        self.record: dict[str, Any] | None = None
        self.frame_error_said = False

    # ---- radio
    def on_radio(self, obj: list[Any]) -> None:
        from swarmex.missions.exploration.messages import Heartbeat, NeedMap

        try:
            src, where, msg = radio_message(obj, self.grid.shape)
        except wire.WireError:
            self.traffic.bad_frames += 1
            return
        if not self.admitted(obj, src, self.cell, where, self.grid.cell, self.params.comm_range):
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
        self.transmit((dst,), msg, encode_radio(DISPLAY, self.cell, msg))

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

        beat = Heartbeat(DISPLAY, *self.cell)
        self.broadcast(beat, encode_radio(DISPLAY, self.cell, beat))
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
        """A robot's HELLO, STATUS or REPORT (shape-checked by :func:`control_message`).

        Every field of a STATUS or REPORT is checked (:func:`status_fields`,
        :func:`report_fields`) before anything changes: a bad one raises WireError, which
        the caller drops and counts, and it does not count as a sign of life either."""
        cmd, rid = obj[0], int(obj[1])
        if rid >= self.params.robots:
            raise wire.EncodingError(f"{cmd}: no robot {rid}")
        status = status_fields(obj[2], self.grid.shape) if cmd == "STATUS" else None
        report = report_fields(obj[2], self.grid.shape) if cmd == "REPORT" else None
        info = self.robots.setdefault(rid, {"seen": now, "finished": False, "t": 0,
                                            "pos": tuple(self.starts[rid]),
                                            "trajectory": [], "goal": None,
                                            "alive": True})
        info["seen"] = now
        if cmd == "HELLO":
            self.air[rid] = str(obj[2])
        elif status is not None:
            info["t"], info["finished"], info["stopped"], info["pos"], moves = status
            info["trajectory"].extend(moves)
            for t, x, y in moves:
                self._emit(ev.move(float(t), rid, float(x), float(y)))
        elif report is not None:
            self.reports[rid] = report

    def broadcast_control(self, obj: list[Any]) -> None:
        for rid in sorted(self.robots):
            self.send_control(rid, obj)

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
        self.say = say
        opts = self.options
        n = self.params.robots
        say(f"swarmex mesh display: view on {self.view_endpoint}, waiting for {n} robots")
        start = time.monotonic()
        deadline = start + opts.timeout
        w = self.grid.world
        self._emit(
            ev.hello("exploration", self.params.strategy, list(range(n)),
                     f"exploration · {self.params.strategy} · {source_name(w.source)} · processes",
                     None, "step", messages="totals"),
            ev.world(w.free, w.width, w.height, w.source),
        )
        # SIGTERM: the launcher's request (it got Ctrl-C or SIGTERM), or a group's
        with StopRequest(also_sigterm=True) as stop:
            # start barrier: every robot said HELLO (or the start timeout passed)
            while (len(self.robots) < n and time.monotonic() - start < opts.start_timeout
                   and not stop.seen):
                self._pump(time.monotonic())
            self.broadcast_control(["GO"])
            say(f"swarmex mesh display: {len(self.robots)} robots started")
            self.t0 = t0 = time.monotonic()
            try:
                code = self._explore(say, stop, deadline)
            except Exception as exc:  # a bug: stop the robots, keep the record so far
                say(f"swarmex mesh display: internal error ({type(exc).__name__}: "
                    f"{exc!s:.80}); stopping the robots")
                code = EXIT_DISPLAY_ERROR
            # stop everyone and collect the reports, still within the stop request: after a
            # group SIGTERM the launcher's own follows, and the default SIGTERM (restored
            # at the end of the block) killed the display before it wrote the record of the
            # run so far, now and then
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
                self._say_warnings()
                if (short := self.forwarder.shortfall()) is not None:
                    say(f"swarmex mesh display: {short}")
        return code

    def _explore(self, say: Callable[[str], object], stop: StopRequest, deadline: float) -> int:
        """The run from GO until every live robot has finished (0), none is left (1), the
        timeout (3) or a stop request (:data:`EXIT_INTERRUPTED`)."""
        opts = self.options
        t0 = self.t0
        tick_wall = 0.1 * opts.time_scale
        finished_since: float | None = None
        next_tick = t0
        next_beat = t0
        while True:
            now = time.monotonic()
            if stop.seen:
                say(f"swarmex mesh display: interrupted ({stop.how}), stopping the robots")
                return EXIT_INTERRUPTED
            if now > deadline:
                say("swarmex mesh display: timeout")
                return 3
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
                    return 0
            else:
                finished_since = None
            if not live and self.robots:
                say("swarmex mesh display: no robot left")
                return 1
            self._pump(now, max(0.0, next_tick - time.monotonic()))

    def _say_warnings(self) -> None:
        while self.warnings:
            self.say(self.warnings.pop(0))

    def _pump(self, now: float, wait: float = 0.05) -> None:
        self._say_warnings()
        self._flush()
        if self.pull.poll(int(min(wait, 0.05) * 1000)):
            for frame in self.recv_all():
                try:
                    self._on_frame(frame, now)
                except FRAME_ERRORS as exc:
                    # a frame the checks let through and the handling still choked on (a
                    # bug): dropped and counted like a bad frame, said once, the run goes on
                    self.traffic.bad_frames += 1
                    if not self.frame_error_said:
                        self.frame_error_said = True
                        self.say(f"swarmex mesh display: dropped a frame that raised "
                                 f"{type(exc).__name__}: {exc!s:.80} (counted as bad)")

    def _on_frame(self, frame: bytes, now: float) -> None:
        """One frame from the PULL socket: a radio frame or a control frame; a malformed
        one is dropped and counted."""
        try:
            obj = wire.unpack(frame)
            if isinstance(obj, list) and obj and obj[0] == RADIO_KIND:
                self.on_radio(obj)
                return
            obj = control_message(obj)
            if obj[0] == "NACK":  # a unicast of ours was out of the receiver's range
                msg = self.link.refused(int(obj[1]), int(obj[2]))
                if msg is not None and self.aodv is not None:
                    self._failed(int(obj[1]), msg)
            elif obj[0] in ("HELLO", "STATUS", "REPORT"):
                self.on_control(obj, now)
        except wire.WireError:
            self.traffic.bad_frames += 1

    def build_record(self, wall: float, ended: bool) -> dict[str, Any]:
        """The run's result record (:func:`swarmex.net.mesh_record.build_record`)."""
        return build_record(self, wall, ended)
