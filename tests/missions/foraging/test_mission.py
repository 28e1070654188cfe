"""The foraging mission behind the Mission contract: ``swarmex.run("foraging", ...)`` is the
CLI's run, bad parameters are InputErrors naming the option, and ``on_frame`` sees every round
(and can stop the run) without changing the record."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError
from swarmex.missions.base import StopRun
from swarmex.missions.foraging import replay
from swarmex.missions.foraging.mission import ForagingMission
from swarmex.missions.foraging.params import MAX_GRID, ForagingParams
from swarmex.missions.foraging.sim import Frame
from swarmex.missions.registry import get, names


def cli_record(tmp_path: Path, argv: list[str]) -> dict[str, Any]:
    out = tmp_path / "r.json"
    assert main(["forage", *argv, "--json", str(out)]) == 0
    rec = json.loads(out.read_text())
    rec.pop("wall_seconds")
    return rec


def api_record(seed: int = 0, on_frame: Any = None, **params: Any) -> dict[str, Any]:
    rec = swarmex.run("foraging", seed=seed, on_frame=on_frame, **params).to_dict()
    rec.pop("wall_seconds")
    return rec


SAME_RUNS = [  # (CLI argv, swarmex.run keywords: Python values or the CLI's strings)
    (
        ["--grid", "16", "--agents", "8", "--algorithm", "sectors", "--food-distance", "20-60",
         "--food-units", "10", "--seed", "3"],
        {"grid": 16, "agents": 8, "algorithm": "sectors", "food_distance": (20, 60),
         "food_units": 10, "seed": 3},
    ),
    (
        ["--grid", "20", "--agents", "8", "--algorithm", "sectors", "--transport", "end-to-end",
         "--food", "15,3", "--food-units", "20", "--seed", "1"],
        {"grid": "20", "agents": "8", "algorithm": "sectors", "transport": "end-to-end",
         "food": (15, 3), "food_units": "20", "seed": 1},
    ),
    (
        ["--grid", "16", "--agents", "2", "--algorithm", "spiral", "--seed", "9"],
        {"grid": 16, "agents": 2, "algorithm": "spiral", "seed": 9},
    ),
    (
        ["--grid", "16", "--agents", "4", "--algorithm", "loop-strips", "--transport",
         "relay-path", "--food", "2,13", "--food-units", "6"],
        {"grid": 16, "agents": 4, "algorithm": "Loop-Strips", "transport": "relay-path",
         "food": "2,13", "food_units": 6},
    ),
    (
        ["--grid", "32", "--agents", "8", "--algorithm", "sector-loop", "--food-distance",
         "60-100", "--food-units", "8", "--seed", "4"],
        {"grid": 32, "agents": 8, "algorithm": "sector-loop", "food_distance": "60-100",
         "food_units": 8, "seed": 4},
    ),
    (
        ["--grid", "32", "--agents", "8", "--algorithm", "comb", "--food", "5,27",
         "--transport", "end-to-end", "--food-units", "5"],
        {"grid": 32, "agents": 8, "algorithm": "comb", "food": (5, 27),
         "transport": "end-to-end", "food_units": 5},
    ),
]  # fmt: skip


@pytest.mark.parametrize(("argv", "kw"), SAME_RUNS)
def test_run_is_the_cli_record(tmp_path, argv, kw):
    kw = dict(kw)
    seed = kw.pop("seed", 0)
    cli = cli_record(tmp_path, argv)
    api = api_record(seed, **kw)
    assert api == cli
    # the params dict, keys in order, as the command wrote it before the contract
    assert list(api["params"]) == [
        "grid", "agents", "algorithm", "transport", "comm", "food", "food_units", "nest",
        "food_distance", "seed",
    ]  # fmt: skip
    assert replay(api) == []


def test_python_band_is_recorded_as_the_cli_string():
    a = api_record(3, grid=16, agents=8, algorithm="sectors", food_distance=(20, 60))
    assert a["params"]["food_distance"] == "20-60"


def test_registry_and_params():
    mission = get("foraging")
    assert isinstance(mission, ForagingMission)
    assert (mission.name, mission.command, mission.time_unit) == ("foraging", "forage", "step")
    assert "foraging" in names()
    assert names() == swarmex.missions()  # callable, and the subpackage's names resolve too
    assert swarmex.missions.foraging.mission.ForagingMission is ForagingMission
    opts = ForagingParams.options()
    assert list(opts) == [
        "grid", "agents", "algorithm", "transport", "comm", "food", "food_distance", "food_units",
        "found", "seed",
    ]  # fmt: skip
    assert {k: o.default for k, o in opts.items() if not o.required} == {
        "transport": "relay-food",
        "comm": "seed",
        "food": None,
        "food_distance": None,
        "food_units": 100,
        "found": (),
        "seed": 0,
    }
    assert opts["food_distance"].flag == "--food-distance"


BAD = [  # (keywords, text the message must contain: the parameter it names)
    ({"comm": "telepathy"}, "comm"),
    ({"grid": 1}, "grid"),
    ({"grid": MAX_GRID + 1}, "grid must be at most"),
    ({"grid": "big"}, "grid"),
    ({"agents": 0}, "agents"),
    ({"agents": 10**6}, "agents"),
    ({"agents": 3}, "agents"),  # strips: g a multiple of n
    ({"algorithm": "twin-strips"}, "algorithm"),
    ({"algorithm": 3}, "algorithm"),
    ({"transport": "teleport"}, "transport"),
    ({"food": (16, 0)}, "food"),
    ({"food": "8,8"}, "food"),
    ({"food": "x"}, "food"),
    ({"food_distance": "9"}, "food_distance"),
    ({"food_distance": (60, 20)}, "food_distance"),
    ({"food": (1, 1), "food_distance": "0-20"}, "food_distance"),
    ({"food_units": 0}, "food_units"),
    ({"food_units": 2.5}, "food_units"),
    ({"seed": -1}, "seed"),
    ({"food_unit": 3}, "food_units"),  # unknown: the nearest name
]


@pytest.mark.parametrize(("kw", "needle"), BAD)
def test_bad_params_raise_input_error_naming_the_parameter(kw, needle):
    params = {"grid": 16, "agents": 4, "algorithm": "strips", **kw}
    seed = params.pop("seed", 0)
    with pytest.raises(InputError, match=needle) as err:
        swarmex.run("foraging", seed=seed, **params)
    assert "--" not in str(err.value)  # the keyword, not the command line's flag


def test_empty_band_is_refused_before_the_run():
    mission = get("foraging")
    params = mission.params(grid=16, agents=4, algorithm="strips", food_distance="0-1")
    with pytest.raises(InputError, match="--food-distance"):
        mission.prepare(params)


# ---------------------------------------------------------------------------- frames

FRAME_RUNS = [  # runs whose transport tail is long (the compiled loop's part)
    {"grid": 16, "agents": 8, "algorithm": "sectors", "food": "3,12", "food_units": 12},
    {"grid": 20, "agents": 8, "algorithm": "sectors", "transport": "end-to-end",
     "food": "15,3", "food_units": 20},
    {"grid": 16, "agents": 4, "algorithm": "strips", "transport": "relay-path",
     "food_distance": "60-80", "food_units": 9},
]  # fmt: skip


@pytest.mark.parametrize("kw", FRAME_RUNS)
def test_frames_are_every_round_and_leave_the_record_unchanged(kw):
    frames: list[Frame] = []
    with_frames = api_record(5, on_frame=frames.append, **kw)
    plain = api_record(5, **kw)
    assert with_frames == plain  # the compiled tail played round by round: same record
    assert with_frames["complete"] is True
    makespan = int(plain["makespan"])
    assert [f.t for f in frames] == list(range(makespan + 1))
    traj = np.asarray([[row[1:] for row in a["trajectory"]] for a in plain["agents"]])
    for f in frames:
        assert np.array_equal(f.positions, traj[:, f.t]), f.t
    # counts against the record's jobs: units home and left at the food after each Look
    jobs = [j for a in plain["agents"] for j in a["jobs"]]
    k = plain["params"]["food_units"]
    for f in frames:
        drops = sum(1 for t, _x, _y, kind in jobs if kind == "drop" and t <= f.t)
        picks = sum(1 for t, _x, _y, kind in jobs if kind == "pickup" and t <= f.t)
        assert (f.delivered, f.food_left) == (drops, k - picks), f.t
        assert int(f.carrying.sum()) == picks - drops, f.t
    informed_at = [a["metrics"]["informed_at"] for a in plain["agents"]]
    for f in frames:
        expect = [at is not None and at <= f.t for at in informed_at]
        assert f.informed.tolist() == expect, f.t
    assert frames[-1].delivered == k


def test_frames_match_the_python_loop():
    """The Python loop (fast=False) and the compiled tail played round by round agree."""
    from swarmex.missions.foraging.sim import run_mission
    from swarmex.missions.foraging.timed import timed_plan

    timed = timed_plan("sectors", 20, 8)
    slow: list[Frame] = []
    fast: list[Frame] = []
    a = run_mission(timed, (15, 3), 20, "end-to-end", fast=False, on_frame=slow.append)
    b = run_mission(timed, (15, 3), 20, "end-to-end", fast=True, on_frame=fast.append)
    assert np.array_equal(a.positions, b.positions) and a.jobs == b.jobs
    assert len(slow) == len(fast) == a.makespan + 1
    for x, y in zip(slow, fast, strict=True):
        assert x.t == y.t and (x.delivered, x.food_left) == (y.delivered, y.food_left)
        assert np.array_equal(x.positions, y.positions)
        assert np.array_equal(x.carrying, y.carrying)
        assert np.array_equal(x.informed, y.informed)


def stop_at(t_stop: int):
    def on_frame(frame: Frame) -> None:
        if frame.t == t_stop:
            raise StopRun

    return on_frame


@pytest.mark.parametrize("where", ["exploring", "communicating", "transporting"])
def test_stop_run_ends_the_run_early(where):
    kw = FRAME_RUNS[1]
    full = api_record(5, **kw)
    found = full["metrics"]["exploration_time"]
    last_comm = max(a["metrics"]["comm_done_at"] for a in full["agents"])
    t_stop = {
        "exploring": found // 2,
        "communicating": found + 1,
        "transporting": (last_comm + int(full["makespan"])) // 2,
    }[where]
    assert 0 < t_stop < full["makespan"]
    rec = api_record(5, on_frame=stop_at(t_stop), **kw)
    assert rec["complete"] is False and rec["makespan"] == t_stop
    assert rec["params"] == full["params"]
    for a, b in zip(rec["agents"], full["agents"], strict=True):
        assert a["trajectory"] == b["trajectory"][: t_stop + 1]
        assert a["jobs"] == [j for j in b["jobs"] if j[0] <= t_stop]
    assert replay(rec) == []  # what was played is still a valid run
    m = rec["metrics"]
    assert m["total_time"] == t_stop
    assert m["all_informed"] is (where == "transporting")
    assert m["food_delivered"] == sum(1 for a in rec["agents"] for j in a["jobs"] if j[3] == "drop")
    if where == "exploring":
        assert m["exploration_time"] is None
        assert all(a["metrics"]["informed_at"] is None for a in rec["agents"])
    else:
        assert m["exploration_time"] == found


def test_stop_run_on_the_first_frame():
    rec = api_record(0, on_frame=stop_at(0), grid=16, agents=4, algorithm="strips")
    assert rec["complete"] is False and rec["makespan"] == 0
    assert all(len(a["trajectory"]) == 1 for a in rec["agents"])


def test_relay_food_joins_at_the_food_and_relay_path_at_the_nearest_path_cell():
    """Transport docstring: Relay-Food walks to the food and enters the relay path there;
    Relay-Path walks to the nearest path cell (ties toward the food) and enters empty."""
    from swarmex.missions.foraging.sim import Mission
    from swarmex.missions.foraging.transport import RELAY_FOOD, RELAY_PATH

    nest, food = (0, 0), (5, 3)  # the path: (0,0) … (5,0) along the row, then up to (5,3)
    for transport, want in [(RELAY_FOOD, food), (RELAY_PATH, (3, 0))]:
        m = Mission(8, nest, food, 1, transport, [(3, 1)])
        m.enter_transport(0)
        assert m.path[m.join_at[0]] == want, transport
    # Relay-Path tie: (4, 1) is 1 from both (4, 0) and (5, 1); the one nearer the food wins
    m = Mission(8, nest, food, 1, RELAY_PATH, [(4, 1)])
    m.enter_transport(0)
    assert m.path[m.join_at[0]] == (5, 1)
