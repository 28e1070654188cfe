"""The mesh display's control link: a bad STATUS or REPORT is dropped and counted.

A robot's telemetry is turned into integers, cells and the record's numbers. One STATUS
whose move time was ``inf`` (``int(inf)``: OverflowError) killed the display and lost the
run's record; a REPORT with ``inf`` counters did the same at the end. The display and a robot
run here in this process, sockets bound on 127.0.0.1, no process started."""

from __future__ import annotations

import math

import pytest

from swarmex.missions.exploration import ExplorationParams
from swarmex.net import wire
from swarmex.net.mesh_frames import report_fields, status_fields
from swarmex.net.mesh_scenario import MeshOptions, write_scenario
from swarmex.worlds.metric import empty_metric

pytestmark = pytest.mark.timeout(120)

GOOD_STATUS = {"t": 5, "finished": False, "stopped": False, "x": 3, "y": 3, "goal": None,
               "moves": [[1, 3, 3], [2, 4, 3]]}

BAD_STATUS = {
    "move time inf": {"moves": [[math.inf, 3, 3]]},
    "move time nan": {"moves": [[math.nan, 3, 3]]},
    "move time huge": {"moves": [[2**63, 3, 3]]},
    "move off the map": {"moves": [[1, 10**6, 3]]},
    "move of two": {"moves": [[1, 3]]},
    "t inf": {"t": math.inf},
    "t float": {"t": 5.0},
    "t negative": {"t": -1},
    "x huge": {"x": 2**64 - 1},
    "x nan": {"x": math.nan},
    "finished a string": {"finished": "no"},
    "moves a map": {"moves": {"a": 1}},
    "no t": {"t": None},
}


@pytest.fixture
def mesh(tmp_path):
    """A display and robot 0 of a 3 x 3 m world (60 x 60 cells), as the launcher starts
    them, in this process."""
    from swarmex.net.mesh_display import DisplayProcess
    from swarmex.net.mesh_robot import RobotProcess

    grid = empty_metric(3, 3)
    params = ExplorationParams(robots=2, laser_range=1.0, comm_range=10.0, seed=1)
    write_scenario(tmp_path, grid, params, MeshOptions(), tmp_path / "mesh.json")
    display = DisplayProcess(tmp_path)
    robot = RobotProcess(tmp_path, 0)
    yield display, robot
    robot.close()
    display.close()
    display.view.close(0)


def _status(**change: object) -> dict:
    return {**GOOD_STATUS, **change}


@pytest.mark.parametrize("case", sorted(BAD_STATUS))
def test_a_bad_status_is_a_wire_error(case):
    with pytest.raises(wire.WireError):
        status_fields(_status(**BAD_STATUS[case]), (60, 60))


def test_a_robots_own_telemetry_passes_the_checks(mesh):
    """What a robot sends, through the wire and back, is accepted whole."""
    _, robot = mesh
    sent: list[list] = []
    robot.control = sent.append  # type: ignore[method-assign]
    robot.tick()  # tick 0: the first scan, and a STATUS (every 5 ticks)
    rep = wire.unpack(wire.pack(["REPORT", 0, robot.report()]))[2]
    status = wire.unpack(wire.pack(sent[-1]))[2]
    t, finished, stopped, pos, moves = status_fields(status, (60, 60))
    assert (t, finished, stopped, pos) == (0, False, False, robot.pos())
    assert moves == [[0, *robot.pos()]]
    checked = report_fields(rep, (60, 60))
    assert checked["trajectory"] == robot.trajectory
    assert checked["traffic"]["frames_out"] == rep["traffic"]["frames_out"]
    assert set(checked) == set(rep)


def _frame(cmd: str, body: dict) -> bytes:
    return wire.pack([cmd, 0, body])


def test_the_display_drops_and_counts_a_bad_status_and_report(mesh):
    display, robot = mesh
    # a forged STATUS (/tmp/audit-net/meshfuzz.py status-inf): it killed the display
    for body in BAD_STATUS.values():
        display._on_frame(_frame("STATUS", _status(**body)), 1.0)
    assert display.traffic.bad_frames == len(BAD_STATUS)
    assert display.robots == {}  # a bad frame is no sign of life either
    display._on_frame(_frame("STATUS", GOOD_STATUS), 2.0)
    assert display.robots[0]["trajectory"] == GOOD_STATUS["moves"]
    assert display.robots[0]["pos"] == (3, 3) and display.robots[0]["seen"] == 2.0
    # REPORTs: infinite, huge, missing, of the wrong size; the good one is kept
    good = wire.unpack(wire.pack(robot.report()))
    bad_reports = [{"steps": math.inf}, {**good, "steps": math.inf},
                   {**good, "moves": 2**64 - 1}, {**good, "free": good["free"][:-1]},
                   {**good, "replan_reasons": {"x": math.nan}},
                   {**good, "traffic": {**good["traffic"], "frames_out": math.inf}},
                   {**good, "unicasts": {"nonsense": 1}},
                   {**good, "trajectory": [[0, -1, 3]]}]
    for rep in bad_reports:
        display._on_frame(_frame("REPORT", rep), 3.0)
    assert display.traffic.bad_frames == len(BAD_STATUS) + len(bad_reports)
    assert display.reports == {}
    record = display.build_record(1.0, False)  # the record still builds
    assert record["agents"][0]["metrics"]["reported"] is False
    display._on_frame(_frame("REPORT", good), 4.0)
    record = display.build_record(1.0, False)
    assert record["agents"][0]["metrics"]["reported"] is True


def test_a_frame_the_handling_chokes_on_is_dropped_and_said_once(mesh, monkeypatch):
    """The last guard: whatever a handler raises past the checks (a bug) costs the frame,
    not the display and the run's record. Frames through the display's own PULL socket."""
    import time

    import zmq

    display, _ = mesh
    said: list[str] = []
    display.say = said.append

    def broken(obj: list, now: float) -> None:
        raise OverflowError("cannot convert float infinity to integer")

    monkeypatch.setattr(display, "on_control", broken)
    push = zmq.Context.instance().socket(zmq.PUSH)
    push.setsockopt(zmq.LINGER, 0)
    push.connect(display.endpoint)
    try:
        for _ in range(2):
            push.send(_frame("STATUS", GOOD_STATUS))
        end = time.monotonic() + 10
        while display.traffic.bad_frames < 2 and time.monotonic() < end:
            display._pump(time.monotonic(), 0.05)
    finally:
        push.close()
    assert display.traffic.bad_frames == 2
    assert len(said) == 1 and "OverflowError" in said[0]
