"""Vehicles: the simulated one, the flight plan, and the MAVLink vehicle against the emulator.

The emulator (``swarmex uav-emulator``'s :class:`Emulator`) runs on a thread in this process,
bound to 127.0.0.1 on a free UDP port, with a bounded ``timeout`` and an emulated clock 50x
the wall's; every wait below is bounded.
"""

from __future__ import annotations

import socket
import threading
import time

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.traversal import uniform_agents
from swarmex.net.agent import open_vehicle
from swarmex.net.traversal import Mission
from swarmex.net.vehicle import (
    FlightPlan,
    Position,
    Safety,
    SimulatedVehicle,
    Task,
    Vehicle,
    parse_link,
)
from swarmex.worlds import GridWorld

pytestmark = pytest.mark.timeout(60)

SPEEDUP = 50.0


def _mission(altitude: float = 0.0) -> Mission:
    free = np.ones((3, 4), dtype=bool)  # 4 columns (x), 3 rows (y)
    specs = uniform_agents([5, 0], 2.22, 10.0, altitude=altitude)  # agent 1's nest: (1, 1)
    return Mission(GridWorld(free), specs, time_scale=1 / SPEEDUP)


def test_simulated_vehicle_does_everything_at_once():
    v = SimulatedVehicle()
    plan = FlightPlan(_mission(), 1, Safety())
    for task in (v.preflight(plan), v.arm(), v.takeoff(5.0), v.goto(plan.position(0), 3.0),
                 v.job(10.0), v.return_and_land()):
        assert isinstance(task, Task) and task.done and not task.failed
    assert v.battery() == 100.0 and v.fault() is None and not v.airborne()
    assert v.describe() == {"kind": "simulated"}
    assert isinstance(open_vehicle(None), SimulatedVehicle)


def test_flight_plan_puts_the_grid_around_home_north_up():
    plan = FlightPlan(_mission(), 1, Safety(edge_length=10.0))
    assert plan.position(5) == Position(0.0, 0.0, 5.0)  # home: the nest, min altitude 5 m
    assert plan.position(6) == Position(0.0, 10.0, 5.0)  # one column right: east
    assert plan.position(1) == Position(10.0, 0.0, 5.0)  # one row up: north
    assert plan.position(11).north == -10.0 and plan.position(11).east == 20.0
    assert plan.speed == pytest.approx(10.0 / 2.22)  # an edge per travel time
    assert plan.farthest() == pytest.approx(np.hypot(10.0, 20.0))
    assert plan.problems() == []
    assert FlightPlan(_mission(altitude=12.0), 1, Safety()).altitude == 12.0
    far = FlightPlan(_mission(altitude=150.0), 1, Safety(edge_length=400.0))
    problems = far.problems()
    assert any("above the 120 m limit" in p for p in problems)
    assert any("beyond the 500 m limit" in p for p in problems)
    capped = FlightPlan(_mission(), 1, Safety(edge_length=100.0))
    assert capped.speed == 10.0 and any("capped" in n for n in capped.notes())


def test_links_and_limits_are_checked():
    assert parse_link("udp:127.0.0.1:14550") == ("udpout:127.0.0.1:14550", 115200)
    assert parse_link("udpin:0.0.0.0:14550")[0] == "udpin:0.0.0.0:14550"
    assert parse_link("tcp:127.0.0.1:5760")[0] == "tcp:127.0.0.1:5760"
    assert parse_link("serial:/dev/serial0:57600") == ("/dev/serial0", 57600)
    assert parse_link("/dev/ttyACM0") == ("/dev/ttyACM0", 921600)
    for bad in ("udp:127.0.0.1", "udp:127.0.0.1:0", "com3", "tcp::5760", "serial:",
                "udp:127.0.0.1:14550:5", "udp:[::1]:14550", "udpin:127.0.0.1:0",
                "tcp:127.0.0.1:5760:1"):
        with pytest.raises(InputError, match="--vehicle"):
            parse_link(bad)
    with pytest.raises(InputError, match="--min-battery"):
        Safety(min_battery=70.0, arm_battery=60.0)
    with pytest.raises(InputError, match="--edge-length"):
        Safety(edge_length=0.0)
    with pytest.raises(InputError, match="--min-altitude .200 m. is above --max-altitude"):
        Safety(min_altitude=200.0, max_altitude=100.0)


def test_the_edge_is_the_agents_else_the_servers_and_they_must_agree():
    """serve --edge-length used to be ignored by a flying agent (it flew 6.67 m edges on a
    mission of 10 m edges, without a word)."""
    m = _mission()
    assert FlightPlan(m, 1, Safety()).edge == 6.67
    m.edge_length = 10.0
    assert FlightPlan(m, 1, Safety()).edge == 10.0
    assert FlightPlan(m, 1, Safety()).position(6) == Position(0.0, 10.0, 5.0)
    assert FlightPlan(m, 1, Safety(edge_length=10.0)).problems() == []
    clash = FlightPlan(m, 1, Safety(edge_length=6.67)).problems()
    assert clash == ["--edge-length 6.67 m differs from the mission's 10 m (serve "
                     "--edge-length): give the same, or leave the agent's out"]
    assert Mission.from_wire(m.to_wire()).edge_length == 10.0


# ---------------------------------------------------------------- MAVLink, against the emulator

mavlink = pytest.importorskip("swarmex.net.mavlink")
emulator = pytest.importorskip("swarmex.net.uav_emulator")


class Emulated:
    """An emulator on a thread and a MAVLink vehicle talking to it."""

    def __init__(self, safety: Safety | None = None, speedup: float = SPEEDUP,
                 **cfg: object) -> None:
        config = emulator.EmulatorConfig(speedup=speedup, timeout=40.0, **cfg)
        self.emu = emulator.Emulator("127.0.0.1", 0, config, say=lambda s: None)
        self.thread = threading.Thread(target=self.emu.run, daemon=True)
        self.thread.start()
        self.safety = safety or Safety(link_timeout=1.0)
        self.vehicle: Vehicle = open_vehicle(f"udp:127.0.0.1:{self.emu.port}", self.safety)
        self.vehicle.time_scale = 1 / speedup
        self.plan = FlightPlan(_mission(), 1, self.safety)

    def run(self, task: Task, limit: float = 15.0) -> Task:
        end = time.monotonic() + limit
        while task.running:
            assert time.monotonic() < end, f"{task.name} still running ({task.phase})"
            self.vehicle.update(time.monotonic())
            time.sleep(0.005)
        return task

    def close(self) -> None:
        self.vehicle.close()
        self.emu.cfg.timeout = 0.0  # the emulator's loop ends at its next turn
        self.thread.join(5)


@pytest.fixture
def emulated():
    made: list[Emulated] = []

    def make(**kw: object) -> Emulated:
        e = Emulated(**kw)  # type: ignore[arg-type]
        made.append(e)
        return e

    yield make
    for e in made:
        e.close()


def test_a_link_that_cannot_be_opened_is_one_clear_error():
    with pytest.raises(InputError, match="--vehicle: cannot open serial:/dev/nonexistent"):
        open_vehicle("serial:/dev/nonexistent-swarmex-port")
    # a typo'd host: at once, not 30 s of silence and "no heartbeat"
    with pytest.raises(InputError, match="--vehicle: cannot resolve the host of udp:nosuch"):
        open_vehicle("udp:nosuchhost.invalid:14550")


def test_take_off_at_real_time(emulated):
    """At real time the climb outlasts the 1 s resend, and ArduCopter refuses a second
    NAV_TAKEOFF once airborne ("can't takeoff again"): every real flight failed at take-off
    (the tests flew at 50x, where the climb took 0.04 s)."""
    e = emulated(speedup=1.0)
    v = e.vehicle
    assert e.run(v.preflight(e.plan)).done
    task = e.run(v.takeoff(5.0), limit=20.0)
    assert task.done, task.reason
    assert v.airborne() and e.emu.copter.alt >= 4.0


def test_the_job_holds_from_the_top_of_its_climb_and_lets_go_of_a_pilot(emulated):
    """The hold was counted from the job's start, so the copter held for the job time minus
    its climb; and a pilot taking over during the hold went unnoticed until it ended. At
    speedup 10 the vehicle's clock comes every 0.4 s, finer than the 0.8 s climb."""
    e = emulated(speedup=10.0)
    v = e.vehicle
    e.run(v.preflight(e.plan))
    e.run(v.takeoff(e.plan.altitude))
    marks: dict[str, float] = {}
    task = v.job(5.0)
    end = time.monotonic() + 15.0
    while task.running:
        assert time.monotonic() < end, f"job still running ({task.phase})"
        v.update(time.monotonic())
        marks.setdefault(task.phase, v.boot_s)
        time.sleep(0.002)
    assert task.done, task.reason
    assert marks["job: descend"] - marks["job: hold"] >= 5.0 - 0.05  # held 5 s at the top
    task = v.job(30.0)
    end = time.monotonic() + 15.0
    while task.phase != "job: hold":
        assert time.monotonic() < end and task.running, f"no hold ({task.phase})"
        v.update(time.monotonic())
        time.sleep(0.002)
    e.emu.copter.set_mode(emulator.LOITER)  # a pilot takes over mid-hold
    e.run(task)
    assert task.failed and "left GUIDED mode (now LOITER)" in task.reason
    assert v.other_control() == "a pilot (mode LOITER)"


def test_a_full_flight_over_mavlink(emulated):
    e = emulated()
    v, plan = e.vehicle, e.plan
    assert e.run(v.preflight(plan)).done, v.preflight(plan).reason
    info = v.describe()
    assert info["kind"] == "mavlink" and info["autopilot"] == "ARDUPILOTMEGA"
    assert info["type"] == "QUADROTOR" and v.battery() == 100.0
    assert e.run(v.arm()).done and not v.airborne()
    assert e.run(v.takeoff(plan.altitude)).done and v.airborne()
    target = plan.position(11)  # two columns east, one row south: 22 m away
    assert e.run(v.goto(target, plan.speed)).done
    here = v.position()
    assert here is not None and here.horizontal_distance(target) <= e.safety.arrive_radius
    copter = e.emu.copter
    t0 = copter.t
    assert e.run(v.job(10.0)).done
    assert copter.t - t0 >= 10.0  # the job's time runs on the vehicle's clock
    task = v.return_and_land()
    phases = []
    end = time.monotonic() + 15.0
    while task.running:
        assert time.monotonic() < end, f"no landing ({task.phase})"
        v.update(time.monotonic())
        if not phases or phases[-1] != task.phase:
            phases.append(task.phase)
        time.sleep(0.005)
    assert task.done and phases[-2:] == ["returning", "landing"], (phases, task.reason)
    assert not copter.armed and copter.landed and abs(copter.n) < 1 and abs(copter.e) < 1
    assert v.battery() < 100.0  # it flew: the battery drained


def test_failed_prearm_checks_name_the_problem(emulated):
    e = emulated(fail_prearm="Compass not calibrated")
    task = e.run(e.vehicle.preflight(e.plan))
    assert task.failed and "PreArm: Compass not calibrated" in task.reason
    e2 = emulated(satellites=4)
    task = e2.run(e2.vehicle.preflight(e2.plan))
    assert task.failed and "GPS: no 3-D fix" in task.reason and "4 satellites" in task.reason
    e3 = emulated(battery=40.0)
    task = e3.run(e3.vehicle.preflight(e3.plan))
    assert task.failed and "battery 40 %" in task.reason


def test_a_lost_link_is_a_fault_and_a_taken_over_vehicle_is_left_alone(emulated):
    e = emulated(drop_link_after=5.0)
    v = e.vehicle
    e.run(v.preflight(e.plan))
    e.run(v.takeoff(e.plan.altitude))
    task = e.run(v.goto(e.plan.position(11), 1.0), 20.0)  # slow: the link drops on the way
    assert task.failed and "link lost" in task.reason and v.fault() is not None
    assert e.emu.copter.mode == emulator.RTL  # the emulated autopilot's failsafe
    e2 = emulated()
    v2 = e2.vehicle
    e2.run(v2.preflight(e2.plan))
    e2.run(v2.takeoff(e2.plan.altitude))
    task = v2.goto(e2.plan.position(11), 1.0)
    e2.emu.copter.set_mode(emulator.LOITER)  # a pilot flips the mode switch
    e2.run(task)
    assert task.failed and "left GUIDED mode (now LOITER)" in task.reason
    assert v2.fault() is None
    assert v2.other_control() == "a pilot (mode LOITER)"
    e2.emu.copter.set_mode(emulator.RTL)  # or the autopilot's failsafe
    v2.update(time.monotonic() + 0.2)
    deadline = time.monotonic() + 5
    while v2.other_control() is None or "RTL" not in v2.other_control():
        assert time.monotonic() < deadline
        v2.update(time.monotonic())
        time.sleep(0.005)
    assert v2.other_control() == "the autopilot or a pilot (mode RTL)"


def _gps_plan(nest: str, nodes_on_edge: int) -> tuple:
    """One agent on seed 000's field as a GPS grid of radius 50 m: (prepared world, plan)."""
    pytest.importorskip("pyproj", reason="GPS grids need the geo extra")
    from swarmex.missions.registry import get
    from swarmex.missions.traversal.mission import agent_specs

    m = get("traversal")
    p = m.params(agents=1, nests=nest, center="43.268304,-79.911135", radius=50,
                 nodes_on_edge=nodes_on_edge, travel_time=2.5)
    prep = m.prepare(p)
    mission = Mission(prep.world, agent_specs(p, prep), "madgta", 0, 0.5, prep.unit_length,
                      0.0, 1 / SPEEDUP, "shared", True, 0.25, {})
    return prep, FlightPlan(mission, 1, Safety())


def test_a_gps_grid_plan_flies_geodesic_offsets_from_the_nest():
    """On a GPS grid (serve --center) nodes sit at their own latitude and longitude: a
    neighbour is 2R/(K-1) metres away along the geodesic, north up, at the mission's speed."""
    prep, plan = _gps_plan("4,4", 9)
    east = plan.position(prep.world.node(5, 4))
    north = plan.position(prep.world.node(4, 3))
    assert east.east == pytest.approx(12.5, abs=0.01) and abs(east.north) < 0.01
    assert north.north == pytest.approx(12.5, abs=0.01) and abs(north.east) < 0.01
    assert plan.speed == pytest.approx(12.5 / 2.5, rel=1e-3)  # 2.5 s per 12.5 m edge
    assert plan.farthest() == pytest.approx(50 * 2**0.5, abs=0.05)  # the grid's corners
    assert plan.nest_latlon() == prep.world.latlon(prep.world.node(4, 4))
    assert plan.notes()[0].startswith(f"GPS grid, nest node {plan.home_node} at 43.268")


def test_a_copter_away_from_its_gps_nest_is_refused(emulated):
    """A GPS-grid mission flew to completion with the copter thousands of km from the grid:
    the plan is offsets from where it arms, and nothing compared that with the nest."""
    _, plan = _gps_plan("1,1", 3)
    centre = emulated(home=(43.268304, -79.911135, 100.0))  # node (1, 1): the grid's centre
    assert centre.run(centre.vehicle.preflight(plan)).done
    away = emulated(home=(10.0, 10.0, 100.0))
    task = away.run(away.vehicle.preflight(plan))
    assert task.failed and "from its nest (node 4 at 43.268304,-79.911135" in task.reason


def test_a_closed_tcp_link_is_a_fault_at_once_and_quiet(capsys):
    """pymavlink prints "EOF on TCP socket" on every read of a closed link: 335,014 lines in
    the 3 s before the link timeout. Now the close is the vehicle's fault, and nothing more
    is read."""
    import socket

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    port = server.getsockname()[1]

    def accept_then_close() -> None:
        conn, _ = server.accept()
        time.sleep(0.2)
        conn.close()

    t = threading.Thread(target=accept_then_close, daemon=True)
    t.start()
    try:
        v = open_vehicle(f"tcp:127.0.0.1:{port}", Safety(link_timeout=30.0))
        end = time.monotonic() + 1.5
        while time.monotonic() < end:
            v.update(time.monotonic())
            time.sleep(0.001)
        assert v.fault() == f"the vehicle's TCP link tcp:127.0.0.1:{port} closed (link lost)"
        v.close()
    finally:
        server.close()
        t.join(2)
    assert len(capsys.readouterr().out.splitlines()) <= 2


def test_each_datagram_is_parsed_on_its_own():
    """A torn datagram (a MAVLink 2 header claiming 255 bytes, cut after 10) costs only
    itself: UDP keeps message boundaries, so the commands in the datagrams after it arrive.
    With one stream parser shared across datagrams the bogus header swallowed them and the
    mode never changed."""
    from pymavlink.dialects.v20 import ardupilotmega as mav

    emu = emulator.Emulator("127.0.0.1", 0, emulator.EmulatorConfig(timeout=5.0),
                            say=lambda s: None)
    gcs = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        to = ("127.0.0.1", emu.port)

        class _To:
            def write(self, b: bytes) -> None:
                gcs.sendto(b, to)

        link = mav.MAVLink(_To(), srcSystem=255, srcComponent=190)
        gcs.sendto(b"\xfd\xff" + bytes(8), to)  # the torn datagram
        link.heartbeat_send(6, 8, 0, 0, 0)
        link.command_long_send(1, 1, mav.MAV_CMD_DO_SET_MODE, 0, 1, emulator.GUIDED,
                               0, 0, 0, 0, 0)
        gcs.sendto(b"\xfe\x09" + bytes(3), to)  # and a torn MAVLink 1 one in the middle
        link.heartbeat_send(6, 8, 0, 0, 0)
        end = time.monotonic() + 5.0
        while emu.received < 3 and time.monotonic() < end:
            time.sleep(0.02)
            emu._receive(time.monotonic())
        assert emu.received == 3  # two heartbeats and the command, nothing else
        assert emu.copter.mode == emulator.GUIDED
    finally:
        gcs.close()
        emu.sock.close()
