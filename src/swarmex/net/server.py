"""``swarmex serve``: seed 000's laptop server (§4.1–4.3) on a ZeroMQ ROUTER socket.

What it does, and only that: hands out ids from its vacant list (C00), the mission data
(C22), acknowledges the initialisation and termination commands, starts the mission clock
when every id is armed (``GO``), relays every broadcast to every agent — it never tells an
agent what to do — and watches: it rebuilds each agent's log from the broadcasts, declares
agents that fall silent gone (``LEFT``; their id returns to the vacant list), lets a spare
take a vacant id mid-mission (``JOIN``), publishes monitor events, and when no agent is left
flying writes the result record (the schema of ``swarmex traverse``) and exits.

Why ROUTER and one socket per agent (a DEALER): replies and relays to one agent travel in
order on one connection, so a late joiner's mission log and the live stream that follows it
can never interleave wrongly; relays are never dropped (high-water marks off), because the
protocol (see :mod:`swarmex.net.traversal`) needs every agent to see every step. Bad frames
(checksum, encoding, content, a sender that is not the id it claims) are dropped and
counted, never relayed; a broadcast's moves are checked against where the stream puts its
sender before the relay, since whatever is relayed the recorder must be able to apply.

An agent declared gone is told so (``LEFT`` for its own id) before it is forgotten: one that
was only paused exits (status 5) and brings its vehicle down rather than fly a plan a spare
may have taken. Before the start only an agent still being initialised has the long init
timeout (it compiles kernels, or replays a long log); an armed one is gone after ``--dead-after``,
and ``GO`` waits until every armed holder has been heard lately. The mission stays open
while a spare that is already waiting can take a vacated id.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import zmq

from swarmex.engine.record import write_record
from swarmex.missions.traversal.metrics import agent_metrics, traversal_record
from swarmex.missions.traversal.sim import TraversalRun
from swarmex.net import events as ev
from swarmex.net import wire
from swarmex.net.interrupt import EXIT_INTERRUPTED, StopRequest
from swarmex.net.traversal import (
    LOSSY,
    Loss,
    Mission,
    Recorder,
    Replica,
    check_broadcast,
    check_stats,
)
from swarmex.worlds.mapfiles import source_name

LIVE = ("init", "ready", "mission", "rtl")
#: the longest the server's loop polls its socket at once (seconds): how soon it sees a stop
POLL_SLICE = 0.1
EXIT_OK, EXIT_INCOMPLETE, EXIT_TIMEOUT = 0, 1, 3


@dataclass
class Peer:
    ident: bytes
    id: int = 0
    has_mission: bool = False
    viewer: bool = False
    last_seen: float = 0.0
    frames_in: int = 0
    bytes_in: int = 0
    frames_out: int = 0
    bytes_out: int = 0
    joined_at: float = 0.0
    vehicle: dict | None = None  # C01's description of what this agent flies
    waiting: bool = False  # told "no vacant id": asks again every 0.2 s (a spare waits)


@dataclass
class Counters:
    frames_in: int = 0
    bytes_in: int = 0
    frames_out: int = 0
    bytes_out: int = 0
    relayed: int = 0
    dropped_checksum: int = 0
    dropped_encoding: int = 0
    dropped_content: int = 0
    dropped_sender: int = 0
    refused: int = 0
    errors: int = 0
    left: list[dict] = field(default_factory=list)
    joined: list[dict] = field(default_factory=list)
    handed_back: list[dict] = field(default_factory=list)
    stats_mismatch: int = 0
    stats_received: int = 0
    lag: list[float] = field(default_factory=list)


class TraversalServer:
    """The mission server. ``run()`` returns the process exit status."""

    def __init__(
        self,
        mission: Mission,
        bind: str,
        json_path: Path | None = None,
        timeout: float = 600.0,
        dead_after: float = 2.0,
        init_timeout: float = 60.0,
        spare_wait: float = 0.0,
        monitor_url: str | None = None,
        say: Callable[[str], object] = print,
        loss: float = 0.0,
    ) -> None:
        self.mission = mission
        self.loss = Loss(mission.n_agents, loss, mission.seed)
        self.bind = bind
        self.json_path = json_path
        self.timeout = timeout
        self.dead_after = dead_after
        self.init_timeout = max(init_timeout, dead_after)  # never shorter than an armed one's
        self.spare_wait = spare_wait
        self.say = say
        self.replica = Replica(mission)
        self.recorder = Recorder(mission)
        n = mission.n_agents
        self.state: dict[int, str] = dict.fromkeys(range(1, n + 1), "vacant")
        self.holder: dict[int, bytes] = {}  # id -> ident of the process holding it
        self.vehicles: dict[int, dict] = {}  # id -> what its current holder flies (C01)
        self.peers: dict[bytes, Peer] = {}
        self.log: list[bytes] = []  # every frame relayed since GO, for late joiners
        self.events: list[ev.Event] = []
        self.pending_events: list[ev.Event] = []
        self.counters = Counters()
        self.started = False
        self.t0w = 0.0
        self.now = 0.0  # the time of the frame being handled (a test's own clock)
        self.all_gone_at: float | None = None
        # processes declared gone: told again (LEFT) if they speak, at most once a beat
        self.gone: dict[bytes, tuple[int, float]] = {}
        self.wall0 = 0.0
        self.forwarder = (ev.IngestForwarder(monitor_url, warn=say) if monitor_url
                          else None)
        self.record: dict[str, Any] | None = None
        self.stop = StopRequest()  # Ctrl-C or SIGTERM seen (see run)
        # its own context, terminated after the socket closes: that waits (up to the
        # linger) for the last frames, END among them. A process that just exits would
        # kill ZeroMQ's I/O thread with them still queued (pyzmq does not terminate
        # contexts at interpreter exit), and the agents would wait for their timeout.
        self.ctx: zmq.Context[zmq.Socket[bytes]] = zmq.Context()
        self.sock = self.ctx.socket(zmq.ROUTER)
        self.sock.setsockopt(zmq.LINGER, 500)
        self.sock.setsockopt(zmq.SNDHWM, 0)
        self.sock.setsockopt(zmq.RCVHWM, 0)
        self.sock.bind(bind)
        self.endpoint = self.sock.getsockopt_string(zmq.LAST_ENDPOINT)

    # ------------------------------------------------------------------ clock
    def clock(self) -> float:
        """Mission seconds now (scaled wall time; the latest event time when unscaled)."""
        if not self.started:
            return 0.0
        scale = self.mission.time_scale
        if scale > 0:
            return max(self.replica.last_t, (time.monotonic() - self.t0w) / scale)
        return self.replica.last_t

    # ------------------------------------------------------------------ sending
    def _send(self, peer: Peer, frame: bytes) -> None:
        try:
            self.sock.send_multipart([peer.ident, frame], flags=zmq.NOBLOCK)
        except zmq.ZMQError:
            return
        peer.frames_out += 1
        peer.bytes_out += len(frame)
        self.counters.frames_out += 1
        self.counters.bytes_out += len(frame)

    def _reply(self, peer: Peer, obj: list[Any]) -> None:
        self._send(peer, wire.pack(obj))

    def _to_agents(self, frame: bytes, keep: bool = True) -> None:
        """Relay to every agent that has the mission data (the sender included: its copy is
        the acknowledgement, and its place in the one stream order)."""
        if keep and self.started:
            self.log.append(frame)
        for p in list(self.peers.values()):
            if p.has_mission and p.id and self.holder.get(p.id) == p.ident:
                self._send(p, frame)

    def _relay(self, frame: bytes, b: wire.Broadcast) -> None:
        """:meth:`_to_agents` for a broadcast, where ``--inject-loss`` may lose it for some
        receivers: they get it wrapped in ``LOST`` (their schedule moves, their belief does
        not; see :class:`~swarmex.net.traversal.Loss`). The log for late joiners keeps it."""
        if self.loss.p <= 0 or b.cmd not in LOSSY:
            self._to_agents(frame)
            return
        if self.started:
            self.log.append(frame)
        lost = self.loss.draw(b.id)
        wrapped: bytes | None = None
        for p in list(self.peers.values()):
            if p.has_mission and p.id and self.holder.get(p.id) == p.ident:
                if lost[p.id - 1]:
                    wrapped = wrapped or wire.pack(["LOST", frame])
                    self._send(p, wrapped)
                else:
                    self._send(p, frame)

    def _emit(self, *events: ev.Event) -> None:
        self.pending_events.extend(events)

    def _flush_events(self) -> None:
        if not self.pending_events:
            return
        batch, self.pending_events = self.pending_events, []
        self.events.extend(batch)
        text = ev.dumps(batch)
        for p in list(self.peers.values()):
            if p.viewer:
                self._reply(p, ["EV", text])
        if self.forwarder is not None:
            self.forwarder.send(batch)

    # ------------------------------------------------------------------ run
    def run(self) -> int:
        """Serve the mission to its end. Ctrl-C or SIGTERM (:class:`StopRequest`) ends it as
        a timeout does: the record of what was done so far is written and the agents get
        ``END`` (they exit at once instead of waiting for ``--server-timeout``)."""
        with StopRequest() as self.stop:
            return self._run()

    def _run(self) -> int:
        self.wall0 = time.monotonic()
        deadline = self.wall0 + self.timeout
        hb = self.mission.heartbeat
        next_hb = self.wall0
        self.say(f"swarmex serve: listening on {self.endpoint} for {self.mission.n_agents} agents")
        try:
            while True:
                now = time.monotonic()
                if self.stop.seen:
                    self.say(f"swarmex serve: interrupted ({self.stop.how}), ending the mission")
                    self._finish(EXIT_INTERRUPTED)
                    return EXIT_INTERRUPTED
                if now >= deadline:
                    self.say("swarmex serve: timeout, the mission did not end")
                    self._finish(EXIT_TIMEOUT)
                    return EXIT_TIMEOUT
                # short slices: a stop request (Ctrl-C) is seen within POLL_SLICE even with
                # a long --heartbeat (one poll of a whole 8 s beat made Ctrl-C wait 7.6 s)
                if self.sock.poll(int(max(1, min(hb, next_hb - now, POLL_SLICE) * 1000))):
                    for _ in range(10_000):  # drain, but keep the heartbeat going
                        try:
                            ident, frame = self.sock.recv_multipart(flags=zmq.NOBLOCK)[:2]
                        except (zmq.Again, ValueError):
                            break
                        self._on_frame(ident, frame, time.monotonic())
                now = time.monotonic()
                self._check_liveness(now)
                if now >= next_hb:
                    next_hb = now + hb
                    beat = wire.pack(["HB", float(self.clock())])
                    for p in list(self.peers.values()):
                        if p.id or p.viewer:
                            self._send(p, beat)
                    self._drop_silent_viewers(now)
                if not self.started:
                    self._maybe_go(now)  # a late beat may have held GO back
                self._flush_events()
                code = self._end_code(now)
                if code is not None:
                    self._finish(code)
                    return code
        finally:
            if self.forwarder is not None:
                self.forwarder.close()
                if (short := self.forwarder.shortfall()) is not None:
                    self.say(f"swarmex serve: {short}")
            self.sock.close(500)
            self.ctx.term()

    def _end_code(self, now: float) -> int | None:
        """The exit status once the mission is over (no id live since the start), else None.
        Incomplete, it still waits ``--spare-wait`` for a spare to come, and as long as a
        spare already waiting can take a vacated id: it asks every 0.2 s, so the end used
        to come first — in the very pass that declared the last agent gone — and the spare
        heard END ("without needing a spare") with the mission unfinished."""
        if not self.started or any(s in LIVE for s in self.state.values()):
            self.all_gone_at = None
            return None
        if self.all_gone_at is None:
            self.all_gone_at = now
        if bool(np.all(self.recorder.job_count[self.recorder.reachable()] >= 1)):
            return EXIT_OK
        if "left" in self.state.values() and self._spare_waiting(now):
            return None
        return EXIT_INCOMPLETE if now - self.all_gone_at >= self.spare_wait else None

    def _spare_waiting(self, now: float) -> bool:
        """Whether a process told "no vacant id" still asks (within a second or
        ``--dead-after``): it takes a vacated id at its next C00."""
        patience = max(self.dead_after, 1.0)
        return any(p.waiting and not p.id and now - p.last_seen <= patience
                   for p in self.peers.values())

    # ------------------------------------------------------------------ frames
    def _on_frame(self, ident: bytes, frame: bytes, now: float) -> None:
        c = self.counters
        c.frames_in += 1
        c.bytes_in += len(frame)
        self.now = now
        peer = self.peers.get(ident)
        if peer is None:
            peer = self.peers[ident] = Peer(ident, joined_at=now)
        gone = self.gone.get(ident)
        if gone is not None and peer.id == 0 and now - gone[1] >= self.mission.heartbeat:
            # a process declared gone still talks (it was paused, or LEFT was lost): tell
            # it again, at most once a heartbeat, so it stops flying a plan a spare may
            # have taken (checked on every frame: its ghost peer stays known after the first)
            self.gone[ident] = (gone[0], now)
            self._reply(peer, ["LEFT", gone[0], float(self.clock())])
        peer.last_seen = now
        peer.frames_in += 1
        peer.bytes_in += len(frame)
        try:
            msg = wire.message(wire.unpack(frame))
        except wire.ChecksumError:
            c.dropped_checksum += 1
            return
        except wire.WireError:
            c.dropped_encoding += 1
            return
        cmd = msg[0]
        try:
            if cmd in wire.BROADCAST_COMMANDS:
                self._on_broadcast(peer, frame, msg)
            else:
                self._on_control(peer, wire.check_control(msg))
        except wire.WireError:
            c.dropped_encoding += 1
        except (KeyError, IndexError, ValueError, TypeError, ArithmeticError) as exc:
            # a frame the checks let through but the server could not apply: a bug, but
            # one frame must never end the mission without its record (a C05 to a node
            # that is not adjacent did, before the move checks). Dropped, counted, said.
            c.dropped_content += 1
            self.say(f"swarmex serve: dropped a {cmd} frame it could not apply "
                     f"({type(exc).__name__}: {exc})")

    def _on_control(self, peer: Peer, msg: list[Any]) -> None:
        cmd = msg[0]
        if cmd == "MON":
            if not peer.viewer:
                peer.viewer = True
                text = ev.dumps(self.events) if self.events else None
                if text:
                    self._reply(peer, ["EV", text])
            return
        if cmd == "HB":
            return
        if cmd == "C00":
            self._on_c00(peer, int(msg[1]))
            return
        if cmd == "C22":
            self._on_c22(peer, int(msg[1]))
            return
        if not peer.id or not peer.has_mission or self.holder.get(peer.id) != peer.ident:
            # seed 000 §4.2: any other command before C22 is an error for this client
            self.counters.errors += 1
            self._reply(peer, ["ERR", f"{cmd} before C22"])
            return
        a = peer.id
        if cmd == "C01":
            if int(msg[1]) != a:
                self.counters.dropped_sender += 1
                return
            peer.vehicle = dict(msg[3]) if len(msg) > 3 else {"kind": "simulated"}
            self.vehicles[a] = peer.vehicle
            self._reply(peer, ["ACK", "C01", a])
            self._to_agents(wire.pack(msg), keep=False)
        elif cmd == "C02":
            self._reply(peer, ["ACK", "C02", a])
        elif cmd == "C03":
            self._reply(peer, ["ACK", "C03", a])
            self._on_armed(a)
        elif cmd == "ST":
            self._on_stats(peer, msg[2])
        elif cmd == "RET":
            if int(msg[1]) != a:
                self.counters.dropped_sender += 1
                return
            self._reply(peer, ["ACK", "RET", a])
            self._on_handback(peer, a, str(msg[2]))
        else:
            self.counters.errors += 1
            self._reply(peer, ["ERR", f"unexpected {cmd}"])

    def _on_c00(self, peer: Peer, want: int) -> None:
        n = self.mission.n_agents
        if peer.id and self.holder.get(peer.id) == peer.ident:
            self._reply(peer, ["ID", peer.id])  # a repeated C00: same answer
            return
        if want > 0:
            if not 1 <= want <= n:
                self._refuse(peer, f"unknown id {want} (this mission has ids 1..{n})")
                return
            holder = self.peers.get(self.holder.get(want, b""))
            if (self.state[want] in LIVE and holder is not None and holder is not peer
                    and self.now - holder.last_seen > self.dead_after):
                # its holder's beats stopped (a process killed and restarted with the same
                # --id): it is gone already, whatever its state's own limit says
                self._declare_left(want, holder, "fell silent (a new agent asks for its id)")
            if self.state[want] in LIVE or self.state[want] == "done":
                self._refuse(peer, f"id {want} is taken")
                return
            chosen = want
        else:  # 0: any vacant id; -1: a spare, only an id vacated during the mission
            free = ("left",) if want < 0 else ("vacant", "left")
            vacant = [i for i, s in self.state.items() if s in free]
            if not vacant:
                self._refuse(peer, "no vacant id")
                return
            chosen = vacant[0]
        peer.id = chosen
        peer.waiting = False
        self.holder[chosen] = peer.ident
        self.state[chosen] = "init"
        self._reply(peer, ["ID", chosen])
        self.say(f"swarmex serve: id {chosen} given to a new agent")

    def _refuse(self, peer: Peer, reason: str) -> None:
        self.counters.refused += 1
        self._reply(peer, ["REF", reason])
        peer.id = 0
        peer.has_mission = False
        peer.waiting = reason == "no vacant id"

    def _on_c22(self, peer: Peer, agent: int) -> None:
        if not agent or peer.id != agent or self.holder.get(agent) != peer.ident:
            # an id this connection was not given: possibly an intruder (§4.2); cut it off
            self._refuse(peer, f"unknown id {agent}")
            self.peers.pop(peer.ident, None)
            return
        data = self.mission.to_wire()
        data["you"] = agent
        data["started"] = self.started
        data["clock"] = float(self.clock())
        peer.has_mission = True
        self._reply(peer, ["MIS", data, list(self.log) if self.started else []])

    def _on_armed(self, agent: int) -> None:
        if not self.started:
            self.state[agent] = "ready"
            self._maybe_go(self.now)
            return
        # a spare: it starts after every event still to run, plus its takeoff
        spec = self.mission.specs[agent - 1]
        t = max(self.clock(), self.replica.min_time()) + spec.takeoff_time
        seq = self.replica.counter
        self.replica.on_join(agent, t, seq)
        self.recorder.on_join(agent)
        self.recorder.incarnation(agent).vehicle = self.vehicles.get(agent)
        self.state[agent] = "mission"
        self.counters.joined.append({"id": agent, "t": t})
        self._to_agents(wire.pack(["JOIN", agent, float(t), seq]))
        kind = (self.vehicles.get(agent) or {}).get("kind", "simulated")
        self._emit(ev.message(self.replica.last_t, agent, "join", *self._xy(spec.nest),
                              extra={"vehicle": kind}))
        self.say(f"swarmex serve: a spare took id {agent} ({kind}), starting at t={t:.2f}")

    def _maybe_go(self, now: float) -> None:
        """GO once every id is armed *and* its holder has been heard lately (within two
        beats, or half ``--dead-after`` if longer): an armed agent that died kept counting
        as ready, and the mission started with everybody waiting at its start event."""
        if not all(s == "ready" for s in self.state.values()):
            return
        fresh = min(self.dead_after, max(2 * self.mission.heartbeat, self.dead_after / 2))
        for a in self.state:
            peer = self.peers.get(self.holder.get(a, b""))
            if peer is None or now - peer.last_seen > fresh:
                return  # checked again every pass of the loop
        self._go()

    def _go(self) -> None:
        self.started = True
        self.t0w = time.monotonic()
        for a in self.state:
            self.state[a] = "mission"
            self.recorder.incarnation(a).vehicle = self.vehicles.get(a)
        m = self.mission
        w = m.world
        kinds = [(self.vehicles.get(a) or {}).get("kind", "simulated") for a in self.state]
        mix = ", ".join(f"{kinds.count(k)} {k}" for k in sorted(set(kinds)))
        self._emit(  # live: no replay speed (the monitor's schema says null)
            ev.hello("traversal", m.algorithm, list(self.state), f"traversal · {m.algorithm} · "
                     f"{source_name(w.source)} · network · {mix}", None,
                     vehicles=[{"id": a, **(self.vehicles.get(a) or {"kind": "simulated"})}
                               for a in self.state]),
            ev.world(w.free, w.width, w.height, w.source),
        )
        self._to_agents(wire.pack(["GO", 0.0]))
        self.say(f"swarmex serve: all agents armed ({mix}), mission started")

    def _xy(self, node: int) -> tuple[float, float]:
        x, y = self.mission.world.graph.pos[node]
        return float(x), float(y)

    def _on_broadcast(self, peer: Peer, frame: bytes, msg: list[Any]) -> None:
        b = wire.Broadcast.from_wire(msg)
        a = b.id
        if (not peer.has_mission or peer.id != a or self.holder.get(a) != peer.ident
                or self.state.get(a) not in ("mission", "rtl") or not self.started):
            self.counters.dropped_sender += 1
            return
        try:  # everything the recorder needs, checked before anything is relayed
            check_broadcast(b, self.mission, here=self.recorder.position(a))
            if b.cmd == "C08" and self.replica.open_job.get(a) != b.node:
                raise wire.EncodingError(f"C08: agent {a} has no job at node {b.node}")
        except wire.WireError:
            self.counters.dropped_content += 1
            return
        self.counters.relayed += 1
        self._relay(frame, b)
        prev = self.recorder.incarnation(a).log.trajectory
        arrival = b.cmd == "C04" or (b.cmd == "C07" and (not prev or prev[-1][1] != b.node))
        self.replica.on_broadcast(b)
        self.recorder.on_broadcast(b, len(frame))
        self._events_for(b, arrival)
        if b.cmd == "C09":
            self.state[a] = "rtl"

    def _events_for(self, b: wire.Broadcast, arrival: bool) -> None:
        x, y = self._xy(b.node) if b.node >= 0 else (None, None)
        t = b.t
        # a move or job event needs a place (a C04/C07 at node -1 passes the wire checks,
        # but "x": null breaks the monitor's schema and ``swarmex watch``)
        if x is not None and y is not None:
            if arrival:
                self._emit(ev.move(t, b.id, x, y))
            if b.cmd == "C07" and b.job:
                self._emit(ev.job(t, b.id, x, y))
        kind = {
            "C04": "pos", "C05": "next", "C06": "halfway", "C09": "finish", "C10": "home",
            "C11": "landed",
        }.get(b.cmd)
        if b.cmd == "C07":
            kind = "job" if b.job else "pos"
        elif b.cmd == "C08":
            kind = "done" if b.job else "undone"
        if kind is not None and b.cmd not in ("C06", "C10", "C11"):
            self._emit(ev.message(max(t, 0.0), b.id, kind, x, y))

    def _vehicle_entry(self, agent: int, inc: Any) -> dict[str, Any]:
        """What id ``agent``'s last holder flew, and for a real vehicle the charge it landed
        with (its statistics' ``battery``): the field day's one number about the airframe."""
        entry = {"id": agent,
                 **(inc.vehicle or self.vehicles.get(agent) or {"kind": "simulated"})}
        battery = (inc.stats or {}).get("battery")
        if (entry.get("kind") != "simulated" and isinstance(battery, int | float)
                and not isinstance(battery, bool) and math.isfinite(battery)):
            entry["battery_end"] = float(battery)
        return entry

    def _on_stats(self, peer: Peer, stats: Any) -> None:
        a = peer.id
        inc = self.recorder.incarnation(a)
        inc.stats = stats if isinstance(stats, dict) else None
        self.counters.stats_received += 1
        if not check_stats(stats, inc.log):
            self.counters.stats_mismatch += 1
        if isinstance(stats, dict) and isinstance(stats.get("lag"), list):
            self.counters.lag.extend(
                float(v) for v in stats["lag"][:100_000]
                if isinstance(v, int | float) and math.isfinite(v)
            )
        self.state[a] = "done"
        self._reply(peer, ["ACK", "ST", a])
        self.say(f"swarmex serve: agent {a} landed and sent its statistics")

    # ------------------------------------------------------------------ faults
    def _check_liveness(self, now: float) -> None:
        for a, s in list(self.state.items()):
            if s not in LIVE:
                continue
            peer = self.peers.get(self.holder.get(a, b""))
            # before the start an agent may be silent longer: one being initialised may
            # be busy (a late joiner replays the log; kernels compile, on a thread that
            # lets it beat), and an armed one that stalls (a loaded machine, a paused
            # process) must not cost the whole run: declared gone before GO, nobody takes
            # its id and the server waits out --timeout. A dead armed
            # agent is still handled at once where it matters: GO waits for every holder
            # to have been heard lately (_maybe_go), and a restart asking for the id of a
            # holder silent for --dead-after takes it over (_on_c00)
            limit = self.init_timeout if s in ("init", "ready") else self.dead_after
            if peer is None or now - peer.last_seen > limit:
                why = "fell silent"
                if s == "init":  # the usual cause, and what to do about it
                    why = (f"fell silent for --init-timeout ({limit:g} s) while initialising"
                           " (a first start compiles kernels: raise --init-timeout on a slow"
                           " or loaded machine)")
                self._declare_left(a, peer, why)

    def _on_handback(self, peer: Peer, agent: int, reason: str) -> None:
        """The agent hands its id back (seed 000 §4.3: "if an agent stops its work
        preliminary, because of some error, including a low battery level, its ID is entered
        back to a list of vacant IDs"): before the start, the id is open to a spare (and to
        any new agent) and the mission waits for one; during it, as a departure."""
        self.counters.handed_back.append({
            "id": agent, "t": self.clock(), "state": self.state[agent], "reason": reason,
            "vehicle": peer.vehicle,
        })
        if self.started:
            self._declare_left(agent, peer, f"handed its id back ({reason})", reason)
            return
        self.state[agent] = "left"
        self.holder.pop(agent, None)
        self.vehicles.pop(agent, None)
        peer.id = 0
        peer.has_mission = False
        self.say(f"swarmex serve: agent {agent} handed its id back before the start ({reason});"
                 f" waiting for a spare to take id {agent}")

    def _declare_left(self, agent: int, peer: Peer | None, why: str = "fell silent",
                      reason: str = "silent") -> None:
        was = self.state[agent]
        # "left" before the start too: open to a spare, as an id handed back is (a silent
        # one used to become "vacant", which a --spare may not take)
        self.state[agent] = "left"
        left = wire.pack(["LEFT", agent, float(self.clock())])
        if peer is not None:
            # tell the process first, then forget it: it exits at once ("declared gone",
            # status 5) instead of flying on, its frames dropped, until its server timeout
            if peer.id == agent and self.holder.get(agent) == peer.ident:
                self._send(peer, left)
            self.gone[peer.ident] = (agent, self.now)
            self.peers.pop(peer.ident, None)
        self.holder.pop(agent, None)
        if not self.started:
            self.say(f"swarmex serve: agent {agent} {why} before the start; id {agent} is "
                     "open to a spare or a new agent")
            return
        t = self.replica.last_t
        node = self.replica.on_left(agent)
        self.recorder.on_left(agent, self.clock(), node)
        self.counters.left.append({"id": agent, "t": self.clock(), "state": was,
                                   "open_job": node, "reason": reason})
        self._to_agents(left)
        # the node whose job reverts to not done, for the page to un-paint
        x, y = self._xy(node) if node >= 0 else (None, None)
        self._emit(ev.message(t, agent, "left", x, y, extra={"reason": reason}))
        self.say(f"swarmex serve: agent {agent} {why} ({was}); id {agent} is vacant"
                 + (f", node {self.mission.world.label(node)} is not done again" if node >= 0
                    else ""))

    def _drop_silent_viewers(self, now: float) -> None:
        for ident, p in list(self.peers.items()):
            if p.viewer and not p.id and now - p.last_seen > 10.0:
                del self.peers[ident]

    # ------------------------------------------------------------------ the end
    def _finish(self, code: int) -> None:
        record = self.build_record()
        self.record = record
        self._emit(ev.end(record, self.events + self.pending_events))
        self._flush_events()
        self._to_agents(wire.pack(["END"]), keep=False)
        end = wire.pack(["END"])
        for p in list(self.peers.values()):  # spares still waiting for an id: nothing to do
            if not p.id and not p.viewer:
                self._send(p, end)
        if self.json_path is not None:
            write_record(self._record_obj, self.json_path)
            self.say(f"swarmex serve: wrote {self.json_path}")
        self.say(
            f"swarmex serve: mission {'complete' if record['complete'] else 'incomplete'},"
            f" makespan {record['makespan']:.2f} s, {self.counters.relayed} broadcasts relayed,"
            f" {self._dropped()} bad frames dropped"
        )

    def _dropped(self) -> int:
        c = self.counters
        return c.dropped_checksum + c.dropped_encoding + c.dropped_content + c.dropped_sender

    def build_record(self) -> dict[str, Any]:
        m = self.mission
        rec = self.recorder
        for a in range(1, m.n_agents + 1):
            rec.incarnation(a)
        ids = list(range(1, m.n_agents + 1))
        logs = [rec.current[a].log for a in ids]
        run = TraversalRun(
            world=m.world,
            agents=logs,
            done_by=rec.done_by,
            job_count=rec.job_count,
            reachable=rec.reachable(),
            algorithm=m.algorithm,
            seed=m.seed,
            messages=rec.messages,
            message_bytes=rec.message_bytes,
            wall_seconds=time.monotonic() - self.wall0,
        )
        record = traversal_record(run, m.params, m.unit_length)
        for entry, a in zip(record.agents, ids, strict=True):
            inc = rec.current[a]
            if inc.left_at is not None:
                entry.metrics["left_at"] = inc.left_at
                entry.metrics["abandoned_jobs"] = len(inc.abandoned_jobs)
        departed = []
        pos = m.world.graph.pos
        for inc in rec.departed:
            met = agent_metrics(inc.log, m.unit_length)
            met["left_at"] = inc.left_at
            met["abandoned_jobs"] = len(inc.abandoned_jobs)
            departed.append({
                "id": inc.log.id,
                "vehicle": inc.vehicle or {"kind": "simulated"},
                "metrics": met,
                "trajectory": [[t, *pos[v].tolist()] for t, v in inc.log.trajectory],
                "jobs": [[t, *pos[v].tolist()] for t, v in inc.log.jobs],
            })
        record.extra["departed_agents"] = departed
        # what each id's last holder flew: a hybrid mission's record tells them apart
        record.extra["vehicles"] = [self._vehicle_entry(a, rec.current[a]) for a in ids]
        record.extra["network"] = self.network_metrics(run.wall_seconds)
        self._record_obj = record
        return record.to_dict()

    def network_metrics(self, wall: float) -> dict[str, Any]:
        c = self.counters
        mission_wall = (time.monotonic() - self.t0w) if self.started else 0.0
        per_agent = []
        for p in self.peers.values():
            if p.id:
                per_agent.append({"id": p.id, "frames_in": p.frames_in, "bytes_in": p.bytes_in,
                                  "frames_out": p.frames_out, "bytes_out": p.bytes_out,
                                  "vehicle": (p.vehicle or {}).get("kind")})
        lag = np.asarray(c.lag) if c.lag else np.zeros(0)
        return {
            "transport": "zeromq",
            "endpoint": self.endpoint,
            "time_scale": self.mission.time_scale,
            "rng_mode": self.mission.rng_mode,
            "mission_wall_seconds": mission_wall,
            "frames_in": c.frames_in,
            "bytes_in": c.bytes_in,
            "frames_out": c.frames_out,
            "bytes_out": c.bytes_out,
            "broadcasts_relayed": c.relayed,
            "inject_loss": self.loss.p,
            "lost_deliveries": self.loss.lost,
            "dropped_checksum": c.dropped_checksum,
            "dropped_encoding": c.dropped_encoding,
            "dropped_content": c.dropped_content,
            "dropped_sender": c.dropped_sender,
            "refused": c.refused,
            "errors": c.errors,
            "left": c.left,
            "joined": c.joined,
            "handed_back": c.handed_back,
            "stats_received": c.stats_received,
            "stats_mismatch": c.stats_mismatch,
            "lag_max": float(lag.max()) if lag.size else None,
            "lag_mean": float(lag.mean()) if lag.size else None,
            "peers": sorted(per_agent, key=lambda d: d["id"]),
        }

