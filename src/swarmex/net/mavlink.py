"""A real (or emulated) multicopter behind :class:`~swarmex.net.vehicle.Vehicle`, over MAVLink.

Seed 000 flew Pixhawks through DroneKit; this speaks MAVLink itself with pymavlink (extra
``uav``), the library DroneKit was built on and that is still maintained. It flies an
**ArduPilot copter** (ArduCopter's GUIDED / RTL flight modes): a Pixhawk-class flight
controller on the onboard computer's serial port, ArduPilot SITL, or ``swarmex
uav-emulator``. What each command does on the link:

* ``preflight``: waits for the autopilot's heartbeat and telemetry (asks for the streams),
  then checks — the mission plan (altitude ceiling, every node within ``--max-distance``),
  an ArduPilot multicopter, disarmed, on the ground, the autopilot's own pre-arm checks
  healthy (``SYS_STATUS``'s pre-arm bit, with its last ``PreArm:`` text), a 3-D GPS fix with
  at least ``--min-satellites`` and HDOP at most ``--max-hdop``, a battery monitor reading
  at least ``--arm-battery`` percent. Any failure fails the task, naming every problem;
* ``arm``: GUIDED mode, then ``MAV_CMD_COMPONENT_ARM_DISARM``; a refusal (``COMMAND_ACK``
  not accepted) fails with the autopilot's reason;
* ``takeoff``: re-arms if the autopilot disarmed meanwhile (ArduCopter disarms a copter
  left idle on the ground), then ``MAV_CMD_NAV_TAKEOFF``, resent only while the copter is
  still on the ground with no accepted answer (ArduCopter refuses a second take-off once
  airborne: "can't takeoff again"); done at the altitude;
* ``goto``: ``MAV_CMD_DO_CHANGE_SPEED`` and ``SET_POSITION_TARGET_LOCAL_NED`` (home + the
  offset, in the autopilot's local frame), repeated every second until the vehicle is within
  ``arrive_radius``; it fails if the vehicle leaves GUIDED (a pilot or a failsafe took
  over: never fight them);
* ``job``: climb ``job_climb`` metres, hold from the top of the climb until the job's
  seconds have passed on the vehicle's clock (``time_boot_ms``), come back down; like every
  flying step it gives up when the copter leaves GUIDED or disarms;
* ``return_and_land``: RTL mode (the autopilot climbs to its RTL altitude, flies home,
  lands and disarms); phase ``returning`` until above home, ``landing`` until disarmed.

Every command is resent until its effect shows (UDP may lose any packet; the take-off alone
stops once accepted, see above), and fails after its expected time plus ``task_timeout``.
No telemetry for ``link_timeout`` seconds, or a closed TCP link, is a :meth:`fault`; the
agent then hands its id back (docs/uav.md). A copter in a mode the agent did not set (a
pilot's LOITER, the autopilot's failsafe RTL or LAND) is someone else's
(:meth:`MavlinkVehicle.other_control`): the agent hands its id back and sends it nothing
more.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from swarmex.errors import InputError
from swarmex.net.vehicle import FlightPlan, Info, Position, Safety, Task, Vehicle, parse_link
from swarmex.worlds.geo import north_east

os.environ.setdefault("MAVLINK20", "1")  # ArduPilot speaks MAVLink 2; pymavlink reads this
from pymavlink import mavutil  # noqa: E402

mav = mavutil.mavlink

#: ArduCopter's custom flight modes used here
GUIDED, RTL, LAND = 4, 6, 9
COPTER_MODES = {0: "STABILIZE", 2: "ALT_HOLD", 3: "AUTO", 4: "GUIDED", 5: "LOITER", 6: "RTL",
                9: "LAND", 16: "POSHOLD", 17: "BRAKE", 21: "SMART_RTL"}
MULTICOPTERS = {
    mav.MAV_TYPE_QUADROTOR, mav.MAV_TYPE_HEXAROTOR, mav.MAV_TYPE_OCTOROTOR,
    mav.MAV_TYPE_TRICOPTER, mav.MAV_TYPE_COAXIAL, mav.MAV_TYPE_HELICOPTER,
    mav.MAV_TYPE_DODECAROTOR, mav.MAV_TYPE_DECAROTOR,
}
ARMED = mav.MAV_MODE_FLAG_SAFETY_ARMED
PREARM = mav.MAV_SYS_STATUS_PREARM_CHECK
#: SET_POSITION_TARGET_*: use the position, ignore velocity, acceleration, yaw and yaw rate
POSITION_ONLY = 0b110111111000
GCS_HEARTBEAT = 1.0  # wall seconds


class _Failed(Exception):
    """A step cannot succeed; the message is the task's reason."""


@dataclass
class _Step:
    name: str
    done: Callable[[], bool]
    send: Callable[[], None] | None = None
    timeout: float = 30.0  # wall seconds
    resend: float = 1.0
    command: int | None = None  # a COMMAND_ACK refusing this command fails the step
    # for a command that must not be repeated once it took (a take-off): evidence it did,
    # checked only after the first send; then no resends, and a refusal of a late resend
    # ("can't takeoff again") does not count. Other steps resend until done(): a repeated
    # mode change or arm is harmless, and an ACK names no parameters, so one for GUIDED
    # could not prove an RTL
    taken: Callable[[float], bool] | None = None
    guard: Callable[[], str | None] | None = None  # a reason to give up, checked each update
    explain: Callable[[], str] | None = None  # what is missing, said on a timeout
    started: float | None = None
    sent: float = -1e18


class MavlinkVehicle(Vehicle):
    kind = "mavlink"

    def __init__(self, link: str, safety: Safety, connect: bool = True) -> None:
        self.link = link
        self.safety = safety
        device, baud = parse_link(link)
        self.conn: Any = None
        self._fault: str | None = None
        if connect:
            _resolve(link, device)
            try:
                # pymavlink prints its TCP retries ("Connection refused sleeping") on stdout
                with contextlib.redirect_stdout(io.StringIO()):
                    self.conn = mavutil.mavlink_connection(
                        device, baud=baud, source_system=255, source_component=190,
                        autoreconnect=False,
                    )
            except ImportError as exc:  # pyserial, for a serial link
                raise InputError(f"--vehicle: cannot open {link}: {exc}; install it with "
                                 "pip install 'swarmex[uav]'") from None
            except OSError as exc:  # no such port, refused
                raise InputError(f"--vehicle: cannot open {link}: {exc}") from None
            if hasattr(self.conn, "handle_eof"):  # TCP: a closed link is a fault, at once
                self.conn.handle_eof = self.conn.handle_disconnect = self._tcp_closed
        self.opened = time.monotonic()
        self.target_system = 0
        self.target_component = 0
        self.autopilot: int | None = None
        self.mav_type: int | None = None
        self.armed = False
        self.mode: int | None = None
        self.sensors: tuple[int, int, int] | None = None  # present, enabled, health
        self.battery_pct: float | None = None
        self.voltage: float | None = None
        self.gps: tuple[int, int, float] | None = None  # fix type, satellites, HDOP
        self.local: tuple[float, float, float] | None = None  # north, east, down (origin)
        self.relative_alt: float | None = None
        self.boot_s = 0.0  # the vehicle's clock (seconds since its boot)
        self.landed_state: int | None = None
        self.home: tuple[float, float, float] | None = None  # local NED of home, on the ground
        self.last_rx: float | None = None
        self.next_hb = 0.0
        self.statustexts: list[tuple[float, int, str]] = []
        self.refused: dict[int, tuple[float, int]] = {}  # command -> (when, MAV_RESULT)
        self.accepted: dict[int, float] = {}  # command -> when the autopilot last accepted it
        self.global_position: tuple[float, float] | None = None  # latitude, longitude (deg)
        self.task: Task | None = None
        self.steps: list[_Step] = []
        self.target: Position | None = None

    # ------------------------------------------------------------------ Vehicle
    def describe(self) -> Info:
        info: Info = {"kind": self.kind, "link": self.link}
        if self.autopilot is not None:
            info["autopilot"] = _enum_name("MAV_AUTOPILOT", self.autopilot)
        if self.mav_type is not None:
            info["type"] = _enum_name("MAV_TYPE", self.mav_type)
        if self.target_system:
            info["sysid"] = self.target_system
        return info

    def fileno(self) -> int | None:
        if self.conn is None:
            return None
        try:
            fd = self.conn.fd if self.conn.fd is not None else self.conn.port.fileno()
            return int(fd)
        except (AttributeError, OSError, ValueError):
            return None

    def heard(self) -> bool:
        return self.autopilot is not None

    def update(self, now: float) -> None:
        self._pump(now)
        if now >= self.next_hb:
            self.next_hb = now + GCS_HEARTBEAT
            self._send_gcs_heartbeat()
        if (self._fault is None and self.last_rx is not None
                and now - self.last_rx > self.safety.link_timeout):
            self._fault = (f"no telemetry from {self.link} for {now - self.last_rx:.1f} s "
                           f"(link lost)")
        self._advance(now)

    def position(self) -> Position | None:
        if self.local is None or self.home is None:
            return None
        n, e, d = self.local
        alt = self.relative_alt if self.relative_alt is not None else self.home[2] - d
        return Position(n - self.home[0], e - self.home[1], alt)

    def battery(self) -> float | None:
        return self.battery_pct

    def fault(self) -> str | None:
        return self._fault

    def airborne(self) -> bool:
        if self.landed_state is not None:
            return self.landed_state != mav.MAV_LANDED_STATE_ON_GROUND
        return self.armed and (self.relative_alt or 0.0) > 0.5

    def close(self) -> None:
        if self.conn is not None:
            self.conn.close()

    # ---- commands
    def preflight(self, plan: FlightPlan) -> Task:
        t = self.safety.task_timeout
        return self._start("preflight", [
            _Step("heartbeat", lambda: self.autopilot is not None, self._request_streams, t),
            _Step("telemetry", self._have_telemetry, self._request_streams, t, resend=2.0,
                  explain=self._missing_telemetry),
            *([_Step("GPS position", lambda: self.global_position is not None,
                     self._request_streams, t, resend=2.0,
                     explain=lambda: "GLOBAL_POSITION_INT gives no latitude and longitude: "
                     "the nest on the GPS grid cannot be checked")]
              if plan.nest_latlon() is not None else []),
            _Step("checks", lambda: self._checks(plan), None, t),
        ])

    def arm(self) -> Task:
        return self._start("arm", self._arm_steps())

    def takeoff(self, altitude: float) -> Task:
        s = self.safety
        alt = float(altitude)
        self.target = Position(0.0, 0.0, alt)
        climb = self._expected(alt / 1.0)
        return self._start("takeoff", [
            *self._arm_steps(),
            _Step("takeoff", lambda: (self.relative_alt or 0.0) >= alt - s.arrive_radius,
                  lambda: self._command(mav.MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, alt),
                  s.task_timeout + climb, command=mav.MAV_CMD_NAV_TAKEOFF,
                  guard=self._guided_guard, taken=self._took_off),
        ])

    def goto(self, target: Position, speed: float) -> Task:
        here = self.position()
        dist = here.horizontal_distance(target) if here is not None else 0.0
        self.target = target
        return self._start("goto", [self._fly_step("goto", target, speed, dist / speed)])

    def job(self, seconds: float) -> Task:
        if seconds <= 0 or self.target is None:
            return Task("job").finish()
        s = self.safety
        base = self.target
        up = Position(base.north, base.east, base.altitude + s.job_climb)
        top: list[float] = []  # the vehicle's clock at the top of the climb

        def held() -> bool:  # the job's time runs on the vehicle's clock, from the top
            if not top:
                top.append(self.boot_s)
            return self.boot_s - top[0] >= seconds

        return self._start("job", [
            self._fly_step("job: climb", up, None, s.job_climb),
            _Step("job: hold", held, None, s.task_timeout + self._expected(seconds),
                  guard=self._guided_guard),
            self._fly_step("job: descend", base, None, s.job_climb),
        ])

    def return_and_land(self) -> Task:
        s = self.safety
        here = self.position() or Position(0.0, 0.0, 0.0)
        home = Position(0.0, 0.0, 0.0)
        back = self._expected(here.horizontal_distance(home) / 2.0 + 20.0)
        down = self._expected(max(here.altitude, 15.0) / 0.5)
        task = self._start("return_and_land", [
            _Step("returning", lambda: self.mode == RTL or not self.armed,
                  lambda: self._set_mode(RTL), s.task_timeout, command=mav.MAV_CMD_DO_SET_MODE),
            _Step("returning", lambda: not self.armed or self._near_home(), None,
                  s.task_timeout + back),
            _Step("landing", lambda: not self.armed, None, s.task_timeout + down),
        ])
        task.phase = "returning"
        return task

    # ------------------------------------------------------------------ tasks
    def _start(self, name: str, steps: list[_Step]) -> Task:
        if self.task is not None and self.task.running:
            self.task.fail(f"replaced by {name}")
        self.task = Task(name)
        self.steps = steps
        self._advance(time.monotonic())
        return self.task

    def _advance(self, now: float) -> None:
        task = self.task
        if task is None or not task.running:
            return
        if self._fault is not None:
            task.fail(self._fault)
            return
        while self.steps:
            st = self.steps[0]
            if st.started is None:
                st.started = now
                task.phase = st.name
            taken = st.taken is not None and st.sent > -1e18 and st.taken(st.started)
            try:
                if st.command is not None and st.command in self.refused and not taken:
                    when, result = self.refused[st.command]
                    if when >= st.started:
                        raise _Failed(f"{st.name}: {_enum_name('MAV_CMD', st.command)} refused "
                                      f"({_enum_name('MAV_RESULT', result)})"
                                      + self._recent_text(now))
                if st.done():
                    self.steps.pop(0)
                    continue
                if st.guard is not None and (why := st.guard()) is not None:
                    raise _Failed(f"{st.name}: {why}")
            except _Failed as exc:
                task.fail(str(exc))
                return
            if now - st.started > st.timeout:
                more = f" ({st.explain()})" if st.explain is not None else ""
                task.fail(f"{st.name}: not done within {st.timeout:.0f} s{more}"
                          + self._recent_text(now))
                return
            if st.send is not None and now - st.sent >= st.resend and not taken:
                st.sent = now
                st.send()
            return
        task.finish()

    def _expected(self, vehicle_seconds: float) -> float:
        """Wall seconds a manoeuvre of ``vehicle_seconds`` may take (five times the nominal)."""
        return 5.0 * max(vehicle_seconds, 0.0) * (self.time_scale or 1.0)

    def _arm_steps(self) -> list[_Step]:
        t = self.safety.task_timeout
        return [
            _Step("mode GUIDED", lambda: self.mode == GUIDED, lambda: self._set_mode(GUIDED), t,
                  command=mav.MAV_CMD_DO_SET_MODE),
            _Step("arm", lambda: self.armed,
                  lambda: self._command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 1),
                  t, command=mav.MAV_CMD_COMPONENT_ARM_DISARM),
        ]

    def _fly_step(self, name: str, target: Position, speed: float | None,
                  nominal: float) -> _Step:
        def send() -> None:
            if speed is not None:
                self._command(mav.MAV_CMD_DO_CHANGE_SPEED, 1, speed, -1)
            self._position_target(target)

        def there() -> bool:
            here = self.position()
            r = self.safety.arrive_radius
            return (here is not None and here.horizontal_distance(target) <= r
                    and abs(here.altitude - target.altitude) <= r)

        return _Step(name, there, send, self.safety.task_timeout + self._expected(nominal),
                     guard=self._guided_guard)

    def _guided_guard(self) -> str | None:
        if not self.armed:
            return "the vehicle disarmed"
        if self.mode != GUIDED:
            now = COPTER_MODES.get(self.mode if self.mode is not None else -1, self.mode)
            return f"the vehicle left GUIDED mode (now {now}): a pilot or a failsafe took over"
        return None

    def _took_off(self, since: float) -> bool:
        """The take-off is under way: the autopilot accepted it since ``since``, or the copter
        has left the ground (by its landed state when it reports one, else its altitude)."""
        if self.accepted.get(mav.MAV_CMD_NAV_TAKEOFF, -1e18) >= since:
            return True
        if self.landed_state is not None:
            return self.landed_state in (mav.MAV_LANDED_STATE_TAKEOFF,
                                         mav.MAV_LANDED_STATE_IN_AIR)
        return (self.relative_alt or 0.0) > 0.5

    def other_control(self) -> str | None:
        """Who flies the copter, if not this agent: an armed copter in a mode other than
        GUIDED was switched by a pilot (LOITER, ...) or by the autopilot's failsafe (RTL,
        LAND). The agent then leaves it alone (docs/uav.md)."""
        if not self.armed or self.mode is None or self.mode == GUIDED:
            return None
        name = COPTER_MODES.get(self.mode, str(self.mode))
        who = "the autopilot or a pilot" if self.mode in (RTL, LAND, 21) else "a pilot"
        return f"{who} (mode {name})"

    def armed_on_ground(self) -> bool:
        return self.armed and not self.airborne()

    def disarm(self) -> Task:
        return self._start("disarm", [
            _Step("disarm", lambda: not self.armed,
                  lambda: self._command(mav.MAV_CMD_COMPONENT_ARM_DISARM, 0),
                  self.safety.task_timeout, command=mav.MAV_CMD_COMPONENT_ARM_DISARM),
        ])

    def _near_home(self) -> bool:
        here = self.position()
        return here is not None and here.horizontal_distance(Position(0, 0, 0)) <= max(
            self.safety.arrive_radius, 2.0)

    def _have_telemetry(self) -> bool:
        return (self.sensors is not None and self.gps is not None and self.local is not None
                and self.relative_alt is not None)

    def _missing_telemetry(self) -> str:
        have = {"SYS_STATUS": self.sensors, "GPS_RAW_INT": self.gps,
                "LOCAL_POSITION_NED (no EKF origin yet?)": self.local,
                "GLOBAL_POSITION_INT": self.relative_alt}
        return "no " + ", ".join(k for k, v in have.items() if v is None)

    def _checks(self, plan: FlightPlan) -> bool:
        s = self.safety
        problems = plan.problems()
        if self.autopilot != mav.MAV_AUTOPILOT_ARDUPILOTMEGA:
            problems.append(f"autopilot {_enum_name('MAV_AUTOPILOT', self.autopilot or 0)} is "
                            "not ArduPilot (the flight modes used are ArduCopter's)")
        if self.mav_type not in MULTICOPTERS:
            problems.append(f"vehicle type {_enum_name('MAV_TYPE', self.mav_type or 0)} is not "
                            "a multicopter")
        if self.armed:
            problems.append("already armed")
        if self.airborne():
            problems.append("not on the ground")
        assert self.sensors is not None and self.gps is not None
        present, enabled, health = self.sensors
        if present & PREARM and enabled & PREARM and not health & PREARM:
            problems.append("the autopilot's pre-arm checks fail" + self._last_prearm_text())
        fix, sats, hdop = self.gps
        if fix < 3:
            problems.append(f"GPS: no 3-D fix (fix type {fix})")
        if sats < s.min_satellites:
            problems.append(f"GPS: {sats} satellites (--min-satellites {s.min_satellites})")
        if hdop > s.max_hdop:
            problems.append(f"GPS: HDOP {hdop:.2f} (--max-hdop {s.max_hdop:g})")
        if self.battery_pct is None:
            problems.append("battery level unknown (no battery monitor): low battery could "
                            "not be caught in flight")
        elif self.battery_pct < s.arm_battery:
            problems.append(f"battery {self.battery_pct:.0f} % (--arm-battery "
                            f"{s.arm_battery:g} %)")
        nest = plan.nest_latlon()
        if nest is not None:  # the "GPS position" step before this one waited for it
            assert self.global_position is not None
            off = math.hypot(*north_east(nest, self.global_position))
            if off > s.nest_radius:
                problems.append(
                    f"the vehicle stands {off:.0f} m from its nest (node {plan.home_node} at "
                    f"{nest[0]:.6f},{nest[1]:.6f}; --nest-radius {s.nest_radius:g} m): the plan"
                    " is flown around where it arms")
        if problems:
            raise _Failed("; ".join(problems))
        return True

    # ------------------------------------------------------------------ link
    def _tcp_closed(self) -> None:
        """pymavlink's EOF and reset handlers (which print a line on every read and would
        reconnect): the link is lost, and nothing more is read from it."""
        if self._fault is None:
            self._fault = f"the vehicle's TCP link {self.link} closed (link lost)"

    def _pump(self, now: float) -> None:
        if self.conn is None or (self._fault is not None and hasattr(self.conn, "handle_eof")):
            return
        for _ in range(2000):
            try:
                msg = self.conn.recv_match(blocking=False)
            except (OSError, ValueError):  # a serial port gone, a socket error
                msg = None
            if msg is None:
                return
            self.on_message(msg, now)

    def on_message(self, msg: Any, now: float) -> None:
        """One telemetry message (public for tests that feed messages by hand)."""
        kind = msg.get_type()
        if kind == "BAD_DATA":
            return
        src = msg.get_srcSystem()
        if kind == "HEARTBEAT":
            if msg.type == mav.MAV_TYPE_GCS or msg.autopilot == mav.MAV_AUTOPILOT_INVALID:
                return  # another ground station, not the vehicle
            if not self.target_system:
                self.target_system = src
                self.target_component = msg.get_srcComponent()
            if src != self.target_system:
                return
            self.autopilot = int(msg.autopilot)
            self.mav_type = int(msg.type)
            self.armed = bool(msg.base_mode & ARMED)
            self.mode = int(msg.custom_mode)
        elif kind == "STATUSTEXT" and not self.target_system:
            pass  # the autopilot's first words (a PreArm: report) may come before its heartbeat
        elif not self.target_system or src != self.target_system:
            return
        self.last_rx = now
        if kind == "SYS_STATUS":
            self.sensors = (int(msg.onboard_control_sensors_present),
                            int(msg.onboard_control_sensors_enabled),
                            int(msg.onboard_control_sensors_health))
            pct = int(msg.battery_remaining)
            self.battery_pct = float(pct) if pct >= 0 else None
            self.voltage = msg.voltage_battery / 1000.0
        elif kind == "GPS_RAW_INT":
            eph = int(msg.eph)
            self.gps = (int(msg.fix_type), int(msg.satellites_visible),
                        eph / 100.0 if eph != 65535 else 99.99)
        elif kind == "GLOBAL_POSITION_INT":
            self.relative_alt = msg.relative_alt / 1000.0
            self.boot_s = msg.time_boot_ms / 1000.0
            if msg.lat or msg.lon:  # 0, 0: no position yet
                self.global_position = (msg.lat / 1e7, msg.lon / 1e7)
        elif kind == "LOCAL_POSITION_NED":
            self.local = (float(msg.x), float(msg.y), float(msg.z))
            if not self.armed or self.home is None:
                self.home = self.local  # home: where it stood before arming
        elif kind == "EXTENDED_SYS_STATE":
            self.landed_state = int(msg.landed_state)
        elif kind == "STATUSTEXT":
            text = msg.text
            if isinstance(text, bytes):
                text = text.decode("utf-8", "replace")
            self.statustexts.append((now, int(msg.severity), str(text).rstrip("\0")))
            del self.statustexts[:-20]
        elif kind == "COMMAND_ACK":
            result = int(msg.result)
            if result in (mav.MAV_RESULT_ACCEPTED, mav.MAV_RESULT_IN_PROGRESS):
                self.accepted[int(msg.command)] = now
            else:
                self.refused[int(msg.command)] = (now, result)

    def _recent_text(self, now: float) -> str:
        texts = [t for when, sev, t in self.statustexts
                 if now - when < 5.0 and sev <= mav.MAV_SEVERITY_WARNING]
        return (": " + texts[-1]) if texts else ""

    def _last_prearm_text(self) -> str:
        texts = [t for _, _, t in self.statustexts if t.lower().startswith(("prearm", "arm"))]
        return (": " + texts[-1]) if texts else ""

    # ---- sending
    def _send_gcs_heartbeat(self) -> None:
        if self.conn is not None:
            self.conn.mav.heartbeat_send(mav.MAV_TYPE_GCS, mav.MAV_AUTOPILOT_INVALID, 0, 0,
                                         mav.MAV_STATE_ACTIVE)

    def _request_streams(self) -> None:
        if self.conn is not None and self.target_system:
            self.conn.mav.request_data_stream_send(self.target_system, self.target_component,
                                                   mav.MAV_DATA_STREAM_ALL, 10, 1)

    def _command(self, command: int, *params: float) -> None:
        if self.conn is None:
            return
        p = [float(v) for v in params] + [0.0] * (7 - len(params))
        self.conn.mav.command_long_send(self.target_system, self.target_component, command, 0,
                                        *p)

    def _set_mode(self, mode: int) -> None:
        self._command(mav.MAV_CMD_DO_SET_MODE, mav.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode)

    def _position_target(self, target: Position) -> None:
        if self.conn is None or self.home is None:
            return
        hn, he, hd = self.home
        self.conn.mav.set_position_target_local_ned_send(
            0, self.target_system, self.target_component, mav.MAV_FRAME_LOCAL_NED,
            POSITION_ONLY, hn + target.north, he + target.east, hd - target.altitude,
            0, 0, 0, 0, 0, 0, 0, 0,
        )


def _resolve(link: str, device: str) -> None:
    """A UDP or TCP link's host must resolve now (a typo'd name was 30 s of silence, then
    "no heartbeat"): one :class:`InputError` line otherwise."""
    import socket

    kind, _, rest = device.partition(":")
    if kind not in ("udpout", "udpin", "tcp"):
        return
    host, _, port = rest.rpartition(":")
    try:
        socket.getaddrinfo(host, int(port))
    except (OSError, UnicodeError) as exc:
        raise InputError(f"--vehicle: cannot resolve the host of {link}: "
                         f"{getattr(exc, 'strerror', None) or exc}") from None


def _enum_name(enum: str, value: int) -> str:
    entry = mav.enums.get(enum, {}).get(value)
    name = entry.name if entry is not None else str(value)
    return name.removeprefix(enum + "_")


__all__ = ["MavlinkVehicle"]
