"""Vehicles: what a networked traversal agent flies (seed 000 §4.3).

Seed 000's ``client.py`` flew the same MADGTA code on a virtual UAV or on a real multicopter
(Pixhawk through DroneKit), "switched ... with a change of a value of one variable", through
a handful of functions: ``uavPreARMcheck()``, ``uavARM()``, ``uavTakeOff(altitude)``,
``uavGoToCell`` / ``uavGoToPoint``, ``uavDoJob()``, ``uavRTL()``, ``uavLAND()``,
``uavDISARM()``. :class:`Vehicle` is that interface:

================================  =========================================================
``preflight(plan)``               the safety pre-arm checks (seed: ``C02`` only if they pass)
``arm()``                         arm the motors (seed: ``C03`` once armed)
``takeoff(altitude)``             take off to the working altitude above home
``goto(position, speed)``         fly to a position (metres north / east of home, altitude)
``job(seconds)``                  do the job where it is (the seed's field pattern: a 2 m
                                  altitude change, held for the job's time)
``return_and_land()``             return to launch, land, disarm (phases ``returning``,
                                  ``landing``; the agent sends C10 and C11 on them)
``position()``, ``battery()``     where it is (a :class:`Position`), percent of charge left
``fault()``                       a reason it can no longer be flown (lost link), or None
================================  =========================================================

Every command returns at once with a :class:`Task` that :meth:`Vehicle.update` advances: the
agent's loop is a poll loop serving a server socket (and, with ``--count``, many agents),
so nothing here blocks. A new command replaces the one before (the seed's flight is one
step at a time).

Two vehicles: :class:`SimulatedVehicle`, the virtual UAV of ``swarmex agent`` without
``--vehicle`` — every command is done at once and pre-arm checks always pass (the thesis:
"with virtual agents, we assume that every such a stage goes successfully"), so mission
times stay the computed ones and a simulated agent behaves exactly as before this module
existed; and :class:`~swarmex.net.mavlink.MavlinkVehicle` (pymavlink, extra ``uav``), which
flies an ArduPilot copter, real or emulated (``swarmex uav-emulator``).

Where the nodes are: :class:`FlightPlan` puts the mission's grid in local metres around the
vehicle's home, which is its nest: node (x, y) is ``(x - x_nest) * edge`` metres east and
``(y_nest - y) * edge`` metres north of home (rows grow southwards, as a map is drawn with
north up), ``edge`` = the agent's ``--edge-length``, else the server's (``serve
--edge-length``, which the mission data carries), else 6.67 m (the thesis's 2.22 s edge at
3 m/s); the two options, when both given, must agree. So any grid mission can be flown or
emulated, each vehicle placed on its nest's spot. On a GPS grid (``serve --center``) nodes
are geodesic offsets from the nest's latitude and longitude, and the pre-arm checks refuse
a vehicle standing farther than ``--nest-radius`` from it.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING

import numpy as np

from swarmex.errors import InputError
from swarmex.net.limits import check_wall_seconds

if TYPE_CHECKING:
    from swarmex.net.traversal import Mission

RUNNING, DONE, FAILED = "running", "done", "failed"
#: metres between grid neighbours when neither the agent nor the server says: the thesis's
#: 2.22 s edge at 3 m/s
DEFAULT_EDGE = 6.67

#: what a vehicle's description may hold (sent to the server in C01: it is on the wire)
Info = dict[str, str | int | float | bool]


@dataclass
class Task:
    """One vehicle command in progress: ``running`` until ``done`` or ``failed``
    (``reason`` says why); ``phase`` names the part under way (``returning``, ``landing``)."""

    name: str
    state: str = RUNNING
    phase: str = ""
    reason: str = ""

    @property
    def done(self) -> bool:
        return self.state == DONE

    @property
    def failed(self) -> bool:
        return self.state == FAILED

    @property
    def running(self) -> bool:
        return self.state == RUNNING

    def finish(self) -> Task:
        if self.state == RUNNING:
            self.state = DONE
        return self

    def fail(self, reason: str) -> Task:
        if self.state == RUNNING:
            self.state, self.reason = FAILED, reason
        return self


@dataclass(frozen=True)
class Position:
    """Metres north and east of home, and metres above it."""

    north: float
    east: float
    altitude: float

    def horizontal_distance(self, other: Position) -> float:
        return math.hypot(self.north - other.north, self.east - other.east)


@dataclass(frozen=True)
class Safety:
    """The limits the agent flies a real vehicle by (``swarmex agent`` options; docs/uav.md)."""

    # metres between grid neighbours: None takes the server's --edge-length, else DEFAULT_EDGE
    edge_length: float | None = None
    min_altitude: float = 5.0  # a mission altitude below this flies at this
    max_altitude: float = 120.0  # refuse a mission above this (the usual legal ceiling)
    max_speed: float = 10.0  # cap on the commanded ground speed, m/s
    max_distance: float = 500.0  # refuse a mission with a node farther from home than this
    min_satellites: int = 6  # pre-arm: the seed's "5-6 satellites" gave a bad fix
    max_hdop: float = 2.0  # pre-arm: horizontal dilution of precision
    arm_battery: float = 60.0  # pre-arm: percent of charge needed to take off
    min_battery: float = 25.0  # in flight: below this the agent hands its id back and lands
    link_timeout: float = 3.0  # wall seconds without telemetry: the link is lost
    task_timeout: float = 30.0  # wall seconds a command may take beyond its expected time
    arrive_radius: float = 1.0  # metres: at a position when this close (and as close in height)
    job_climb: float = 2.0  # metres: the job's altitude change (seed §5.2.2)
    nest_radius: float = 10.0  # pre-arm on a GPS grid: metres the vehicle may stand off its nest

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if v is None and f.name == "edge_length":
                continue
            if not (isinstance(v, int | float) and math.isfinite(v) and v >= 0):
                raise InputError(f"--{f.name.replace('_', '-')} must be a number >= 0, got {v}")
        for name in ("edge_length", "max_speed", "link_timeout", "task_timeout",
                     "arrive_radius", "max_altitude", "nest_radius"):
            v = getattr(self, name)
            if v is not None and not v > 0:
                raise InputError(f"--{name.replace('_', '-')} must be > 0")
        for name in ("link_timeout", "task_timeout"):  # wall seconds, as every net command's
            check_wall_seconds(getattr(self, name), f"--{name.replace('_', '-')}")
        if self.min_altitude > self.max_altitude:
            raise InputError(f"--min-altitude ({self.min_altitude:g} m) is above --max-altitude"
                             f" ({self.max_altitude:g} m)")
        if self.min_battery > 100 or self.arm_battery > 100:
            raise InputError("--min-battery and --arm-battery are percentages (0..100)")
        if self.min_battery >= self.arm_battery:
            raise InputError(
                f"--min-battery ({self.min_battery:g}) must be below --arm-battery "
                f"({self.arm_battery:g})"
            )


class FlightPlan:
    """One agent's mission in its vehicle's frame: node positions around home, altitude,
    ground speed, and the checks a mission must pass before a real vehicle flies it."""

    def __init__(self, mission: Mission, me: int, safety: Safety) -> None:
        spec = mission.specs[me - 1]
        self.safety = safety
        self.home_node = spec.nest
        self.pos = mission.world.graph.pos
        self.free = ~mission.world.blocked
        self.mission_edge = mission.edge_length  # serve --edge-length, if given
        self.edge = (safety.edge_length if safety.edge_length is not None
                     else self.mission_edge if self.mission_edge is not None else DEFAULT_EDGE)
        self.altitude = max(spec.altitude, safety.min_altitude)
        self.mission_altitude = spec.altitude
        # mission speeds are length units per second; a unit is one grid edge here
        self.wanted_speed = spec.travel_speed / mission.unit_length * self.edge
        self.speed = min(self.wanted_speed, safety.max_speed)
        # a GPS grid (serve --center): nodes sit at their own latitude and longitude, and the
        # plan's metres are geodesic offsets from the nest's (the vehicle's home must be at
        # its nest); otherwise nodes sit in local metres around home, one edge apart
        self.latlon = mission.latlon
        self.geo = mission.latlon(self.home_node) is not None
        if self.geo:  # mission speeds are metres per second on a GPS grid
            self.wanted_speed = spec.travel_speed
            self.speed = min(self.wanted_speed, safety.max_speed)

    def position(self, node: int) -> Position:
        if self.geo:
            north, east = self._geodesic_offset(node)
            return Position(north, east, self.altitude)
        hx, hy = self.pos[self.home_node]
        x, y = self.pos[node]
        return Position(float((hy - y) * self.edge), float((x - hx) * self.edge), self.altitude)

    def _geodesic_offset(self, node: int) -> tuple[float, float]:
        """Metres north and east of the nest along the WGS84 geodesic (pyproj)."""
        from swarmex.worlds.geo import north_east

        home, there = self.latlon(self.home_node), self.latlon(node)
        assert home is not None and there is not None
        return north_east(home, there)

    def nest_latlon(self) -> tuple[float, float] | None:
        """Where the vehicle must stand (its nest) on a GPS grid, else None."""
        return self.latlon(self.home_node) if self.geo else None

    def farthest(self) -> float:
        """Metres from home to the farthest free node."""
        if self.geo:
            nodes = np.flatnonzero(self.free)
            return max((math.hypot(*self._geodesic_offset(int(v))) for v in nodes), default=0.0)
        d = (self.pos[self.free] - self.pos[self.home_node]) * self.edge
        return float(np.hypot(d[:, 0], d[:, 1]).max()) if d.size else 0.0

    def problems(self) -> list[str]:
        s = self.safety
        out = []
        if self.altitude > s.max_altitude:
            out.append(f"mission altitude {self.altitude:g} m is above the "
                       f"{s.max_altitude:g} m limit")
        far = self.farthest()
        if far > s.max_distance:
            scale = "" if self.geo else f" (--edge-length {self.edge:g} m)"
            out.append(f"a node is {far:.0f} m from home, beyond the {s.max_distance:g} m limit"
                       + scale)
        if (s.edge_length is not None and self.mission_edge is not None
                and not math.isclose(s.edge_length, self.mission_edge)):
            out.append(f"--edge-length {s.edge_length:g} m differs from the mission's "
                       f"{self.mission_edge:g} m (serve --edge-length): give the same, or "
                       "leave the agent's out")
        return out

    def notes(self) -> list[str]:
        """What the agent tells its operator about the plan before flying it."""
        nest = self.nest_latlon()
        where = (f"GPS grid, nest node {self.home_node} at {nest[0]:.6f},{nest[1]:.6f}"
                 if nest is not None else f"grid edge {self.edge:g} m")
        out = [f"{where}, altitude {self.altitude:g} m, ground speed "
               f"{self.speed:.2f} m/s, farthest node {self.farthest():.0f} m from home"]
        if self.altitude != self.mission_altitude:
            out.append(f"the mission's altitude {self.mission_altitude:g} m is below "
                       f"--min-altitude: flying at {self.altitude:g} m")
        if self.speed < self.wanted_speed:
            out.append(f"the mission's speed {self.wanted_speed:.2f} m/s is capped at "
                       f"--max-speed {self.safety.max_speed:g} m/s (the mission will lag)")
        return out


class Vehicle(ABC):
    """What an agent flies; see the module docstring. ``time_scale`` is wall seconds per
    vehicle second (the agent sets the mission's), used for how long a command may take."""

    kind = "vehicle"
    time_scale = 1.0

    @abstractmethod
    def describe(self) -> Info:
        """``kind`` plus whatever identifies the vehicle (link, autopilot, type)."""

    def fileno(self) -> int | None:
        """A file descriptor to wake the agent's poll loop on telemetry (None: none)."""
        return None

    def heard(self) -> bool:
        """Whether the vehicle has answered at all (its first heartbeat)."""
        return True

    @abstractmethod
    def update(self, now: float) -> None:
        """Read telemetry and advance the current command (``now``: ``time.monotonic()``)."""

    @abstractmethod
    def preflight(self, plan: FlightPlan) -> Task: ...

    @abstractmethod
    def arm(self) -> Task: ...

    @abstractmethod
    def takeoff(self, altitude: float) -> Task: ...

    @abstractmethod
    def goto(self, target: Position, speed: float) -> Task: ...

    @abstractmethod
    def job(self, seconds: float) -> Task: ...

    @abstractmethod
    def return_and_land(self) -> Task: ...

    @abstractmethod
    def position(self) -> Position | None: ...

    @abstractmethod
    def battery(self) -> float | None: ...

    def fault(self) -> str | None:
        return None

    def other_control(self) -> str | None:
        """Who flies the vehicle if not its agent (a pilot, a failsafe), else None: the
        agent then commands it no more."""
        return None

    def disarm(self) -> Task:
        """Stop the motors of a vehicle on the ground."""
        return Task("disarm").finish()

    def armed_on_ground(self) -> bool:
        """Armed but not flying (a take-off that failed on the ground)."""
        return False

    @abstractmethod
    def airborne(self) -> bool: ...

    def close(self) -> None:
        return None


class SimulatedVehicle(Vehicle):
    """The virtual UAV: every command is done at once (the mission's computed times are its
    flight), pre-arm checks always pass, the battery never drains (the thesis's assumption:
    "an agent has no battery limit")."""

    kind = "simulated"

    def __init__(self) -> None:
        self._pos = Position(0.0, 0.0, 0.0)
        self._altitude = 0.0
        self._flying = False

    def describe(self) -> Info:
        return {"kind": self.kind}

    def update(self, now: float) -> None:
        return None

    def preflight(self, plan: FlightPlan) -> Task:
        return Task("preflight").finish()

    def arm(self) -> Task:
        return Task("arm").finish()

    def takeoff(self, altitude: float) -> Task:
        self._flying = True
        self._altitude = altitude
        self._pos = Position(self._pos.north, self._pos.east, altitude)
        return Task("takeoff").finish()

    def goto(self, target: Position, speed: float) -> Task:
        self._pos = target
        return Task("goto").finish()

    def job(self, seconds: float) -> Task:
        return Task("job").finish()

    def return_and_land(self) -> Task:
        self._pos = Position(0.0, 0.0, 0.0)
        self._flying = False
        return Task("return_and_land", phase="landed").finish()

    def position(self) -> Position:
        return self._pos

    def battery(self) -> float:
        return 100.0

    def airborne(self) -> bool:
        return self._flying


#: how ``--vehicle`` names a link, and what pymavlink calls it
LINK_FORMS = (
    ("udp:", "udpout:", "udp:HOST:PORT — the vehicle listens there (swarmex uav-emulator, "
     "mavlink-router, MAVProxy --out udpin:...)"),
    ("udpin:", "udpin:", "udpin:HOST:PORT — listen here; the vehicle sends to it "
     "(MAVProxy --out udp:HOST:PORT)"),
    ("tcp:", "tcp:", "tcp:HOST:PORT — a TCP MAVLink server (ArduPilot SITL's 5760)"),
    ("serial:", "", "serial:DEVICE[:BAUD] — the flight controller's port (/dev/serial0:921600)"),
)


def parse_link(link: str) -> tuple[str, int]:
    """``--vehicle``'s value as (pymavlink device, baud); :class:`InputError` if malformed."""
    text = link.strip()
    if text.startswith("/dev/"):
        text = "serial:" + text
    for prefix, device, _ in LINK_FORMS:
        if not text.startswith(prefix):
            continue
        rest = text[len(prefix):]
        if prefix == "serial:":
            dev, _sep, baud = rest.partition(":")
            if not dev or (baud and not baud.isdigit()):
                break
            return dev, int(baud) if baud else 921600
        host, sep, port = rest.rpartition(":")
        # one host:port (pymavlink takes no IPv6 literal and no third field); port 0 would
        # listen where no vehicle can be told to send
        if (not sep or not host or ":" in host or not port.isdigit()
                or not 0 < int(port) <= 65535):
            break
        return device + rest, 115200
    forms = ", ".join(f[2].split(" ")[0] for f in LINK_FORMS)
    raise InputError(f"--vehicle: expected one of {forms}; got {link!r}")


__all__ = [
    "DONE",
    "FAILED",
    "RUNNING",
    "FlightPlan",
    "Info",
    "Position",
    "Safety",
    "SimulatedVehicle",
    "Task",
    "Vehicle",
    "parse_link",
]
