"""Hybrid missions end to end: ``swarmex uav-emulator`` + ``swarmex agent --vehicle`` beside
simulated agents, one ``swarmex serve`` (seed 000 §4.3, §5.2.2: "a hybrid mode of real and
simulated UAVs").

Every process is a subprocess on 127.0.0.1 (the server on a free TCP port, the emulator on a
free UDP port, both read back from their first line), every process has its own --timeout,
every wait is bounded and leftovers are killed. The emulated clock runs 50x the wall's and
the mission's time scale is 1/50, so the copter keeps pace and a mission takes seconds.
"""

from __future__ import annotations

import json

import pytest

from swarmex.missions.traversal import run_traversal, traversal_record, uniform_agents
from tests.e2e.test_cli_traversal import free_mask, replay
from tests.e2e.test_net_traversal import GRID, OBSTACLES, Viewer, _world
from tests.net.netproc import Procs, endpoint

pytest.importorskip("pymavlink")
pytestmark = pytest.mark.timeout(120)

SPEEDUP = 50
SERVE = ["--agents", 3, "--seed", 7, "--port", 0, "--time-scale", 1 / SPEEDUP, "--timeout", 80]


def _start(procs: Procs, rec_path, *emulator_args: object) -> tuple:
    emu = procs.start("emulator", "uav-emulator", "--listen", "udp:127.0.0.1:0", "--speedup",
                      SPEEDUP, "--exit-when-idle", 2, "--timeout", 80, *emulator_args)
    server = procs.start("server", "serve", *GRID, *SERVE, "--json", rec_path)
    address = endpoint(server)
    link = emu.wait_line(r"listening on (udp:127\.0\.0\.1:\d+)", 30)[1]
    return emu, server, address, link


def _simulated() -> dict:
    world = _world()
    return traversal_record(
        run_traversal(world, uniform_agents([0, 0, 0], 2.22, 10.0), seed=7), {}
    ).to_dict()


def _same_run(net: dict, sim: dict) -> None:
    assert net["complete"] and net["makespan"] == sim["makespan"]
    for x, y in zip(net["agents"], sim["agents"], strict=True):
        assert x["trajectory"] == y["trajectory"] and x["jobs"] == y["jobs"]


def test_hybrid_mission_one_emulated_copter_two_simulated_agents(tmp_path):
    rec_path = tmp_path / "hybrid.json"
    with Procs() as procs:
        emu, server, address, link = _start(procs, rec_path)
        viewer = Viewer(address)
        copter = procs.start("mavlink", "agent", "--connect", address, "--id", 3,
                             "--vehicle", link)
        sims = procs.start("simulated", "agent", "--connect", address, "--count", 2)
        assert server.wait(90) == 0, server.output
        assert copter.wait(15) == 0, copter.output
        assert sims.wait(15) == 0, sims.output
        assert emu.wait(15) == 0, emu.output
        viewer.thread.join(10)
    net = json.loads(rec_path.read_text())
    # the copter flies the agent's moves; mission times are computed, so the hybrid run is
    # the simulated run of the same seed
    _same_run(net, _simulated())
    replay(net, free_mask(6, 6, OBSTACLES))
    kinds = [v["kind"] for v in net["vehicles"]]
    assert kinds == ["simulated", "simulated", "mavlink"]
    assert net["vehicles"][2]["autopilot"] == "ARDUPILOTMEGA"
    # the charge the copter landed with: it flew, so the emulator's battery drained
    assert 0 < net["vehicles"][2]["battery_end"] < 100
    assert "battery_end" not in net["vehicles"][0]
    assert [p["vehicle"] for p in net["network"]["peers"]] == kinds
    assert net["network"]["handed_back"] == [] and net["network"]["left"] == []
    assert net["network"]["stats_received"] == 3 and net["network"]["stats_mismatch"] == 0
    hello = viewer.events[0]
    assert hello["type"] == "hello" and "1 mavlink, 2 simulated" in hello["title"]
    assert [v["kind"] for v in hello["vehicles"]] == kinds
    assert "Takeoff to 5.0 m" in emu.output and "Land complete" in emu.output
    assert "mission started" in server.output and "(1 mavlink, 2 simulated)" in server.output


def test_failed_prearm_hands_the_id_to_a_spare(tmp_path):
    rec_path = tmp_path / "prearm.json"
    with Procs() as procs:
        emu, server, address, link = _start(procs, rec_path, "--fail-prearm",
                                            "Compass not calibrated")
        copter = procs.start("mavlink", "agent", "--connect", address, "--id", 3,
                             "--vehicle", link)
        sims = procs.start("simulated", "agent", "--connect", address, "--count", 2,
                           "--spares", 1, "--connect-timeout", 60)
        assert copter.wait(40) == 6, copter.output  # its vehicle failed: id handed back
        assert server.wait(60) == 0, server.output
        assert sims.wait(15) == 0, sims.output
        assert emu.wait(15) == 0, emu.output
    net = json.loads(rec_path.read_text())
    _same_run(net, _simulated())  # the spare armed before the start: nothing else changed
    (back,) = net["network"]["handed_back"]
    assert back["id"] == 3 and back["vehicle"]["kind"] == "mavlink"
    assert "PreArm: Compass not calibrated" in back["reason"]
    assert [v["kind"] for v in net["vehicles"]] == ["simulated"] * 3
    assert "handing id 3 back: pre-arm checks failed" in copter.output


@pytest.mark.parametrize(
    ("fault", "reason", "landing"),
    [
        (["--drop-link-after", 40], "link lost", "vehicle lost"),
        (["--battery", 70, "--drain", 60], "low battery", "vehicle landed"),
    ],
    ids=["lost-link", "low-battery"],
)
def test_a_copter_lost_mid_mission_hands_its_id_to_a_spare(tmp_path, fault, reason, landing):
    """The copter's link drops 40 s after take-off (it flies its failsafe RTL unheard), or
    its battery runs below 25 % (its agent brings it home): either way the agent hands id 3
    back mid-mission and a spare finishes its work."""
    rec_path = tmp_path / "lost.json"
    with Procs() as procs:
        emu, server, address, link = _start(procs, rec_path, *fault)
        viewer = Viewer(address)
        copter = procs.start("mavlink", "agent", "--connect", address, "--id", 3,
                             "--vehicle", link, "--link-timeout", 1)
        sims = procs.start("simulated", "agent", "--connect", address, "--count", 2,
                           "--spares", 1, "--connect-timeout", 60)
        assert server.wait(90) == 0, server.output
        assert copter.wait(15) == 6, copter.output
        assert sims.wait(15) == 0, sims.output
        assert emu.wait(15) == 0, emu.output  # landed, then left alone: it exits
        viewer.stop = True
    net = json.loads(rec_path.read_text())
    assert net["complete"]
    n = net["network"]
    assert [d["id"] for d in n["left"]] == [3] and reason in n["left"][0]["reason"]
    assert [d["id"] for d in n["joined"]] == [3]
    assert [d["id"] for d in n["handed_back"]] == [3]
    (gone,) = net["departed_agents"]
    assert gone["vehicle"]["kind"] == "mavlink" and len(gone["jobs"]) >= 1
    assert [v["kind"] for v in net["vehicles"]] == ["simulated"] * 3
    replay({**net, "agents": net["agents"] + net["departed_agents"]}, free_mask(6, 6, OBSTACLES))
    assert "Land complete" in emu.output and landing in copter.output
    assert ("link dropped" in emu.output) == (reason == "link lost")
    events = viewer.events
    join = [e for e in events if e.get("kind") == "join"]
    left = [e for e in events if e.get("kind") == "left"]
    assert join and join[0]["vehicle"] == "simulated"
    assert left and reason in left[0]["reason"]
