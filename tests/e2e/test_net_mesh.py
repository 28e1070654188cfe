"""Exploration as OS processes (``swarmex explore --processes``): one process per robot and a
display process on a ZeroMQ mesh, with a robot killed mid-run and 30 % of radio frames lost.

The launcher runs in this process (it only spawns and waits); the robots and the display are
real subprocesses on 127.0.0.1, bounded in time and killed by the launcher if they outlive
the run. The record is checked like a simulated one: every step legal on the true map."""

from __future__ import annotations

import re
import threading
import time

import numpy as np
import pytest

from swarmex.missions.exploration import ExplorationParams
from swarmex.missions.exploration.sim import legal_step
from swarmex.net.events import viewer_batches
from swarmex.net.mesh import run_processes
from swarmex.net.mesh_scenario import MeshOptions
from swarmex.worlds.metric import empty_metric

pytestmark = pytest.mark.timeout(120)


def test_mesh_survives_a_killed_robot_and_thirty_percent_loss(tmp_path):
    grid = empty_metric(3, 3)  # 60 x 60 cells of 5 cm, walls around
    params = ExplorationParams(robots=3, laser_range=1.0, comm_range=10.0, seed=1)
    options = MeshOptions(time_scale=0.2, loss=0.3, inject_kill={1: 20}, dead_after=3.0,
                          timeout=90)
    events: list[dict] = []
    lines: list[str] = []
    watchers: list[threading.Thread] = []

    t0 = time.monotonic()

    def say(line: str) -> None:
        lines.append(f"{time.monotonic() - t0:.1f}s {line}")
        m = re.search(r"view on (tcp://127\.0\.0\.1:\d+)", line)
        if m:  # a live viewer of the display, as `swarmex watch` is
            def watch(address: str = m[1]) -> None:
                for batch in viewer_batches(address, timeout=60):
                    events.extend(batch)

            watchers.append(threading.Thread(target=watch, daemon=True))
            watchers[-1].start()

    record = run_processes(grid, params, options, tmp_path / "mesh.json", say=say)
    for w in watchers:  # the viewer stops at the end event
        w.join(10)
    assert (tmp_path / "mesh.json").exists()
    m = record["metrics"]
    assert record["mission"] == "exploration" and record["time_unit"] == "step"
    assert record["complete"], lines
    assert m["explored_fraction"] >= 0.99
    assert m["robots_lost"] == 1 and any("robot 1 fell silent" in s for s in lines)
    alive = {a["id"]: a["metrics"]["alive"] for a in record["agents"]}
    assert alive == {0: True, 1: False, 2: True}
    # the injected loss happened, and the survivors' radios saw it
    lost = sum(a["metrics"]["traffic"]["lost_injected"] for a in record["agents"]
               if a["metrics"].get("reported"))
    assert lost > 0
    # the killed robot died at tick 20: its telemetry stops there
    assert record["agents"][1]["trajectory"][-1][0] <= 20
    # every step of every robot is legal on the true map (8-moves, no corner cutting)
    free = grid.free
    for a in record["agents"]:
        traj = a["trajectory"]
        for (t0, x0, y0), (t1, x1, y1) in zip(traj, traj[1:], strict=False):
            assert t1 > t0
            assert legal_step(free, (x0, y0), (x1, y1))
    # the monitor stream of the display
    kinds = [e["type"] for e in events]
    assert kinds[:2] == ["hello", "world"] and events[0]["source"] == "network"
    # the page shows the totals at the end, not a message rate of 0 (no message events)
    assert events[0]["messages"] == "totals"
    assert {e.get("kind") for e in events if e["type"] == "message"} <= {"left"}
    assert events[-1]["type"] == "end" and events[-1]["messages"] == m["messages_sent"] > 0
    assert "move" in kinds and kinds[-1] == "end"
    assert np.isclose(events[-1]["makespan"], record["makespan"])


def test_bad_network_options_exit_2(capsys):
    from swarmex.cli import main

    for argv, msg in (
        (["mesh", "--empty", "3x3", "--robots", "2", "--inject-loss", "1.5"], "--inject-loss"),
        (["mesh", "--empty", "3x3", "--robots", "2", "--inject-kill", "5@3"], "no robot 5"),
        (["mesh", "--empty", "3x3", "--robots", "2", "--inject-kill", "x"], "ID@TICK"),
        (["serve", "--grid", "3x3", "--agents", "2", "--port", "0", "--time-scale", "-1"],
         "--time-scale"),
        (["agent", "--connect", "localhost:5"], "tcp://"),
    ):
        assert main(argv) == 2
        assert msg in capsys.readouterr().err


def test_scans_cross_the_mesh_by_multi_hop_relay():
    """Three closed rooms in a row, one robot in each: the outer two are out of radio range
    of each other (and the display sits with the first), so the third robot's scans reach
    the first one and the display only through the middle robot's relaying."""
    from swarmex.worlds import GridWorld
    from swarmex.worlds.metric import MetricGrid

    free = np.zeros((22, 64), dtype=bool)
    for x0 in (1, 22, 43):  # 20 x 20 rooms (1 m), one wall cell between them
        free[1:21, x0:x0 + 20] = True
    grid = MetricGrid(GridWorld(free, source="three rooms"), 0.05)
    starts = ((11, 11), (32, 11), (53, 11))  # 1.05 m apart; the ends 2.1 m apart
    params = ExplorationParams(robots=3, laser_range=0.3, comm_range=1.5, seed=3,
                               starts=starts)
    record = run_processes(grid, params, MeshOptions(time_scale=0.1, timeout=60),
                           say=lambda _s: None)
    assert record["complete"] and record["metrics"]["explored_fraction"] >= 0.99
    assert all(a["metrics"]["reported"] for a in record["agents"])
    by = {a["id"]: a["metrics"]["scans_by_origin"] for a in record["agents"]}
    assert by[0].get("2", 0) > 0 and by[2].get("0", 0) > 0  # 0 and 2 never heard each other
    assert record["metrics"]["display_scans_by_origin"].get("2", 0) > 0
    # the radio really was range-limited: heartbeats between the ends were not heard
    assert record["agents"][0]["metrics"]["traffic"]["unheard_broadcasts"] > 0
    assert record["agents"][2]["metrics"]["traffic"]["unheard_broadcasts"] > 0


def test_unicasts_cross_a_line_of_robots_by_aodv():
    """Four closed rooms in a row, one robot in each, a radio (1.5 m) that reaches only the
    next room (1.05 m) — the line is 3.15 m long. NEED_MAP / MAP between robots that never
    hear each other must be routed by AODV through the robots in between (a tenth of the
    radio frames is lost, so archives have holes to ask for). Checked two ways: the robots'
    AODV statistics, and what the receivers saw arrive in routed envelopes."""
    from swarmex.worlds import GridWorld
    from swarmex.worlds.metric import MetricGrid

    n = 4
    free = np.zeros((22, 1 + 21 * n), dtype=bool)
    starts = []
    for i in range(n):  # 20 x 20 rooms (1 m), one wall cell between them
        free[1:21, 1 + 21 * i:21 + 21 * i] = True
        starts.append((11 + 21 * i, 11))
    grid = MetricGrid(GridWorld(free, source="rooms in a row"), 0.05)
    params = ExplorationParams(robots=n, laser_range=0.3, comm_range=1.5, seed=3,
                               starts=tuple(starts))
    assert (starts[2][0] - starts[0][0]) * grid.cell > params.comm_range  # two hops at least
    record = run_processes(grid, params, MeshOptions(time_scale=0.1, loss=0.1, timeout=60),
                           say=lambda _s: None)
    m = record["metrics"]
    assert record["params"]["aodv"] is True
    assert record["complete"] and m["explored_fraction"] >= 0.99
    assert all(a["metrics"]["reported"] for a in record["agents"])
    u = m["unicasts"]
    assert u["delivered_multihop"] > 0 and u["discoveries"] > 0 and u["gap_requests"] > 0
    assert m["aodv_messages"] > 0 and m["aodv_bytes"] > 0
    assert set(m["multihop_in_by_kind"]) <= {"NEED_MAP", "MAP", "CHANGE_GOAL"}
    assert m["multihop_in_by_kind"].get("NEED_MAP", 0) + m["multihop_in_by_kind"].get("MAP", 0) > 0
    # the wire's count of routed arrivals is AODV's count of multi-hop deliveries
    assert sum(m["multihop_in_by_kind"].values()) == (
        u["delivered_multihop"] + m["display_unicasts"]["delivered_multihop"])
    # the ends never heard each other: everything between them was relayed or routed
    assert record["agents"][0]["metrics"]["traffic"]["unheard_broadcasts"] > 0
    by = {a["id"]: a["metrics"]["scans_by_origin"] for a in record["agents"]}
    assert by[0].get(str(n - 1), 0) > 0 and by[n - 1].get("0", 0) > 0


@pytest.mark.parametrize("target", ["launcher", "group"])
def test_sigterm_to_the_launcher_keeps_the_record_so_far_and_leaves_no_process(tmp_path, target):
    """``kill``, ``timeout`` or a service manager stopping ``swarmex mesh`` used to lose the
    record and leave the display and the robots running for 20 s; Ctrl-C lost the record.
    ``group``: the signal reaches every process (``timeout``, a service manager's stop), the
    fork server and the robots included."""
    import json
    import os
    import signal
    import subprocess
    import sys

    out = tmp_path / "mesh.json"
    proc = subprocess.Popen(
        [sys.executable, "-m", "swarmex", "mesh", "--empty", "8x8", "--robots", "2",
         "--time-scale", "1", "--json", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )
    try:
        assert proc.stdout is not None
        for line in proc.stdout:  # the robots are exploring
            if "robots started" in line:
                break
        time.sleep(2.0)
        children = _descendants(proc.pid)
        assert len(children) >= 4, "no display and robots"  # fork server, display, 2 robots
        if target == "group":
            os.killpg(proc.pid, signal.SIGTERM)
        else:
            proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=40)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    assert f"interrupted; the record of the run so far is in {out}" in err
    record = json.loads(out.read_text())
    assert not record["complete"] and 0 < record["metrics"]["explored_fraction"] < 1
    time.sleep(0.5)
    left = [pid for pid in children if _alive(pid)]
    assert not left, f"processes left running: {left}"


def test_a_forged_status_and_report_cost_only_themselves(tmp_path, monkeypatch):
    """A STATUS whose move time is ``inf`` (``int(inf)``: OverflowError) killed the display,
    and the launcher then lost the run's record with a traceback; a REPORT of ``inf`` did
    the same. Sent here to the display's own socket mid-run, as a stray sender would: both
    are dropped and counted, and the run completes."""
    import tempfile

    import zmq

    from swarmex.net import wire

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))  # where the run's air is
    grid = empty_metric(3, 3)
    params = ExplorationParams(robots=2, laser_range=1.0, comm_range=10.0, seed=1)
    options = MeshOptions(time_scale=0.2, timeout=90)
    lines: list[str] = []

    def say(line: str) -> None:
        lines.append(line)
        if "robots started" not in line:
            return
        addr = next(tmp_path.glob("swarmex-mesh-*/node-10000.addr")).read_text().strip()
        push = zmq.Context.instance().socket(zmq.PUSH)
        push.setsockopt(zmq.LINGER, 2000)
        push.connect(addr)
        push.send(wire.pack(["STATUS", 0, {"t": 5, "finished": False, "x": 1, "y": 1,
                                           "moves": [[float("inf"), 1, 1]]}]))
        push.send(wire.pack(["REPORT", 1, {"steps": float("inf")}]))
        push.close()

    record = run_processes(grid, params, options, tmp_path / "mesh.json", say=say)
    assert any("robots started" in s for s in lines)
    assert record["complete"], lines
    assert record["metrics"]["display_traffic"]["bad_frames"] >= 2
    assert all(a["metrics"]["reported"] for a in record["agents"])


def test_a_killed_display_ends_the_launcher_in_one_line(tmp_path):
    """The display SIGKILLed mid-run (the OOM killer, a stray kill): the launcher said a
    RuntimeError's traceback and waited 10 s for each robot. Now one line on stderr, exit
    status 3, no record written (the run's state died with the display), no process left."""
    import os
    import signal

    out = tmp_path / "mesh.json"
    proc = _launch_mesh(tmp_path, out)
    try:
        children = _descendants(proc.pid)
        addr = next(tmp_path.glob("swarmex-mesh-*/node-10000.addr")).read_text()
        display = _listening(int(addr.rsplit(":", 1)[1]), children)
        os.kill(display, signal.SIGKILL)
        t0 = time.monotonic()
        _, err = proc.communicate(timeout=40)
        took = time.monotonic() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(5)
    assert proc.returncode == 3, err
    assert "Traceback" not in err
    assert err.strip().splitlines() == [
        "swarmex: the display process ended (exit -9) without writing the record; "
        "nothing written"]
    assert not out.exists()
    assert took < 8, took  # not 10 s of waiting for each robot
    time.sleep(0.5)
    left = [pid for pid in children if _alive(pid)]
    assert not left, f"processes left running: {left}"


def test_a_second_sigterm_to_the_display_does_not_lose_the_record(tmp_path):
    """After a group SIGTERM the launcher sends the display its own: the display asked to
    stop once, and the second came after it had restored the default handler, which killed
    it before it wrote the record of the run so far (the group test failed now and then).
    Here the second comes while it collects the reports: the record is still written."""
    import json
    import os
    import signal

    out = tmp_path / "mesh.json"
    proc = _launch_mesh(tmp_path, out)
    try:
        time.sleep(1.0)
        addr = next(tmp_path.glob("swarmex-mesh-*/node-10000.addr")).read_text()
        children = _descendants(proc.pid)
        display = _listening(int(addr.rsplit(":", 1)[1]), children)
        robots = [p for p in children if p != display and _parent(p) == _parent(display)]
        assert len(robots) == 2
        # a robot that will never report keeps the display collecting for seconds: the
        # second SIGTERM lands there, whatever the machine's load
        os.kill(robots[1], signal.SIGKILL)
        os.kill(display, signal.SIGTERM)
        for line in proc.stdout:  # the display has left its loop: collecting the reports
            if "stopping the robots" in line:
                break
        time.sleep(0.5)
        os.kill(display, signal.SIGTERM)
        _, err = proc.communicate(timeout=40)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(5)
    assert "Traceback" not in err
    assert proc.returncode == 1, err  # the display ended the run: incomplete, not lost
    record = json.loads(out.read_text())
    assert not record["complete"] and record["metrics"]["explored_fraction"] > 0
    assert [a["metrics"]["reported"] for a in record["agents"]].count(True) == 1


def _launch_mesh(tmp_path, out):
    """``swarmex mesh`` of 2 robots on 8 × 8 m in its own session (its run folder under
    ``tmp_path``), returned once its robots have started."""
    import os
    import subprocess
    import sys

    proc = subprocess.Popen(
        [sys.executable, "-m", "swarmex", "mesh", "--empty", "8x8", "--robots", "2",
         "--time-scale", "1", "--json", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
        env={**os.environ, "TMPDIR": str(tmp_path)},
    )
    assert proc.stdout is not None
    for line in proc.stdout:
        if "robots started" in line:
            break
    return proc


def _parent(pid: int) -> int:
    from pathlib import Path

    return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])


def _listening(port: int, pids: list[int]) -> int:
    """Which of ``pids`` has the TCP socket listening on 127.0.0.1:``port`` (Linux /proc):
    the display's PULL socket, whose endpoint it published in the air."""
    import os
    from pathlib import Path

    inode = None
    for row in Path("/proc/net/tcp").read_text().splitlines()[1:]:
        f = row.split()
        if f[1] == f"0100007F:{port:04X}" and f[3] == "0A":
            inode = f[9]
    assert inode is not None, f"nothing listens on port {port}"
    for pid in pids:
        for fd in Path(f"/proc/{pid}/fd").glob("*"):
            try:
                if os.readlink(fd) == f"socket:[{inode}]":
                    return pid
            except OSError:
                continue
    raise AssertionError(f"no process of the run listens on port {port}")


def _descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (Linux /proc): the display and the robots are the fork
    server's children, not the launcher's."""
    from pathlib import Path

    parent: dict[int, int] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            parent[int(stat.parent.name)] = int(stat.read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            continue
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        kids = [c for c, pp in parent.items() if pp == p]
        out += kids
        todo += kids
    return out


def _alive(pid: int) -> bool:
    from pathlib import Path

    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"
