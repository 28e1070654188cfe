"""``swarmex uav-emulator``: a MAVLink multicopter to fly missions against without a drone.

It answers, over UDP, the part of ArduCopter's MAVLink interface that ``swarmex agent
--vehicle`` (:class:`~swarmex.net.mavlink.MavlinkVehicle`) and most ground stations use,
written with the same library (pymavlink, extra ``uav``):

* it sends ``HEARTBEAT`` (a quadrotor, autopilot ArduPilot, ArduCopter's mode numbers),
  ``SYS_STATUS`` (sensor health with the pre-arm bit, battery voltage and percent),
  ``GPS_RAW_INT``, ``GLOBAL_POSITION_INT`` (``time_boot_ms`` on the emulated clock),
  ``LOCAL_POSITION_NED`` (origin at home), ``EXTENDED_SYS_STATE``, ``HOME_POSITION``,
  ``STATUSTEXT`` and ``COMMAND_ACK``;
* it obeys ``COMMAND_LONG`` / ``COMMAND_INT`` arm and disarm (with pre-arm checks: a GPS
  fix, the mode, and an injected failure), ``DO_SET_MODE`` and ``SET_MODE`` (GUIDED, RTL,
  LAND, STABILIZE, LOITER, ...), ``NAV_TAKEOFF``, ``DO_CHANGE_SPEED``, ``NAV_RETURN_TO_LAUNCH``,
  ``NAV_LAND``, ``GET_HOME_POSITION``, and ``SET_POSITION_TARGET_LOCAL_NED`` in GUIDED;
* it flies plausibly: horizontal speed up to the commanded one with a braking curve,
  climb 2.5 m/s, descent 1.5 m/s (0.5 m/s below 10 m when landing), RTL climbs to 15 m,
  returns, lands and disarms, a copter armed on the ground for 10 s disarms itself, the
  battery drains with flight time (``--drain`` percent per minute; the seed's copters flew
  about 15 minutes), and without a ground station for 5 s in GUIDED it does what ArduPilot's
  GCS failsafe does: RTL.

Faults for dry runs and tests: ``--fail-prearm TEXT`` refuses arming with ``PreArm: TEXT``
(and reports the pre-arm bit unhealthy); ``--satellites N`` below 6 leaves it without a 3-D
fix; ``--battery`` / ``--drain`` run it low; ``--drop-link-after S`` makes it fall silent S
emulated seconds after its first take-off — it neither sends nor hears anything more — and
fly its failsafe RTL. ``--speedup F`` (at most 1000) runs the emulated clock F times faster
than the wall (as SITL's ``--speedup``): with ``swarmex serve --time-scale 1/F`` the mission
and the vehicle keep pace. It listens on one UDP port and talks to whoever sent the latest
packet; each datagram is parsed on its own (a torn one costs only itself).
"""

from __future__ import annotations

import contextlib
import math
import os
import select
import socket
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from swarmex.errors import InputError, check_number
from swarmex.net.limits import check_wall_seconds

os.environ.setdefault("MAVLINK20", "1")
from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

STABILIZE, ALT_HOLD, GUIDED, LOITER, RTL, LAND = 0, 2, 4, 5, 6, 9
MODES = {STABILIZE: "STABILIZE", ALT_HOLD: "ALT_HOLD", 3: "AUTO", GUIDED: "GUIDED",
         LOITER: "LOITER", RTL: "RTL", LAND: "LAND", 16: "POSHOLD", 17: "BRAKE"}
ARMABLE = (STABILIZE, ALT_HOLD, GUIDED, LOITER, 16)
EARTH_RADIUS = 6_378_137.0  # WGS-84 semi-major axis, for the telemetry's lat/lon only
SENSORS = (mavlink.MAV_SYS_STATUS_SENSOR_3D_GYRO | mavlink.MAV_SYS_STATUS_SENSOR_3D_ACCEL
           | mavlink.MAV_SYS_STATUS_SENSOR_3D_MAG | mavlink.MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE
           | mavlink.MAV_SYS_STATUS_SENSOR_GPS | mavlink.MAV_SYS_STATUS_SENSOR_BATTERY
           | mavlink.MAV_SYS_STATUS_PREARM_CHECK)
#: the fastest emulated clock. An emulated second is 20 physics steps of about 1 µs, so at
#: 1000x a wall second costs some 20 ms of steps and the emulator keeps pace even on a slow
#: board; at 1e12 each loop's catch-up took hours and --timeout was never reached
SPEEDUP_MAX = 1000.0


@dataclass
class EmulatorConfig:
    speedup: float = 1.0  # emulated seconds per wall second
    battery: float = 100.0  # percent at start
    drain: float = 6.0  # percent per minute of flight (a battery lasts ~15 min, as the seed's)
    satellites: int = 12
    fail_prearm: str | None = None  # arming refused with "PreArm: <text>"
    drop_link_after: float | None = None  # emulated seconds after the first take-off
    home: tuple[float, float, float] = (43.268304, -79.911135, 100.0)  # seed 000's field
    speed: float = 5.0  # default horizontal speed (ArduCopter's WPNAV_SPEED), m/s
    max_speed: float = 20.0  # cap on DO_CHANGE_SPEED, m/s
    rate: float = 25.0  # telemetry messages of each kind per wall second
    gcs_timeout: float = 5.0  # wall seconds without a ground station before failsafe RTL
    idle_exit: float | None = None  # exit this long on the ground after the GCS fell silent
    timeout: float | None = None  # exit after this many wall seconds in any case
    sysid: int = 1

    def __post_init__(self) -> None:
        check_number(self.speedup, "--speedup", above=0)
        if self.speedup > SPEEDUP_MAX:
            raise InputError(f"--speedup must be > 0 and at most {SPEEDUP_MAX:g} (emulated"
                             f" seconds per wall second), got {self.speedup:g}")
        if not 0 <= self.battery <= 100:
            raise InputError(f"--battery must be a percentage (0..100), got {self.battery}")
        check_number(self.drain, "--drain", at_least=0)
        if not 0 <= self.satellites <= 60:
            raise InputError(f"--satellites must be in 0..60, got {self.satellites}")
        if self.drop_link_after is not None:
            check_number(self.drop_link_after, "--drop-link-after", at_least=0)
        lat, lon, alt = self.home
        if not (-90 < lat < 90 and -180 <= lon <= 180):
            raise InputError(f"--home: latitude/longitude out of range: {lat}, {lon}")
        if not (math.isfinite(alt) and -500.0 <= alt <= 9000.0):  # telemetry holds mm in int32
            raise InputError(f"--home: altitude must be a number of metres in -500..9000, "
                             f"got {alt}")
        for name, flag in (("idle_exit", "--exit-when-idle"), ("timeout", "--timeout")):
            v = getattr(self, name)
            if v is not None:  # wall seconds, bounded as every net command's
                check_wall_seconds(v, flag)


def hdop_of(satellites: int) -> float:
    """A plausible HDOP for ``satellites`` in view: 1.93 at 6 (the least a 3-D fix is
    reported with here, which passes the agent's default --max-hdop 2), 1.27 at 12."""
    return 0.6 + 8.0 / max(satellites, 1)


class Copter:
    """The emulated airframe and the autopilot's flight-mode logic, on an emulated clock."""

    ACCEL = 2.5  # m/s², the braking curve
    UP, DOWN, LAND_SLOW = 2.5, 1.5, 0.5  # m/s
    RTL_ALT = 15.0  # m
    DISARM_DELAY = 10.0  # s armed on the ground before the autopilot disarms

    def __init__(self, cfg: EmulatorConfig, say: Callable[[int, str], None]) -> None:
        self.cfg = cfg
        self.say = say  # (MAV_SEVERITY, text): a STATUSTEXT
        self.t = 0.0
        self.n = self.e = self.alt = 0.0
        self.vn = self.ve = self.vup = 0.0
        self.armed = False
        self.landed = True
        self.mode = STABILIZE
        self.target: tuple[float, float, float] | None = None
        self.speed = cfg.speed
        self.battery = cfg.battery
        self.idle = 0.0
        self.rtl_stage = ""
        self.first_takeoff: float | None = None
        self.flights = 0
        self.changed = False  # armed or mode changed since the last heartbeat

    # ---- the autopilot's answers
    def prearm_problem(self) -> str | None:
        if self.cfg.fail_prearm:
            return f"PreArm: {self.cfg.fail_prearm}"
        if self.cfg.satellites < 6:
            return "PreArm: GPS 1: Bad fix"
        if self.battery < 10:
            return "PreArm: Battery 1 below minimum arming capacity"
        return None

    def arm(self) -> str | None:
        if self.armed:
            return None
        problem = self.prearm_problem()
        if problem is not None:
            return problem
        if self.mode not in ARMABLE:
            return f"Arm: Mode not armable ({MODES.get(self.mode, self.mode)})"
        self.armed, self.idle, self.changed = True, 0.0, True
        self.say(mavlink.MAV_SEVERITY_INFO, "Arming motors")
        return None

    def disarm(self, force: bool = False) -> bool:
        if not self.armed:
            return True
        if not self.landed and not force:
            return False
        self.armed = False
        self.changed = True
        self.target = None
        self.say(mavlink.MAV_SEVERITY_INFO, "Disarming motors")
        return True

    def set_mode(self, mode: int) -> bool:
        if mode not in MODES:
            return False
        if mode == GUIDED and self.cfg.satellites < 6:
            return False  # no position estimate: GUIDED refused
        if mode != self.mode:
            self.mode = mode
            self.changed = True
            self.rtl_stage = "climb" if mode == RTL else ""
            if mode in (LOITER, STABILIZE, ALT_HOLD, 16):
                self.target = (self.n, self.e, self.alt)
            self.say(mavlink.MAV_SEVERITY_INFO, f"Mode {MODES[mode]}")
        return True

    def takeoff(self, alt: float) -> bool:
        if not (self.armed and self.mode == GUIDED and self.landed and alt > 0):
            return False
        self.landed = False
        self.target = (self.n, self.e, alt)
        if self.first_takeoff is None:
            self.first_takeoff = self.t
        self.flights += 1
        self.say(mavlink.MAV_SEVERITY_INFO, f"Takeoff to {alt:.1f} m")
        return True

    def set_target(self, n: float, e: float, alt: float) -> bool:
        if self.mode != GUIDED or not self.armed or self.landed:
            return False
        self.target = (n, e, max(alt, 0.0))
        return True

    # ---- physics
    def step(self, dt: float, until: float | None = None) -> None:
        """Advance the emulated clock by ``dt`` seconds in steps of at most 50 ms; with
        ``until`` (a ``time.monotonic()`` value), stop catching up once the wall clock passes
        it, so that the caller's --timeout holds however far behind the clock has fallen."""
        while dt > 1e-9:
            h = min(dt, 0.05)
            self._step(h)
            dt -= h
            if until is not None and time.monotonic() >= until:
                return

    def _step(self, h: float) -> None:
        self.t += h
        n0, e0, a0 = self.n, self.e, self.alt
        if self.armed and self.landed:
            self.idle += h
            if self.idle >= self.DISARM_DELAY:
                self.disarm()
        elif self.armed:
            if self.mode == GUIDED and self.target is not None:
                self._toward(*self.target, h)
            elif self.mode == RTL:
                self._rtl(h)
            elif self.mode == LAND:
                self._descend(h)
            elif self.target is not None:  # LOITER and the others: hold where it was
                self._toward(*self.target, h)
        self.vn, self.ve, self.vup = (self.n - n0) / h, (self.e - e0) / h, (self.alt - a0) / h
        if self.armed:
            ground = math.hypot(self.vn, self.ve)
            rate = self.cfg.drain / 60.0 * (1.0 + 0.25 * ground / 5.0)
            self.battery = max(0.0, self.battery - rate * h * (0.1 if self.landed else 1.0))

    def _toward(self, n: float, e: float, alt: float, h: float) -> None:
        dn, de = n - self.n, e - self.e
        d = math.hypot(dn, de)
        if d > 1e-6:
            v = min(self.speed, math.sqrt(2 * self.ACCEL * d))
            k = min(1.0, v * h / d)
            self.n += dn * k
            self.e += de * k
        dz = alt - self.alt
        if abs(dz) > 1e-6:
            rate = self.UP if dz > 0 else self.DOWN
            v = min(rate, math.sqrt(2 * self.ACCEL * abs(dz)))
            self.alt += math.copysign(min(abs(dz), v * h), dz)

    def _rtl(self, h: float) -> None:
        if self.rtl_stage == "climb":
            top = max(self.RTL_ALT, self.alt)
            self._toward(self.n, self.e, top, h)
            if self.alt >= top - 0.1:
                self.rtl_stage = "return"
        elif self.rtl_stage == "return":
            self._toward(0.0, 0.0, self.alt, h)
            if math.hypot(self.n, self.e) < 0.5:
                self.rtl_stage = "land"
        else:
            self._descend(h)

    def _descend(self, h: float) -> None:
        rate = self.DOWN if self.alt > 10.0 else self.LAND_SLOW
        self.alt = max(0.0, self.alt - rate * h)
        if self.alt <= 0.0:
            self.landed = True
            self.say(mavlink.MAV_SEVERITY_INFO, "Land complete")
            self.disarm()

    # ---- what the telemetry reports
    def latlon(self) -> tuple[float, float]:
        """Home + the local offset on a tangent plane: metre-scale telemetry only (no grid
        is built from it)."""
        lat0, lon0, _ = self.cfg.home
        lat = lat0 + math.degrees(self.n / EARTH_RADIUS)
        lon = lon0 + math.degrees(self.e / (EARTH_RADIUS * math.cos(math.radians(lat0))))
        return lat, lon

    def landed_state(self) -> int:
        if self.landed:
            return mavlink.MAV_LANDED_STATE_ON_GROUND
        if self.mode == LAND or (self.mode == RTL and self.rtl_stage == "land"):
            return mavlink.MAV_LANDED_STATE_LANDING
        return mavlink.MAV_LANDED_STATE_IN_AIR


class _Out:
    """The MAVLink encoder's file: sends each packet to the latest ground station."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = sock
        self.addr: tuple[str, int] | None = None
        self.enabled = True

    def write(self, buf: bytes) -> None:
        if self.addr is not None and self.enabled:
            with contextlib.suppress(OSError):
                self.sock.sendto(buf, self.addr)


def parse_listen(text: str) -> tuple[str, int]:
    """``udp:HOST:PORT`` → (host, port); port 0 picks a free one."""
    if not text.startswith("udp:"):
        raise InputError(f"--listen: expected udp:HOST:PORT, got {text!r}")
    host, sep, port = text[4:].rpartition(":")
    if not sep or not host or not port.isdigit() or not 0 <= int(port) <= 65535:
        raise InputError(f"--listen: expected udp:HOST:PORT, got {text!r}")
    return host, int(port)


class Emulator:
    def __init__(self, host: str, port: int, cfg: EmulatorConfig,
                 say: Callable[[str], object] = print) -> None:
        self.cfg = cfg
        self.log = say
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            self.sock.bind((host, port))
        except OSError as exc:
            self.sock.close()
            raise InputError(f"--listen: cannot bind udp:{host}:{port}: {exc}") from None
        self.sock.setblocking(False)
        self.host, self.port = self.sock.getsockname()[:2]
        self.out = _Out(self.sock)
        self.mav = mavlink.MAVLink(self.out, srcSystem=cfg.sysid, srcComponent=1)
        self.mav.robust_parsing = True
        self.copter = Copter(cfg, self._statustext)
        self.link_up = True
        self.last_gcs: float | None = None
        self.failsafe = False
        self.received = 0
        self.sent_texts: list[str] = []
        self.prearm_said: float | None = None

    @property
    def address(self) -> str:
        return f"udp:{self.host}:{self.port}"

    def _statustext(self, severity: int, text: str) -> None:
        self.sent_texts.append(text)
        self.log(f"swarmex uav-emulator: {text}")
        self.mav.statustext_send(severity, text.encode()[:50])

    # ------------------------------------------------------------------ loop
    def run(self) -> int:
        cfg = self.cfg
        self.log(f"swarmex uav-emulator: listening on {self.address} (speedup {cfg.speedup:g})")
        start = last = time.monotonic()
        # the wall time to leave at: checked inside the catch-up too (copter.step), not only
        # between loops, which a long catch-up postponed by seconds
        deadline = None if cfg.timeout is None else start + cfg.timeout
        period = 1.0 / cfg.rate
        next_tel = start
        next_hb = next_home = start
        try:
            while True:
                now = time.monotonic()
                if deadline is not None and now >= deadline:
                    self.log("swarmex uav-emulator: --timeout reached")
                    return 0
                if self._idle_done(now):
                    self.log("swarmex uav-emulator: on the ground, no ground station: exiting")
                    return 0
                wait = max(0.0, min(next_tel, next_hb) - now)
                readable, _, _ = select.select([self.sock], [], [], wait)
                if readable:
                    self._receive(time.monotonic())
                now = time.monotonic()
                self.copter.step((now - last) * cfg.speedup, until=deadline)
                last = now
                self._faults(now)
                self._report_prearm()
                if now >= next_hb or self.copter.changed:
                    # 1 Hz on the emulated clock (as SITL's scheduler), and on every change
                    next_hb = now + max(period, 1.0 / cfg.speedup)
                    self.copter.changed = False
                    self._heartbeat()
                if now >= next_home:
                    next_home = now + 2.0
                    self._home()
                if now >= next_tel:
                    next_tel = now + period
                    self._telemetry()
        finally:
            self.sock.close()

    def _report_prearm(self) -> None:
        """As ArduPilot does while disarmed: the failing pre-arm check, every 30 s (and as
        soon as a ground station is there)."""
        c = self.copter
        if c.armed or self.out.addr is None or not self.link_up:
            return
        problem = c.prearm_problem()
        if problem is None or (self.prearm_said is not None and c.t - self.prearm_said < 30.0):
            return
        self.prearm_said = c.t
        self._statustext(mavlink.MAV_SEVERITY_CRITICAL, problem)

    def _idle_done(self, now: float) -> bool:
        c = self.copter
        limit = self.cfg.idle_exit
        if limit is None or c.armed or not c.landed:
            return False
        if self.last_gcs is None:  # waiting for its ground station (an agent) to come
            return False
        return now - self.last_gcs >= limit

    def _faults(self, now: float) -> None:
        c = self.copter
        drop = self.cfg.drop_link_after
        if (self.link_up and drop is not None and c.first_takeoff is not None
                and c.t - c.first_takeoff >= drop):
            self.link_up = False
            self.out.enabled = False
            self.log(f"swarmex uav-emulator: fault injection: link dropped {drop:g} s after "
                     "take-off; failsafe RTL")
            c.set_mode(RTL)
        gcs_lost = self.last_gcs is None or now - self.last_gcs > self.cfg.gcs_timeout
        if c.armed and not c.landed and c.mode == GUIDED and gcs_lost and not self.failsafe:
            self.failsafe = True
            self.log("swarmex uav-emulator: no ground station: failsafe RTL")
            c.set_mode(RTL)

    # ------------------------------------------------------------------ receiving
    def _receive(self, now: float) -> None:
        for _ in range(1000):
            try:
                data, addr = self.sock.recvfrom(65535)
            except (BlockingIOError, InterruptedError):
                return
            except OSError:
                return
            if not self.link_up:
                continue  # the radio is dead: nothing gets through
            self.out.addr = addr
            for m in self._parse(data):
                self.received += 1
                self._on_message(m, now)

    def _parse(self, data: bytes) -> list[Any]:
        """The messages of one datagram, parsed on its own.

        UDP keeps message boundaries (a MAVLink sender puts whole messages in each
        datagram), so a torn or garbage datagram costs only itself. One stream parser shared
        across datagrams kept a torn header's claim (say, 255 bytes to come) and ate the
        valid messages of the datagrams after it; a fresh parser per datagram (microseconds,
        at a ground station's few dozen datagrams a second) carries nothing over. What the
        datagram held before an error still counts."""
        parser = mavlink.MAVLink(None, srcSystem=self.cfg.sysid, srcComponent=1)
        parser.robust_parsing = True
        msgs: list[Any] = []
        try:  # parse_buffer's loop, keeping the messages parsed before an exception
            m = parser.parse_char(data)
            while m is not None:
                msgs.append(m)
                m = parser.parse_char(b"")
        except Exception:  # pymavlink raises MAVError and friends on garbage
            pass
        return msgs

    def _on_message(self, m: Any, now: float) -> None:
        kind = m.get_type()
        if kind == "BAD_DATA":
            return
        self.last_gcs = now
        self.failsafe = False
        c = self.copter
        if kind in ("COMMAND_LONG", "COMMAND_INT"):
            self._on_command(m)
        elif kind == "SET_MODE":
            ok = c.set_mode(int(m.custom_mode))
            if not ok:
                self._statustext(mavlink.MAV_SEVERITY_WARNING, "Flight mode change failed")
        elif kind == "SET_POSITION_TARGET_LOCAL_NED":
            if m.type_mask & 0b111:
                return  # position ignored: velocity control is not emulated
            c.set_target(float(m.x), float(m.y), -float(m.z))

    def _on_command(self, m: Any) -> None:
        c = self.copter
        cmd = int(m.command)
        p = [float(getattr(m, f"param{i}")) for i in range(1, 5)]
        p7 = float(m.z if m.get_type() == "COMMAND_INT" else m.param7)
        ok = mavlink.MAV_RESULT_ACCEPTED
        bad = mavlink.MAV_RESULT_FAILED
        result = ok
        if cmd == mavlink.MAV_CMD_COMPONENT_ARM_DISARM:
            if p[0] >= 0.5:
                problem = c.arm()
                if problem is not None:
                    self._statustext(mavlink.MAV_SEVERITY_CRITICAL, problem)
                    result = bad
            elif not c.disarm(force=int(p[1]) == 21196):
                result = bad
        elif cmd == mavlink.MAV_CMD_DO_SET_MODE:
            result = ok if c.set_mode(int(p[1])) else bad
        elif cmd == mavlink.MAV_CMD_NAV_TAKEOFF:
            result = ok if c.takeoff(p7) else bad
        elif cmd == mavlink.MAV_CMD_DO_CHANGE_SPEED:
            if p[1] > 0:
                c.speed = min(p[1], self.cfg.max_speed)
        elif cmd == mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH:
            result = ok if c.set_mode(RTL) else bad
        elif cmd == mavlink.MAV_CMD_NAV_LAND:
            result = ok if c.set_mode(LAND) else bad
        elif cmd == mavlink.MAV_CMD_GET_HOME_POSITION:
            self._home()
        elif cmd in (mavlink.MAV_CMD_SET_MESSAGE_INTERVAL, mavlink.MAV_CMD_REQUEST_MESSAGE):
            pass  # everything streams at --rate anyway
        else:
            result = mavlink.MAV_RESULT_UNSUPPORTED
        self.mav.command_ack_send(cmd, result)

    # ------------------------------------------------------------------ sending
    def _heartbeat(self) -> None:
        c = self.copter
        base = (mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | mavlink.MAV_MODE_FLAG_STABILIZE_ENABLED
                | (mavlink.MAV_MODE_FLAG_GUIDED_ENABLED if c.mode == GUIDED else 0)
                | (mavlink.MAV_MODE_FLAG_SAFETY_ARMED if c.armed else 0))
        state = mavlink.MAV_STATE_ACTIVE if c.armed else mavlink.MAV_STATE_STANDBY
        self.mav.heartbeat_send(mavlink.MAV_TYPE_QUADROTOR, mavlink.MAV_AUTOPILOT_ARDUPILOTMEGA,
                                base, c.mode, state)

    def _home(self) -> None:
        lat, lon, alt = self.cfg.home
        self.mav.home_position_send(int(lat * 1e7), int(lon * 1e7), int(alt * 1000), 0, 0, 0,
                                    [1.0, 0.0, 0.0, 0.0], 0, 0, 0)

    def _telemetry(self) -> None:
        c, cfg = self.copter, self.cfg
        boot_ms = int(c.t * 1000) & 0xFFFFFFFF
        health = SENSORS
        if c.prearm_problem() is not None:
            health &= ~mavlink.MAV_SYS_STATUS_PREARM_CHECK
        cells = 4
        volts = cells * (3.3 + 0.9 * c.battery / 100.0)
        current = (1500 if not c.landed else 50) if c.armed else 0
        self.mav.sys_status_send(SENSORS, SENSORS, health, 250, int(volts * 1000), current,
                                 int(round(c.battery)), 0, 0, 0, 0, 0, 0)
        lat, lon = c.latlon()
        fix = 3 if cfg.satellites >= 6 else (2 if cfg.satellites >= 4 else 0)
        hdop = hdop_of(cfg.satellites)
        self.mav.gps_raw_int_send(int(c.t * 1e6), fix, int(lat * 1e7), int(lon * 1e7),
                                  int((cfg.home[2] + c.alt) * 1000), int(hdop * 100), 120,
                                  int(math.hypot(c.vn, c.ve) * 100), 0, cfg.satellites)
        hdg = int(math.degrees(math.atan2(c.ve, c.vn)) % 360 * 100)
        self.mav.global_position_int_send(boot_ms, int(lat * 1e7), int(lon * 1e7),
                                          int((cfg.home[2] + c.alt) * 1000), int(c.alt * 1000),
                                          int(c.vn * 100), int(c.ve * 100), int(-c.vup * 100),
                                          hdg)
        self.mav.local_position_ned_send(boot_ms, c.n, c.e, -c.alt, c.vn, c.ve, -c.vup)
        self.mav.extended_sys_state_send(mavlink.MAV_VTOL_STATE_UNDEFINED, c.landed_state())


def run_emulator(listen: str, cfg: EmulatorConfig, say: Callable[[str], object] = print) -> int:
    host, port = parse_listen(listen)
    return Emulator(host, port, cfg, say).run()


__all__ = ["Copter", "Emulator", "EmulatorConfig", "parse_listen", "run_emulator"]
