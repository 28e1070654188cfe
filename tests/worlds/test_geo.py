"""GPS grids (issue 15, item 3): seed 000's K x K grid around a latitude and longitude,
positions and edge lengths geodesic (pyproj), checked against pyproj's own inverse problem
and against the seed's printed example (docs/uav.md, "GPS grids")."""

from __future__ import annotations

import json
import math
import sys
from typing import Any

import numpy as np
import pytest

pyproj = pytest.importorskip("pyproj")

import swarmex  # noqa: E402
from swarmex.cli import main  # noqa: E402
from swarmex.errors import InputError  # noqa: E402
from swarmex.worlds.geo import GeoGrid, gps_grid  # noqa: E402

GEOD = pyproj.Geod(ellps="WGS84")
SEED_CENTER = (43.268304, -79.911135)  # seed 000 §4.3: -radius 50 -nodesOnEdge 9
SEED_NODE1 = (43.267849, -79.911591)  # its printed "[1, 43.267849, -79.911591, 0]"


def _inv(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    az, _, dist = GEOD.inv(a[1], a[0], b[1], b[0])
    return az, dist


def test_nodes_are_geodesic_offsets_from_the_centre_row_0_north() -> None:
    k, r = 9, 50.0
    world = gps_grid(SEED_CENTER, r, k)
    assert world.width == world.height == k and world.edge_m == 12.5
    s = 2 * r / (k - 1)
    for node in range(k * k):
        x, y = world.xy(node)
        east, north = -r + x * s, r - y * s
        if east == north == 0:
            assert world.latlon(node) == pytest.approx(SEED_CENTER, abs=1e-12)
            continue
        az, dist = _inv(SEED_CENTER, world.latlon(node))
        assert dist == pytest.approx(math.hypot(east, north), abs=1e-6)
        assert az == pytest.approx(math.degrees(math.atan2(east, north)), abs=1e-6)
    lat = world.latlon_array[:, 0].reshape(k, k)
    lon = world.latlon_array[:, 1].reshape(k, k)
    assert np.all(np.diff(lat, axis=0) < 0) and np.all(np.diff(lon, axis=1) > 0)


def test_edges_are_as_long_as_the_geodesics() -> None:
    world = gps_grid((60.0, 10.0), 200.0, 5, connectivity=8)
    g = world.graph
    for u in range(g.n_nodes):
        for v, w in zip(g.neighbors(u), g.neighbor_weights(u), strict=True):
            assert w == pytest.approx(_inv(world.latlon(u), world.latlon(int(v)))[1], rel=1e-12)
    straight = [w for u in range(g.n_nodes) for v, w in zip(g.neighbors(u),
                g.neighbor_weights(u), strict=True) if abs(int(v) - u) in (1, 5)]
    assert np.allclose(straight, 100.0, atol=1e-3)  # 2R / (K - 1), to a millimetre


def test_the_record_lists_every_node_and_travel_follows_real_distances() -> None:
    rec = swarmex.run("traversal", center=SEED_CENTER, radius=50, nodes_on_edge=9, seed=3,
                      fleet=[{"id": 1, "travel_speed": 3.0}, {"id": 2, "travel_speed": 2.0,
                                                               "nest": "8,8"}]).to_dict()
    w = rec["world"]
    assert w["kind"] == "grid" and w["nodes_on_edge"] == 9 and w["center"] == list(SEED_CENTER)
    latlon = w["nodes_latlon"]
    assert len(latlon) == 81 and latlon[40] == pytest.approx(list(SEED_CENTER), abs=1e-12)
    assert rec["params"]["center"] == list(SEED_CENTER) and rec["params"]["radius"] == 50
    assert rec["complete"]
    for agent, speed in zip(rec["agents"], (3.0, 2.0), strict=True):
        traj = agent["trajectory"]
        jobs = {(t, x, y) for t, x, y in agent["jobs"]}
        flown = 0.0
        for (t0, x0, y0), (t1, x1, y1) in zip(traj, traj[1:], strict=False):
            a, b = latlon[int(y0) * 9 + int(x0)], latlon[int(y1) * 9 + int(x1)]
            dist = _inv(tuple(a), tuple(b))[1]
            flown += dist / speed
            assert dist == pytest.approx(12.5, abs=1e-3)
            # the arrival follows the departure (or the end of the job there) by the flight
            job = agent["metrics"]["job_time"] / max(len(jobs), 1) if (t0, x0, y0) in jobs else 0
            assert t1 - t0 == pytest.approx(job + dist / speed, rel=1e-9)
        assert agent["metrics"]["travel_time"] == pytest.approx(flown, rel=1e-12)


def test_the_seeds_printed_example_compared() -> None:
    """The figures docs/uav.md quotes: the seed's node 1 lies 50.55 m south and 37.02 m west
    of its centre (a degree grid: 0.000101 degrees both ways), ours 50 m and 50 m; the two
    south-west corners are 13.0 m apart, almost all of it east-west."""
    _, south = _inv(SEED_CENTER, (SEED_NODE1[0], SEED_CENTER[1]))
    _, west = _inv((SEED_NODE1[0], SEED_CENTER[1]), SEED_NODE1)
    assert south == pytest.approx(50.55, abs=0.01) and west == pytest.approx(37.02, abs=0.01)
    ours = gps_grid(SEED_CENTER, 50.0, 9)
    corner = ours.latlon(ours.node(0, 8))
    assert corner == pytest.approx((43.267854, -79.911751), abs=5e-7)
    assert _inv(corner, SEED_NODE1)[1] == pytest.approx(13.0, abs=0.05)
    # the seed's spacing north-south: node 1 -> node 5 is 4 steps of 11.22 m
    _, four = _inv(SEED_NODE1, (43.268253, SEED_NODE1[1]))
    assert four / 4 == pytest.approx(11.22, abs=0.01)


def test_obstacles_and_the_wire_round_trip() -> None:
    from swarmex.missions.traversal.agents import uniform_agents
    from swarmex.missions.traversal.sim import run_traversal
    from swarmex.net.traversal import Mission, run_inprocess

    world = gps_grid((-33.86, 151.21), 30.0, 6)
    free = world.free.copy()
    free[2, 1:4] = False
    world = world.with_free(free)
    specs = uniform_agents([0, 35], 2.22, 10.0, world.edge_m)
    mission = Mission(world, specs, seed=2)
    back = Mission.from_wire(mission.to_wire())
    assert isinstance(back.world, GeoGrid) and back.world.center == world.center
    assert np.array_equal(back.world.latlon_array, world.latlon_array)
    assert np.array_equal(back.world.graph.weights, world.graph.weights)
    cores, recorder = run_inprocess(back)
    run = run_traversal(world, specs, "madgta", 2)
    for sim_log, (_, core) in zip(run.agents, sorted(cores.items()), strict=True):
        assert core.log.trajectory == sim_log.trajectory
        assert core.log.travel_time == sim_log.travel_time
    assert back.latlon(0) == world.latlon(0)


BAD = [
    (["--center", "43.2,-79.9", "--nodes-on-edge", "9"], "--center needs --radius"),
    (["--center", "43.2,-79.9", "--radius", "50"], "--center needs --nodes-on-edge"),
    (["--center", "95,-79.9", "--radius", "50", "--nodes-on-edge", "9"], "latitude"),
    (["--center", "43.2", "--radius", "50", "--nodes-on-edge", "9"], "expected LAT,LON"),
    # a grid round a pole: its "grid" nodes sat at longitudes ±45/±90/±135
    (["--center", "89.9999,179.9999", "--radius", "100000", "--nodes-on-edge", "3"],
     "--center 89.9999,179.9999 with --radius 100000: the grid reaches the north pole"),
    (["--center", "-89.2,10", "--radius", "100000", "--nodes-on-edge", "3"], "south pole"),
    (["--center", "43.2,-79.9", "--radius", "50", "--nodes-on-edge", "1"],
     "--nodes-on-edge must be at least 2"),
    (["--center", "43.2,-79.9", "--radius", "0", "--nodes-on-edge", "3"],
     "--radius must be greater than 0"),
    (["--center", "43.2,-79.9", "--radius", "50", "--nodes-on-edge", "3", "--grid", "3x3"],
     "exactly one of"),
    (["--grid", "3x3", "--radius", "50"], "--radius belongs to a GPS grid"),
    (["--center", "43.2,-79.9", "--radius", "50", "--nodes-on-edge", "3",
      "--edge-length", "5"], "geodesic lengths"),
    (["--center", "43.2,-79.9", "--radius", "50", "--nodes-on-edge", "3",
      "--obstacles", "3,0"], "outside the 3x3 map"),
]


@pytest.mark.parametrize(("argv", "message"), BAD)
def test_bad_gps_options_exit_2_with_one_line(argv: list[str], message: str,
                                              capsys: Any) -> None:
    code = main(["traverse", "--agents", "2", *argv])
    out, err = capsys.readouterr()
    assert code == 2, out
    assert err.count("\n") == 1 and message in err, err


def test_a_grid_near_a_pole_that_does_not_contain_it_is_built() -> None:
    from swarmex.worlds.geo import gps_grid

    grid = gps_grid((89.0, 0.0), 80_000, 3)  # 111.7 km from the pole: the north edge at 80
    assert grid.latlon(1)[0] < 90.0 and grid.latlon(1)[0] > 89.7


def test_toml_and_cli_give_the_python_record(tmp_path: Any, capsys: Any) -> None:
    py = swarmex.run("traversal", center="43.268304,-79.911135", radius=20, nodes_on_edge=4,
                     agents=2, seed=1).to_dict()
    scenario = tmp_path / "gps.toml"
    scenario.write_text('mission = "traversal"\ncenter = [43.268304, -79.911135]\n'
                        "radius = 20\nnodes_on_edge = 4\nagents = 2\nseed = 1\n")
    out = tmp_path / "r.json"
    assert main(["run", str(scenario), "--json", str(out)]) == 0
    capsys.readouterr()
    strip = lambda r: {k: v for k, v in r.items() if k != "wall_seconds"}  # noqa: E731
    assert strip(json.loads(out.read_text())) == strip(py)


def test_without_pyproj_one_line_names_the_extra(monkeypatch: Any) -> None:
    monkeypatch.setitem(sys.modules, "pyproj", None)  # an import of it now fails
    with pytest.raises(InputError, match=r"pip install 'swarmex\[geo\]'"):
        gps_grid(SEED_CENTER, 50.0, 3)
