"""``swarmex serve`` with a fleet file on a GPS grid (issue 15, items 1 and 3), end to end:
the networked record is ``swarmex traverse``'s with the same options (bar the wall clock,
message bytes and the network block), per-agent values and ``world.nodes_latlon`` included."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.net.netproc import Procs, endpoint

pytest.importorskip("pyproj")
pytestmark = pytest.mark.timeout(90)

FLEET = """\
id,nest,altitude,travel_speed,job_time,up_speed,down_speed
1,"0,0",5,3.0,10,1.5,0.3
2,"4,4",15,2.0,12,2.5,0.5
3,,,,6,,
"""
OPTIONS = ["--center", "43.268304,-79.911135", "--radius", "20", "--nodes-on-edge", "5",
           "--obstacles", "2,1;2,2", "--seed", "3"]


def test_serve_flies_the_fleet_on_the_gps_grid_as_traverse_does(tmp_path: Path) -> None:
    from swarmex.cli import main

    fleet = tmp_path / "fleet.csv"
    fleet.write_text(FLEET)
    sim_path, net_path = tmp_path / "sim.json", tmp_path / "net.json"
    assert main(["traverse", *OPTIONS, "--fleet", str(fleet), "--json", str(sim_path)]) == 0
    with Procs() as procs:
        server = procs.start("server", "serve", *OPTIONS, "--fleet", fleet, "--port", 0,
                             "--time-scale", 0, "--timeout", 60, "--json", net_path)
        address = endpoint(server)
        agents = procs.start("agents", "agent", "--connect", address, "--count", 3,
                             "--server-timeout", 20)
        assert server.wait(75) == 0, server.output
        assert agents.wait(15) == 0, agents.output
    sim, net = json.loads(sim_path.read_text()), json.loads(net_path.read_text())
    assert net["complete"] and net["makespan"] == sim["makespan"]
    assert net["world"] == sim["world"] and len(net["world"]["nodes_latlon"]) == 25
    net_params = {k: v for k, v in net["params"].items() if k != "network"}
    assert net_params == sim["params"]
    speeds = [r["travel_speed"] for r in net["params"]["fleet"]]
    assert speeds == [3.0, 2.0, pytest.approx(10.0 / 2.22)]  # edges of 2R / (K - 1) = 10 m
    for x, y in zip(net["agents"], sim["agents"], strict=True):
        assert x["trajectory"] == y["trajectory"] and x["metrics"] == y["metrics"]


def test_serve_refuses_a_bad_fleet_row_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from swarmex.cli import main

    fleet = tmp_path / "fleet.toml"
    fleet.write_text('[[agents]]\nid = 1\n[[agents]]\nid = 2\nup_speed = "fast"\n')
    assert main(["serve", "--grid", "5x5", "--fleet", str(fleet), "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "--fleet" in err and "agent 2: up_speed: expected a number, got 'fast'" in err
