"""``swarmex agent``: one traversal UAV as a network client (seed 000's ``client.py``).

An :class:`AgentClient` is one agent with its own DEALER socket: it asks the server for an
id (C00; a given ``--id`` is "a concrete id for a real UAV"), the mission data (C22), sends
C01–C03 (new rival, pre-arm checks, armed) each acknowledged, waits for the mission clock
(``GO``), runs MADGTA through :class:`~swarmex.net.traversal.AgentCore` in scaled real time
(C04 at the nest, C05 next node, C06 halfway, C07 at the node / job started, C08 job done),
then the termination stage (C09 return to launch, C10 home, C11 landed) and uploads its
statistics. See :mod:`swarmex.net.traversal` for when an event may run. Between the mission
data and C01 the algorithm's kernels compile on a thread (:func:`warm_in_background`; state
``compiling``) while the agent keeps beating; frames that arrive meanwhile are read after.

Several agents can share one process (``--count``): each keeps its own socket and state and
they share a poller, which saves the interpreter start-up of a process per UAV in tests and
benchmarks; the protocol cannot tell.

What the agent flies is a :class:`~swarmex.net.vehicle.Vehicle`: the simulated one (every
command done at once: the computed mission times are its flight, exactly as before vehicles
existed) or a MAVLink copter (``--vehicle``). The agent drives it through the seed's stages:
pre-arm checks before C02, arming before C03, take-off before its start event (C04), a flight
to each node before the arrival event runs (C07), the job before the job's end (C08), return
to launch and landing before C10 and C11. An event runs when the protocol says it may *and*
the vehicle is there: mission times stay the computed ones, a slow vehicle only adds lag. A
failed pre-arm check or arming, a failed flight command, a lost vehicle link or a battery
below ``--min-battery`` make the agent hand its id back to the server (``RET``; seed 000
§4.3: the id returns to the vacant list and a spare can take it) and bring the vehicle down.

The server ending the mission (``END``) or declaring this agent gone (``LEFT`` for its id)
ends it the way a silent server does (:meth:`AgentClient.leave`): a vehicle still flying is
brought down first. How long a server may be silent follows the mission's heartbeat too.

Every receive has a timeout. Exit status: 0 landed and statistics acknowledged (or the
mission ended), 1 the mission ended before this agent finished, 3 the server went silent,
4 refused (unknown id, or no vacant id, or a fixed ``--id`` still taken, before
``--connect-timeout``; a spare the server has
answered waits for the whole mission instead), 5 the server declared
this agent gone, 6 its vehicle failed (no heartbeat, a failed check, a low battery, a lost
link; an id it held was handed back).
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import zmq

from swarmex.errors import InputError
from swarmex.net import wire
from swarmex.net.interrupt import EXIT_INTERRUPTED, StopRequest
from swarmex.net.traversal import (
    AgentCore,
    Mission,
    Replica,
    catch_up,
    check_broadcast,
    ends_step,
    has_own_kernels,
    warm_policy,
    warm_up,
)
from swarmex.net.vehicle import (
    FlightPlan,
    Safety,
    SimulatedVehicle,
    Task,
    Vehicle,
    parse_link,
)

EXIT_OK, EXIT_UNFINISHED, EXIT_SERVER_GONE, EXIT_REFUSED, EXIT_DECLARED_GONE = 0, 1, 3, 4, 5
EXIT_HANDED_BACK = 6

#: the algorithms whose kernels this process compiles (or has compiled) off the main thread
_WARMING: dict[str, Future[None]] = {}


def warm_in_background(algorithm: str) -> Future[None]:
    """``warm_policy(algorithm)`` on a thread of its own, once per process (agents sharing
    a process share it). Why a thread: on a cold cache an algorithm's kernels compile for
    7-20 s of CPU (madgta-r, madgta-s) after the agent has its id, and an agent compiling
    on its main thread sent no heartbeat, so only the server's long init timeout kept its
    id. numba's compiler is mostly Python and its LLVM calls go through ctypes, which lets
    go of the GIL: measured on a cold cache, the main thread waited at most 0.28 s between
    two 50 ms sleeps during a 19 s compile of madgta-s. A daemon thread, so Ctrl-C during a
    compile does not wait for it."""
    job = _WARMING.get(algorithm)
    if job is None:
        job = _WARMING[algorithm] = Future()
        if not has_own_kernels(algorithm):  # nothing to wait a tick for
            job.set_result(None)
            return job

        def compile_kernels() -> None:
            try:
                warm_policy(algorithm)
            except BaseException as exc:  # handed to the agent's loop, which re-raises it
                job.set_exception(exc)
            else:
                job.set_result(None)

        threading.Thread(target=compile_kernels, name=f"warm {algorithm}", daemon=True).start()
    return job


#: states in which the vehicle is being readied or flown (its faults count)
VEHICLE_STATES = ("prearm", "c02", "arming", "c03", "ready", "mission", "rtl", "landing")


@dataclass
class Faults:
    """Fault injection for tests: damaged frames beside the real ones, and a sudden death."""

    corrupt: float = 0.0  # probability that a bad copy precedes a frame
    die_after: int | None = None  # exit abruptly (no goodbye) after this many events
    seed: int = 0
    rng: np.random.Generator = field(init=False)

    def __post_init__(self) -> None:
        # numpy's generators take only seeds >= 0 (-1 was a ValueError traceback from
        # default_rng). No upper bound: this seed stays in the process, never on the wire
        if self.seed < 0:
            raise InputError(f"--fault-seed must be at least 0, got {self.seed}")
        self.rng = np.random.default_rng(self.seed)


class AgentClient:
    def __init__(
        self,
        ctx: zmq.Context,
        address: str,
        want_id: int = 0,
        server_timeout: float = 10.0,
        connect_timeout: float = 30.0,
        faults: Faults | None = None,
        say: Callable[[str], object] = print,
        vehicle: Vehicle | None = None,
        safety: Safety | None = None,
        warn: Callable[[str], object] | None = None,
    ) -> None:
        self.address = address
        self.vehicle: Vehicle = vehicle or SimulatedVehicle()
        self.safety = safety or Safety()
        self.plan: FlightPlan | None = None
        self.task: Task | None = None  # the vehicle's command the next event waits for
        self.handed_back: str | None = None
        self.grounding_exit = EXIT_HANDED_BACK  # the status once the vehicle is down
        self.left_to: str | None = None  # who flies the vehicle after a hand-back, if not us
        self.want_id = want_id
        self.server_timeout = server_timeout
        self.connect_timeout = connect_timeout
        self.faults = faults or Faults()
        self.say = say
        self.warn = warn or say  # why it ends badly (the CLI: on standard error)
        self.sock = ctx.socket(zmq.DEALER)
        self.sock.setsockopt(zmq.LINGER, 1000)
        self.sock.setsockopt(zmq.RCVHWM, 0)
        self.sock.setsockopt(zmq.SNDHWM, 0)
        self.sock.connect(address)
        self.id = 0
        self.state = "hello"
        self.exit_code: int | None = None
        self.mission: Mission | None = None
        self.core: AgentCore | None = None
        self.replica: Replica | None = None
        self.t0w: float | None = None
        self.inflight = False
        self.events_done = 0
        self.halfway_due: float | None = None
        self.halfway_node = -1
        self.rtl_due: float | None = None
        self.land_due: float | None = None
        self.finish_t = 0.0
        self.lag: list[float] = []
        self.dropped = 0
        self.frames_out = 0
        self.bytes_out = 0
        now = time.monotonic()
        self.started_at = now
        self.last_server = now
        self.next_hb = now
        self.retry_at: float | None = None
        self.waiting = False
        # while the algorithm's kernels compile (state "compiling"): the mission data, and
        # the frames that came since, played in order once they are ready
        self.pending: tuple[Future[None], Mission, dict[str, Any], list[Any]] | None = None
        self.held: list[bytes] = []
        self._send(["C00", want_id])

    # ------------------------------------------------------------------ io
    def _send_frame(self, frame: bytes) -> None:
        f = self.faults
        if f.corrupt > 0 and f.rng.random() < f.corrupt:
            bad = wire.corrupt(frame, f.rng)
            self.sock.send(bad)
            self.frames_out += 1
            self.bytes_out += len(bad)
        self.sock.send(frame)
        self.frames_out += 1
        self.bytes_out += len(frame)

    def _send(self, obj: list[Any]) -> None:
        self._send_frame(wire.pack(obj))

    def _done(self, code: int, why: str = "") -> None:
        if self.exit_code is None:
            self.exit_code = code
            if why:
                (self.say if code == EXIT_OK else self.warn)(
                    f"swarmex agent {self.id or '?'}: {why}"
                )

    # ------------------------------------------------------------------ receiving
    def on_frame(self, frame: bytes, now: float) -> None:
        self.last_server = now
        if self.state == "grounding":
            return  # the id is handed back: the mission is no longer this agent's
        if self.state == "compiling":
            self.held.append(frame)  # read once the mission is set up, in order
            return
        try:
            msg = wire.message(wire.unpack(frame))
            if msg[0] in wire.BROADCAST_COMMANDS:
                b = wire.Broadcast.from_wire(msg)
                if self.mission is None:
                    return
                check_broadcast(b, self.mission)
                self._on_broadcast(b)
                return
            wire.check_control(msg)
            self._on_control(msg, now)
        except wire.WireError:
            self.dropped += 1  # seed 000 §4.1: a message with a bad checksum is skipped

    def _on_broadcast(self, b: wire.Broadcast) -> None:
        assert self.core is not None and self.replica is not None
        self.core.receive(b)
        self.replica.on_broadcast(b)
        if b.id == self.id and ends_step(b):
            self.inflight = False

    def _on_control(self, msg: list[Any], now: float) -> None:
        cmd = msg[0]
        if cmd == "ID" and self.state == "hello":
            self.id = int(msg[1])
            self.state = "mission-data"
            self._send(["C22", self.id])
        elif cmd == "REF":
            reason = str(msg[1])
            if reason == "no vacant id" and self.want_id <= 0 and self.state == "hello":
                if self.retry_at is None and not self.waiting:
                    # a spare waits as long as the mission runs; another agent for
                    # --connect-timeout (see tick)
                    limit = ("as long as the mission runs" if self.want_id < 0
                             else f"up to {self.connect_timeout:g} s")
                    self.say(f"swarmex agent: waiting for a vacant id ({limit})")
                self.waiting = True
                self.retry_at = now + 0.2  # a spare waits for an id to fall vacant
                if self.want_id == 0 and now - self.started_at > self.connect_timeout:
                    self._done(EXIT_REFUSED, f"refused: {reason}")
                return
            if (reason == f"id {self.want_id} is taken" and self.state == "hello"
                    and now - self.started_at <= self.connect_timeout):
                # a fixed id whose holder may have died (a restarted process asking for its
                # own id): the server frees it after --dead-after of silence, so ask again
                # for --connect-timeout instead of giving up at once
                if not self.waiting:
                    self.say(f"swarmex agent: id {self.want_id} is taken; asking again for up "
                             f"to {self.connect_timeout:g} s")
                self.waiting = True
                self.retry_at = now + 0.2
                return
            self._done(EXIT_REFUSED, f"refused: {reason}")
        elif cmd == "ERR":
            self.say(f"swarmex agent {self.id}: server error: {msg[1]}")
        elif cmd == "MIS" and self.state == "mission-data":
            self._on_mission(msg[1], msg[2], now)
        elif cmd == "ACK":
            self._on_ack(str(msg[1]), now)
        elif cmd == "GO" and self.state == "ready":
            self._anchor(float(msg[1]), now)
            self._launch()
        elif cmd == "LEFT" and self.id and int(msg[1]) == self.id:
            # the server gave my id up (it did not hear me for --dead-after): a spare may
            # fly my plan now. Land first, as for a silent server (leave), then exit 5
            self.leave(EXIT_DECLARED_GONE, "the server declared me gone", now)
        elif cmd == "LEFT" and self.replica is not None:
            a = int(msg[1])
            node = self.replica.on_left(a)
            assert self.core is not None
            self.core.forget(a, node)
        elif cmd == "JOIN" and self.replica is not None:
            a = int(msg[1])
            self.replica.on_join(a, float(msg[2]), int(msg[3]))
            if a == self.id and self.state == "ready":
                self._launch()
        elif cmd == "LOST" and self.mission is not None and self.replica is not None:
            b = wire.decode_broadcast(msg[1])  # what my radio lost: its timing only
            check_broadcast(b, self.mission)
            if b.id == self.id:
                self._on_broadcast(b)
            else:
                self.replica.on_broadcast(b)
        elif cmd == "END":
            if self.state == "done":
                self._done(EXIT_OK)
            elif self.state == "hello" and self.want_id < 0:
                self._done(EXIT_OK, "the mission ended without needing a spare")
            elif self.state == "hello":  # never got an id: it did not join, it did not fail
                self._done(EXIT_REFUSED, "refused: the mission ended with no vacant id for me")
            else:  # a copter still flying comes down first (leave), as on a silent server
                self.leave(EXIT_UNFINISHED, "the mission ended before I finished", now)

    def _anchor(self, clock: float, now: float) -> None:
        assert self.mission is not None
        self.t0w = now - clock * self.mission.time_scale

    def _on_mission(self, data: dict[str, Any], log: list[Any], now: float) -> None:
        mission = Mission.from_wire(data)
        if not 1 <= self.id <= mission.n_agents:
            raise wire.EncodingError("mission data without my id")
        # the algorithm's own kernels, now that it is known and before C01, compiled on a
        # thread while this one keeps beating (warm_in_background)
        job = warm_in_background(mission.algorithm)
        if not job.done():
            self.state = "compiling"
            self.pending = (job, mission, data, log)
            return
        self._set_up(mission, data, log, now)

    def _compiled(self, now: float) -> None:
        """The kernels are ready: set the mission up, then read what came meanwhile."""
        assert self.pending is not None
        job, mission, data, log = self.pending
        job.result()  # a failed compile ends the agent as it did on the main thread
        self.pending = None
        self._set_up(mission, data, log, now)
        held, self.held = self.held, []
        for frame in held:
            self.on_frame(frame, now)

    def _set_up(self, mission: Mission, data: dict[str, Any], log: list[Any],
                now: float) -> None:
        """The agent's core, its replica of the others and its flight plan; then C01."""
        self.mission = mission
        self.core = AgentCore(mission, self.id)
        self.replica = Replica(mission)
        for frame in log:  # a late joiner rebuilds what everybody else knows
            self._replay(frame)
        if data.get("started"):
            self._anchor(float(data.get("clock") or 0.0), time.monotonic())
        self.plan = FlightPlan(mission, self.id, self.safety)
        self.vehicle.time_scale = mission.time_scale or 1.0
        if not isinstance(self.vehicle, SimulatedVehicle):
            for note in self.plan.notes():
                self.say(f"swarmex agent {self.id}: {note}")
        self.state = "c01"
        self._send(["C01", self.id, int(mission.specs[self.id - 1].nest),
                    self.vehicle.describe()])

    def _replay(self, frame: bytes) -> None:
        assert self.core is not None and self.replica is not None
        try:
            msg = wire.decode_message(frame)
        except wire.WireError:
            self.dropped += 1
            return
        catch_up(self.core.belief, self.replica, msg)

    def _on_ack(self, what: str, now: float) -> None:
        if what == "C01" and self.state == "c01":
            assert self.plan is not None
            self.state = "prearm"  # C02 only once the pre-arm checks pass (§4.2)
            self.task = self.vehicle.preflight(self.plan)
            self._init_step(now)
        elif what == "C02" and self.state == "c02":
            self.state = "arming"  # C03 once armed
            self.task = self.vehicle.arm()
            self._init_step(now)
        elif what == "C03" and self.state == "c03":
            self.state = "ready"
        elif what == "ST" and self.state == "stats":
            self.state = "done"
            self._done(EXIT_OK)

    # ------------------------------------------------------------------ the vehicle
    def _init_step(self, now: float) -> None:
        """Pre-arm checks, then arming: C02 and C03 go out when the vehicle's task is done
        (at once for the simulated vehicle: "a virtual UAV always passes")."""
        task = self.task
        if task is None or self.state not in ("prearm", "arming"):
            return
        self.vehicle.update(now)
        if task.failed:
            what = "pre-arm checks failed" if self.state == "prearm" else "arming failed"
            self._hand_back(f"{what}: {task.reason}", now)
        elif task.done:
            if self.state == "prearm":
                self.state = "c02"
                self._send(["C02", self.id])
            else:
                self.state = "c03"
                self._send(["C03", self.id])

    def _launch(self) -> None:
        """The mission starts for this agent: take off (its start event waits for it)."""
        assert self.plan is not None
        self.state = "mission"
        self.task = self.vehicle.takeoff(self.plan.altitude)

    def _vehicle_ready(self, now: float) -> bool:
        """Whether the vehicle has done what the next event needs (there, job done, home)."""
        task = self.task
        if task is None or task.done:
            return True
        self.vehicle.update(now)
        if task.failed:
            self._hand_back(f"{task.name} failed: {task.reason}", now)
            return False
        return task.done

    def _command_vehicle(self) -> None:
        """After a step: fly to the announced node, do the job here, or go home."""
        core, plan = self.core, self.plan
        assert core is not None and plan is not None
        if core.finished:
            self.task = self.vehicle.return_and_land()
        elif core.next_kind == "arrive":
            self.task = self.vehicle.goto(plan.position(core.next_node), plan.speed)
        elif core.next_kind == "job_end":
            self.task = self.vehicle.job(core.spec.job_time)

    def _watch_vehicle(self, now: float) -> None:
        """A lost vehicle, or a low battery during the mission: hand the id back."""
        why = self.vehicle.fault()
        task = self.task
        if why is None and self.state == "mission" and task is not None and task.failed:
            why = f"{task.name} failed: {task.reason}"  # noticed before this agent's turn
        if why is None and self.state == "mission":
            other = self.vehicle.other_control()
            level = self.vehicle.battery()
            if other is not None:  # between commands: nothing else would notice
                why = f"{other} took over"
            elif level is not None and level < self.safety.min_battery:
                why = (f"low battery: {level:.0f} % (--min-battery "
                       f"{self.safety.min_battery:g} %)")
        if why is not None:
            self._hand_back(why, now)

    def _hand_back(self, reason: str, now: float, exit_code: int = EXIT_HANDED_BACK,
                   tell_server: bool = True) -> None:
        """Seed 000 §4.3: an agent that stops its work early (an error, a low battery) has
        its id entered back to the vacant list, so a spare can continue its work. The
        vehicle returns to launch and lands (the seed's later fix: RTL on errors), unless a
        pilot or the autopilot's failsafe already flies it (never fight them); a copter
        still armed on the ground is disarmed. The process then exits ``exit_code``."""
        if self.handed_back is not None:
            return
        self.handed_back = reason
        self.grounding_exit = exit_code
        was = self.state
        if tell_server:
            self.say(f"swarmex agent {self.id or '?'}: handing id {self.id} back: {reason}")
            if self.id and self.mission is not None:
                self._send(["RET", self.id, reason])
        self.state = "grounding"
        self.task = None
        if self.vehicle.fault() is not None:
            return
        # the agent's own RTL (a mission's end under way) is not someone else's
        other = None if was in ("rtl", "landing") else self.vehicle.other_control()
        if other is not None:
            self.left_to = other
            self.say(f"swarmex agent {self.id}: {other} flies the vehicle: leaving it alone")
        elif self.vehicle.airborne():
            self.say(f"swarmex agent {self.id}: returning to launch")
            self.task = self.vehicle.return_and_land()
        elif self.vehicle.armed_on_ground():
            self.say(f"swarmex agent {self.id}: disarming")
            self.task = self.vehicle.disarm()

    def leave(self, code: int, why: str, now: float) -> None:
        """End this agent (``code``, ``why``); a vehicle it still flies is brought down
        first, as on a hand-back: the server being gone (or the agent's ``--timeout``)
        must not leave a copter hovering in GUIDED until a failsafe, which a ground station
        watching through a router may keep from firing."""
        if self.exit_code is not None or self.state == "grounding":
            return
        real = not isinstance(self.vehicle, SimulatedVehicle)
        if real and (self.vehicle.airborne() or self.vehicle.armed_on_ground()):
            self.say(f"swarmex agent {self.id or '?'}: {why}")
            self._hand_back(why, now, exit_code=code, tell_server=False)
            return
        self._done(code, why)

    def interrupt(self, now: float, how: str = "Ctrl-C") -> None:
        """Ctrl-C (or SIGTERM, ``how``): an agent holding an id hands it back and lands
        (:meth:`_hand_back`); one still asking for an id, or a waiting spare, just leaves."""
        if self.exit_code is not None or self.state == "grounding":
            return  # already bringing the vehicle down: the first signal must not abandon it
        if self.id and self.state in VEHICLE_STATES:
            self._hand_back(f"interrupted ({how})", now)
        else:
            self._done(EXIT_UNFINISHED, f"interrupted ({how})")

    def _grounding_tick(self, now: float) -> float:
        task, fault = self.task, self.vehicle.fault()
        if task is not None and task.running and fault is None:
            return 0.05
        if (task is not None and task.failed and task.name == "disarm" and fault is None
                and self.vehicle.other_control() is None):
            # refused: the copter was lifting off (ArduCopter disarms only when landed), so
            # it is brought down instead of being left to finish its take-off alone
            self.say(f"swarmex agent {self.id}: disarm refused ({task.reason}); returning to "
                     "launch")
            self.task = self.vehicle.return_and_land()
            return 0.05
        if fault is not None:
            how = f"lost: {fault}"
        elif self.left_to is not None:
            how = f"left to {self.left_to}"
        elif task is None:
            how = "on the ground"
        elif task.done:
            how = "landed" if task.name == "return_and_land" else "disarmed on the ground"
        else:
            how = f"not confirmed landed: {task.reason}"
        if self.grounding_exit == EXIT_HANDED_BACK:
            self._done(EXIT_HANDED_BACK, f"id handed back ({self.handed_back}); vehicle {how}")
        else:
            self._done(self.grounding_exit, f"{self.handed_back}; vehicle {how}")
        return 1.0

    def _server_silent(self, now: float) -> bool:
        """Nothing heard from the server for ``server_timeout`` (at least three of the
        mission's heartbeats, once the mission data says how often the server beats: a
        server beating every 12 s was declared gone by the default 10 s), and nothing
        waiting unread. Agents sharing a process read their sockets in turn after they all
        tick, so while one handled a frame for a long time (a kernel compiled on a cold
        cache, under load) the others' frames waited unread, and they declared a live
        server gone."""
        limit = self.server_timeout
        if self.mission is not None:
            limit = max(limit, 3 * self.mission.heartbeat)
        if now - self.last_server <= limit:
            return False
        return not self.sock.poll(0, zmq.POLLIN)

    # ------------------------------------------------------------------ acting
    def wall_of(self, t: float) -> float:
        assert self.t0w is not None and self.mission is not None
        return self.t0w + t * self.mission.time_scale

    def tick(self, now: float) -> float:
        """Do whatever is due; returns the seconds until something may be due again."""
        if self.exit_code is not None:
            return 1.0
        self.vehicle.update(now)
        if self.state == "grounding":
            return self._grounding_tick(now)
        if self.state in VEHICLE_STATES:
            self._watch_vehicle(now)
            if self.state == "grounding":
                return 0.0
        if self.state in ("prearm", "arming"):
            self._init_step(now)
        if self.state == "compiling" and self.pending is not None and self.pending[0].done():
            self._compiled(now)
        if self.state == "hello" and self.want_id < 0 and self.waiting:
            # a spare the server has answered waits for a vacated id as long as the mission
            # runs (END releases it); only a silent server ends the wait
            if self._server_silent(now):
                self.leave(EXIT_SERVER_GONE, "the server went silent", now)
                return 0.0
        elif self.state == "hello":  # §4.3: keep trying to connect for a while
            if now - self.started_at > self.connect_timeout:
                self._done(EXIT_SERVER_GONE if not self.waiting else EXIT_REFUSED,
                           f"refused: id {self.want_id} is taken"
                           if self.waiting and self.want_id > 0 else "no id from the server")
                return 1.0
        elif self._server_silent(now):
            self.leave(EXIT_SERVER_GONE, "the server went silent", now)
            return 0.0
        if self.state == "hello" and self.retry_at is not None and now >= self.retry_at:
            self.retry_at = None
            self._send(["C00", self.want_id])
        wait = max(0.0, self.next_hb - now)
        if not self.id:  # no id yet, so no heartbeat: sleep until the next ask, not spin
            # (next_hb does not advance without an id, and a waiting spare polled at 100 %)
            wait = max(0.0, self.retry_at - now) if self.retry_at is not None else 0.2
        if now >= self.next_hb and self.id:
            mission = self.mission or (self.pending[1] if self.pending is not None else None)
            hb = mission.heartbeat if mission is not None else 0.25
            self.next_hb = now + hb
            self._send(["HB", self.id])
            wait = hb
        if self.state == "mission":
            wait = min(wait, self._mission_tick(now))
        elif self.state in ("rtl", "landing"):
            wait = min(wait, self._termination_tick(now))
        elif self.state == "compiling":
            wait = min(wait, 0.05)  # to see the compile end (a thread's event, not a frame)
        if not isinstance(self.vehicle, SimulatedVehicle):
            wait = min(wait, 0.05)  # telemetry to read, link and battery to watch
        return wait

    def _mission_tick(self, now: float) -> float:
        core, rep = self.core, self.replica
        assert core is not None and rep is not None
        if self.halfway_due is not None and now >= self.halfway_due:
            self._halfway()
        if self.inflight:
            return 0.05
        if core.finished:
            return 0.05
        if rep.next_agent() != self.id:
            return 0.05 if self.halfway_due is None else max(0.0, self.halfway_due - now)
        key = rep.pending[self.id]
        assert key is not None
        t = key[0]
        due = self.wall_of(t)
        if now < due:
            return due - now
        if not self._vehicle_ready(now):
            return 0.0 if self.state == "grounding" else 0.02
        if self.halfway_due is not None:
            self._halfway()
        scale = self.mission.time_scale if self.mission else 0.0
        if scale > 0:
            self.lag.append((now - due) / scale)
        out = core.step(t, rep.rng)
        for b in out:
            self._send_frame(b.frame())
        self.inflight = True
        self.events_done += 1
        if core.next_kind == "arrive" and not core.finished:
            eta = out[-1].eta
            self.halfway_due = self.wall_of(t + (eta - t) / 2)
            self.halfway_node = core.next_node
        self._command_vehicle()
        if core.finished:
            self.finish_t = t
            self.state = "rtl"
            self.rtl_due = self.wall_of(t + core.rtl_time())
        die = self.faults.die_after
        if die is not None and self.events_done >= die:
            self.say(f"swarmex agent {self.id}: fault injection: dying after {die} events")
            os._exit(137)
        return 0.0

    def _halfway(self) -> None:
        assert self.core is not None
        self.halfway_due = None
        b = wire.Broadcast("C06", self.id, self.halfway_node)
        self._send_frame(b.frame())

    def _termination_tick(self, now: float) -> float:
        core = self.core
        assert core is not None and self.mission is not None
        spec = core.spec
        task = self.task
        if task is not None and task.failed:
            self._hand_back(f"{task.name} failed: {task.reason}", now)
            return 0.0
        if self.state == "rtl":
            assert self.rtl_due is not None
            if now < self.rtl_due:
                return self.rtl_due - now
            if task is not None and task.running and task.phase == "returning":
                return 0.02  # C10 once above home
            t = self.finish_t + core.rtl_time()
            self._send_frame(wire.Broadcast("C10", self.id, spec.nest, t=t).frame())
            self.state = "landing"
            self.land_due = self.wall_of(t + spec.landing_time)
        assert self.land_due is not None
        if now < self.land_due:
            return self.land_due - now
        if task is not None and task.running:
            return 0.02  # C11 once landed and disarmed
        t = self.finish_t + core.rtl_time() + spec.landing_time
        self._send_frame(wire.Broadcast("C11", self.id, spec.nest, t=t).frame())
        stats = core.stats()
        stats["lag"] = self.lag
        stats["dropped"] = self.dropped
        stats["frames_out"] = self.frames_out
        stats["bytes_out"] = self.bytes_out
        stats["vehicle"] = self.vehicle.describe()
        stats["battery"] = self.vehicle.battery()
        self.state = "stats"
        self._send(["ST", self.id, stats])
        return 0.05

    def close(self) -> None:
        self.sock.close(1000 if self.exit_code in (EXIT_OK, EXIT_HANDED_BACK) else 0)
        self.vehicle.close()


def open_vehicle(link: str | None, safety: Safety | None = None) -> Vehicle:
    """The vehicle ``--vehicle`` names (None: the simulated one). A MAVLink link needs the
    ``uav`` extra (one line naming it when pymavlink is missing)."""
    if link is None:
        return SimulatedVehicle()
    parse_link(link)
    from swarmex.errors import require

    require("pymavlink", "uav", "--vehicle")
    from swarmex.net.mavlink import MavlinkVehicle

    return MavlinkVehicle(link, safety or Safety())


def wait_for_vehicle(vehicle: Vehicle, timeout: float,
                     say: Callable[[str], object] = print) -> bool:
    """Before asking for an id: the vehicle's first heartbeat (no vehicle, no agent)."""
    deadline = time.monotonic() + timeout
    link = vehicle.describe().get("link", vehicle.kind)
    while not vehicle.heard():
        now = time.monotonic()
        if now > deadline:
            say(f"swarmex agent: no heartbeat from the vehicle at {link} within {timeout:g} s")
            vehicle.close()
            return False
        vehicle.update(now)
        time.sleep(0.02)
    info = vehicle.describe()
    say(f"swarmex agent: vehicle at {link}: " + ", ".join(
        f"{k} {v}" for k, v in info.items() if k not in ("kind", "link")))
    return True


def run_agents(
    address: str,
    count: int = 1,
    want_id: int = 0,
    server_timeout: float = 10.0,
    connect_timeout: float = 30.0,
    timeout: float = 3600.0,
    faults: Faults | None = None,
    say: Callable[[str], object] = print,
    spares: int = 0,
    vehicle: Vehicle | None = None,
    safety: Safety | None = None,
    warn: Callable[[str], object] | None = None,
) -> int:
    """Run ``count`` agents (each its own connection) until all are done; the worst status.
    ``spares`` more wait for an id vacated mid-mission (as ``--spare`` does). ``vehicle``
    (with ``count`` 1 and no spares: one agent flies one vehicle) replaces the simulated
    one; ``safety`` holds its limits. ``say`` gets what the agents report, ``warn`` (default
    ``say``) why one of them ended with a failure status.

    Compiled kernels run on one thread here: each agent stands for one UAV's computer, and
    several agent processes share the machine, where numba's parallel regions (the field
    cache's batched BFS) would only fight over the cores — a parallel launch per decision
    cost ~10 ms under load against ~0.1 ms serial. Results do not depend on it.
    """
    import numba

    if vehicle is not None and (count != 1 or spares):
        raise ValueError("a vehicle is flown by one agent: count 1, no spares")
    numba.set_num_threads(1)
    warm_up()
    if vehicle is not None and not wait_for_vehicle(vehicle, (safety or Safety()).task_timeout,
                                                    say):
        return EXIT_HANDED_BACK
    # A context of their own, terminated at the end: that waits (up to each socket's
    # linger) until the last frames are out. pyzmq does not terminate contexts at
    # interpreter exit, so a process ending right after its id hand-back (RET) or its
    # stats (ST) could kill ZeroMQ's I/O thread with the frame still queued; the server
    # would then wait for the id until its init timeout (the likely cause of one CI
    # failure under load, not reproduced).
    ctx: zmq.Context[zmq.Socket[bytes]] = zmq.Context()
    try:
        agents = [
            AgentClient(ctx, address, want_id if count == 1 or want_id < 0 else 0,
                        server_timeout, connect_timeout, faults, say, vehicle, safety, warn)
            for _ in range(count)
        ] + [
            AgentClient(ctx, address, -1, server_timeout, connect_timeout, faults, say,
                        warn=warn)
            for _ in range(spares)
        ]
    except zmq.ZMQError as exc:  # EMFILE: more sockets than the process may open
        ctx.destroy(linger=0)
        raise InputError(f"--count {count} --spares {spares}: cannot open that many agents in"
                         f" one process ({exc}); run them in several processes, or raise"
                         " the open-file limit (ulimit -n)") from None
    poller = zmq.Poller()
    for a in agents:
        poller.register(a.sock, zmq.POLLIN)
    fd = vehicle.fileno() if vehicle is not None else None
    if fd is not None:  # wake on telemetry too (the agent's tick reads it)
        poller.register(fd, zmq.POLLIN)
    by_sock = {a.sock: a for a in agents}
    deadline = time.monotonic() + timeout
    # Ctrl-C or SIGTERM: every agent hands its id back (RET) and brings its vehicle down, as
    # for a vehicle fault, instead of vanishing: the server frees the ids at once (not after
    # --dead-after) and a real copter returns to launch rather than hovering until the
    # autopilot's GCS failsafe
    handled = timed_out = False
    with StopRequest() as stop:
        try:
            while any(a.exit_code is None for a in agents):
                now = time.monotonic()
                if stop.seen and not handled:
                    handled = True
                    for a in agents:
                        a.interrupt(now, stop.how)
                    continue
                if now > deadline and not timed_out:
                    timed_out = True  # vehicles still flying are brought down first
                    for a in agents:
                        a.leave(EXIT_SERVER_GONE, "timeout", now)
                    continue
                wait = min(a.tick(now) for a in agents if a.exit_code is None)
                ready = dict(poller.poll(int(max(0.0, min(wait, 0.5)) * 1000)))
                for sock in ready:
                    if sock not in by_sock:
                        continue  # the vehicle's link: read by the next tick
                    agent = by_sock[sock]
                    for _ in range(100_000):
                        try:
                            frame = sock.recv(flags=zmq.NOBLOCK)
                        except zmq.Again:
                            break
                        agent.on_frame(frame, time.monotonic())
                        if agent.state == "mission" and not agent.inflight:
                            break  # act as soon as it may be this agent's turn
        finally:
            for a in agents:
                a.close()
            ctx.term()
    if stop.seen:
        return EXIT_INTERRUPTED
    return max(a.exit_code or 0 for a in agents)
