"""The roadmap mission behind the contract: ``swarmex.run("roadmap", ...)`` is the CLI's run,
its parameters are checked up front and named, and ``on_frame`` sees every step (and can stop
the run)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError
from swarmex.missions.base import StopRun
from swarmex.missions.registry import get
from swarmex.missions.roadmap import replay_problems
from swarmex.missions.roadmap.params import RASTER_CELLS, RoadmapParams, SensorRange
from swarmex.missions.roadmap.sim import RoadmapFrame
from swarmex.sensing.coverage_raster import DEFAULT_CELLS
from swarmex.worlds.polygon import load_polygon_world

from .conftest import CLUTTER


@pytest.fixture
def env(tmp_path: Path) -> Path:
    p = tmp_path / "clutter.json"
    p.write_text(json.dumps(CLUTTER))
    return p


def cli_record(tmp_path: Path, argv: list[str]) -> dict[str, Any]:
    out = tmp_path / "cli.json"
    assert main(["roadmap", *argv, "--json", str(out)]) == 0
    return json.loads(out.read_text())


def without_wall(record: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in record.items() if k != "wall_seconds"}


# (CLI argv, the same run as Python keyword values); {env} is the environment file
CASES = [
    (
        ["--agents", "3", "--nodes", "60", "--step", "12", "--sensor-range", "1eps",
         "--seed", "1"],
        {"agents": 3, "nodes": 60, "step": 12.0, "sensor_range": "1eps", "seed": 1},
    ),
    (
        ["--task", "search", "--planner", "wma-rrt-takeover", "--agents", "3", "--nodes", "80",
         "--step", "10", "--sensor-range", "inf", "--starts", "10,10;16,10;13,15",
         "--goal", "150.5,120", "--seed", "2"],
        {"task": "search", "planner": "wma-rrt-takeover", "agents": 3, "nodes": 80, "step": 10,
         "sensor_range": math.inf, "starts": [(10, 10), (16, 10), (13, 15)],
         "goal": (150.5, 120), "seed": 2},
    ),
    (
        ["--planner", "prm", "--agents", "2", "--nodes", "50", "--step", "15",
         "--sensor-range", "25", "--step-budget", "40", "--raster", "64", "--seed", "3"],
        {"planner": "prm", "agents": "2", "nodes": "50", "step": "15", "sensor_range": 25.0,
         "step_budget": 40, "raster": 64, "seed": 3},
    ),
    (
        ["--task", "search", "--planner", "wma-rrt-fairshare", "--agents", "3", "--nodes",
         "80", "--step", "10", "--sensor-range", "20", "--goal", "150,120", "--seed", "4"],
        {"task": "search", "planner": "wma-rrt-fairshare", "agents": 3, "nodes": 80,
         "step": 10, "sensor_range": 20, "goal": "150,120", "seed": 4},
    ),
]


@pytest.mark.parametrize(("argv", "values"), CASES,
                         ids=["strings-eps", "search-python", "prm", "fairshare"])
def test_python_run_is_the_cli_run(env: Path, tmp_path: Path, argv: list[str],
                                   values: dict[str, Any]) -> None:
    cli = cli_record(tmp_path, ["--env", str(env), *argv])
    seed = values.pop("seed")
    rec = swarmex.run("roadmap", env=str(env), seed=seed, **values).to_dict()
    assert without_wall(rec) == without_wall(cli)
    assert replay_problems(rec, load_polygon_world(env)) == []


def test_a_loaded_world_is_the_same_as_its_file(env: Path) -> None:
    kw: dict[str, Any] = {"agents": 2, "nodes": 40, "step": 12, "sensor_range": "2ε"}
    from_file = swarmex.run("roadmap", env=env, **kw).to_dict()
    from_world = swarmex.run("roadmap", env=load_polygon_world(env), **kw).to_dict()
    assert without_wall(from_file) == without_wall(from_world)
    assert from_file["params"]["sensor_range"] == 24.0


def test_params_read_strings_and_python_values(env: Path) -> None:
    p = RoadmapParams.from_values(env=str(env), agents="2", nodes=10, step="4.5",
                                  sensor_range="0.5*eps", goal="1.5, 2", starts="1,2;3.5,4;")
    assert p.env == env and p.agents == 2 and p.step == 4.5
    assert p.sensor_range == SensorRange(0.5, per_step=True) and p.range_length == 2.25
    assert p.goal == (1.5, 2.0) and p.starts == ((1.0, 2.0), (3.5, 4.0))
    q = RoadmapParams.from_values(env=env, agents=2, nodes=10, step=4.5,
                                  sensor_range=float("inf"), goal=np.array([1.5, 2]),
                                  starts=np.array([[1, 2], [3.5, 4]]))
    assert q.goal == p.goal and q.starts == p.starts and math.isinf(q.range_length)
    assert (q.task, q.planner, q.seed, q.step_budget, q.raster) == (
        "coverage", "wma-rrt", 0, None, 256)
    assert RASTER_CELLS == DEFAULT_CELLS  # the Params' default is the raster's own


BAD: list[tuple[dict[str, Any], str]] = [
    ({"agents": "three"}, "agents"),
    ({"agents": 0}, "agents"),
    ({"nodes": 2}, "fewer than agents"),
    ({"step": 0}, "step"),
    ({"step": float("nan")}, "step"),
    ({"sensor_range": "far"}, "sensor_range"),
    ({"sensor_range": 0}, "sensor_range"),
    ({"sensor_range": "-2eps"}, "multiple of ε"),
    ({"sensor_range": True}, "sensor_range"),
    ({"task": "sweep"}, "task"),
    ({"planner": "rrt*"}, "planner"),
    ({"goal": "1,2;3,4"}, "goal"),
    ({"goal": (1.0,)}, "goal"),
    ({"goal": "x,2"}, "goal"),
    ({"starts": "10,10;12,12"}, "2 positions for agents 3"),
    ({"starts": "10;12,12;5,5"}, "starts"),
    ({"starts": ""}, "starts"),
    ({"step_budget": 0}, "step_budget"),
    ({"raster": 4}, "raster"),
    ({"raster": 10**6}, "raster must be at most"),
    ({"seed": -1}, "seed must be at least 0"),
    ({"env": 42}, "env"),
    ({"sensor": 20}, "did you mean 'sensor_range'"),
]


@pytest.mark.parametrize(("change", "needle"), BAD, ids=[b[1] + str(i) for i, b in enumerate(BAD)])
def test_bad_params_name_the_parameter(env: Path, change: dict[str, Any], needle: str) -> None:
    kw: dict[str, Any] = {"env": env, "agents": 3, "nodes": 30, "step": 10,
                          "sensor_range": 20, **change}
    if "sensor" in change:
        kw.pop("sensor_range")
    with pytest.raises(InputError, match=needle) as err:
        swarmex.run("roadmap", **kw)
    assert "--" not in str(err.value)  # the keyword, not the command line's flag


@pytest.mark.parametrize(
    ("change", "needle"),
    [
        ({"env": "missing.json"}, "not found"),
        ({"task": "search", "goal": None, "env": "nogoal"}, "needs a goal"),
        ({"task": "search", "goal": "50,45"}, "inside an obstacle"),
        ({"goal": "300,10"}, "outside the bounds"),
        ({"starts": "50,45;10,10;12,12"}, "inside an obstacle"),
    ],
)
def test_world_checks_happen_in_prepare(env: Path, tmp_path: Path, change: dict[str, Any],
                                        needle: str) -> None:
    if change.get("env") == "nogoal":
        change["env"] = tmp_path / "nogoal.json"
        change["env"].write_text(json.dumps({"bounds": [0, 0, 100, 100], "obstacles": []}))
    elif change.get("env") == "missing.json":
        change["env"] = tmp_path / "missing.json"
    mission = get("roadmap")
    params = mission.params({"env": env, "agents": 3, "nodes": 30, "step": 10,
                             "sensor_range": 20, **change})  # valid without the world
    with pytest.raises(InputError, match=needle):
        mission.prepare(params)


def test_a_missing_required_option_is_named(env: Path) -> None:
    with pytest.raises(InputError, match="sensor_range is required"):
        swarmex.run("roadmap", env=env, agents=2, nodes=10, step=5)


def test_on_frame_sees_every_step_and_changes_nothing(env: Path) -> None:
    kw: dict[str, Any] = {"env": env, "task": "search", "agents": 3, "nodes": 80, "step": 10,
                          "sensor_range": 15, "seed": 4}
    frames: list[RoadmapFrame] = []
    rec = swarmex.run("roadmap", on_frame=frames.append, **kw).to_dict()
    assert without_wall(rec) == without_wall(swarmex.run("roadmap", **kw).to_dict())
    steps = rec["metrics"]["steps"]
    assert [f.step for f in frames] == list(range(steps + 1))
    for f in frames:  # each frame's positions are the trajectories' at that step
        for i, tr in enumerate(rec["agents"]):
            held = [p for p in tr["trajectory"] if p[0] <= f.step][-1]
            assert np.allclose(f.positions[i], held[1:])
            assert (i in f.moved) == (held[0] == f.step and f.step > 0)
    assert frames[-1].coverage == pytest.approx(rec["metrics"]["coverage"], abs=1e-6)
    assert frames[-1].goal_found == rec["metrics"]["goal_found"]
    assert frames[-1].edge_traversals.tolist() == rec["board"]["edge_traversals"]
    assert [c for c in frames[0].edge_traversals] == [0] * frames[0].roadmap.n_edges
    assert frames[-1].states == tuple(a["metrics"]["final_state"] for a in rec["agents"])


def test_stop_run_ends_early_and_incomplete(env: Path) -> None:
    kw: dict[str, Any] = {"env": env, "agents": 3, "nodes": 80, "step": 10,
                          "sensor_range": 15, "seed": 4}
    full = swarmex.run("roadmap", **kw).to_dict()
    assert full["complete"] and full["metrics"]["steps"] > 5

    def stop_at_5(frame: RoadmapFrame) -> None:
        if frame.step == 5:
            raise StopRun

    rec = swarmex.run("roadmap", on_frame=stop_at_5, **kw).to_dict()
    assert rec["complete"] is False and rec["makespan"] == 5 == rec["metrics"]["steps"]
    assert not rec["metrics"]["budget_exhausted"]
    for a, b in zip(rec["agents"], full["agents"], strict=True):  # the same run, cut short
        assert a["trajectory"] == [p for p in b["trajectory"] if p[0] <= 5]
    assert replay_problems(rec, load_polygon_world(env)) == []

    def stop_at_once(frame: RoadmapFrame) -> None:
        raise StopRun

    rec0 = swarmex.run("roadmap", on_frame=stop_at_once, **kw).to_dict()
    assert rec0["complete"] is False and rec0["metrics"]["steps"] == 0
    assert all(len(a["trajectory"]) == 1 for a in rec0["agents"])
