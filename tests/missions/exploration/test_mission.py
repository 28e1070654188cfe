"""The exploration mission behind the Mission contract (issue 12): ``swarmex.run`` equals the
CLI's record, parameters are checked up front naming the option, frames reach ``on_frame``
and ``StopRun`` ends a run."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError
from swarmex.missions.base import StopRun
from swarmex.missions.exploration import ExplorationParams, run_exploration
from swarmex.missions.exploration.frames import FrameRecorder, Snapshot
from swarmex.missions.registry import get
from swarmex.worlds.metric import empty_metric

TINY_MAP = Path(__file__).resolve().parents[2] / "golden" / "tiny.map"


def cli_record(tmp_path: Path, argv: list[str]) -> dict[str, Any]:
    out = tmp_path / "cli.json"
    assert main(["explore", *argv, "--json", str(out)]) in (0, 1)
    return json.loads(out.read_text())


def without_wall(record: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in record.items() if k != "wall_seconds"}


@pytest.mark.parametrize(
    ("kwargs", "argv"),
    [
        (
            {"empty": "3x3", "robots": 2, "laser_range": 1, "comm_range": 2,
             "strategy": "minpos", "seed": 3},
            ["--empty", "3x3", "--robots", "2", "--laser-range", "1", "--comm-range", "2",
             "--strategy", "minpos", "--seed", "3"],
        ),
        (  # Python values: a size tuple, start pairs, booleans
            {"empty": (4, 4), "cell": 0.1, "robots": 3, "starts": [(5, 5), (10, 10), (20, 20)],
             "aodv": False, "conflict_yield": True, "plan_pause": 2, "comm_range": 1.5,
             "seed": 1},
            ["--empty", "4x4", "--cell", "0.1", "--robots", "3", "--starts", "5,5;10,10;20,20",
             "--no-aodv", "--conflict-yield", "--plan-pause", "2", "--comm-range", "1.5",
             "--seed", "1"],
        ),
        (  # a map file, fewer beams, a tick cap (an incomplete run)
            {"map": str(TINY_MAP), "cell": 0.25, "robots": 2, "beams": 180, "max_ticks": 12,
             "robot_radius": 0.1, "strategy": "hungarian", "seed": 2},
            ["--map", str(TINY_MAP), "--cell", "0.25", "--robots", "2", "--beams", "180",
             "--max-ticks", "12", "--robot-radius", "0.1", "--strategy", "hungarian",
             "--seed", "2"],
        ),
        (  # the strategy beyond the seed (issue 17 item 2)
            {"empty": "3x3", "robots": 3, "laser_range": 0.8, "comm_range": 3,
             "strategy": "hungarian-exclusion", "seed": 4},
            ["--empty", "3x3", "--robots", "3", "--laser-range", "0.8", "--comm-range", "3",
             "--strategy", "hungarian-exclusion", "--seed", "4"],
        ),
        (  # issue 17 item 2: pockets first, a lonely robot's rendezvous
            {"empty": "3x3", "robots": 3, "laser_range": 0.6, "comm_range": 1,
             "strategy": "adaptive-exclusion", "seed": 5},
            ["--empty", "3x3", "--robots", "3", "--laser-range", "0.6", "--comm-range", "1",
             "--strategy", "adaptive-exclusion", "--seed", "5"],
        ),
    ],
    ids=["empty-minpos", "python-values", "map-max-ticks", "hungarian-exclusion",
         "adaptive-exclusion"],
)
def test_run_equals_the_cli_record(
    tmp_path: Path, kwargs: dict[str, Any], argv: list[str]
) -> None:
    seed = kwargs.pop("seed")
    rec = swarmex.run("exploration", seed=seed, **kwargs).to_dict()
    assert rec["mission"] == "exploration" and rec["time_unit"] == "step"
    assert without_wall(rec) == without_wall(cli_record(tmp_path, argv))


def test_strings_and_python_values_make_the_same_params() -> None:
    m = get("exploration")
    a = m.params(empty="20x20", robots="3", starts="1,2;3,4;5,6", aodv="false", cell="0.1")
    b = m.params(empty=(20, 20), robots=3, starts=[(1, 2), (3, 4), (5, 6)], aodv=False, cell=0.1)
    assert a == b
    assert a.empty == (20.0, 20.0) and a.starts == ((1, 2), (3, 4), (5, 6))
    assert m.params(empty="3x3", robots=1, starts="").starts is None  # blank: the default start


def test_defaults_live_in_the_params() -> None:
    opts = ExplorationParams.options()
    assert opts["robots"].required
    assert opts["laser_range"].default == 2.0 and opts["comm_range"].default == 10.0
    assert opts["aodv"].default is True and opts["aodv"].negation == "--no-aodv"
    assert {"map", "empty", "cell", "max_ticks", "plan_pause"} <= set(opts)
    # the simulator's own constants are fields, not options
    assert "plan_period" not in opts and ExplorationParams(robots=1).plan_period == 20


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"empty": "3x3", "robots": 0}, "robots"),
        ({"empty": "3x3", "robots": "many"}, "robots"),
        ({"empty": "3x3", "robots": 1, "laser_range": "far"}, "laser_range"),
        ({"empty": "3x3", "robots": 1, "comm_range": -2}, "comm_range"),
        ({"empty": "3x3", "robots": 1, "strategy": "auction"}, "strategy"),
        ({"empty": "3x3", "robots": 1, "beams": 4}, "beams"),
        ({"empty": "3x3", "robots": 1, "max_ticks": 0}, "max_ticks"),
        ({"empty": "3x3", "robots": 1, "plan_pause": -1}, "plan_pause"),
        ({"empty": "3x3", "robots": 1, "cell": 0}, "cell"),
        ({"empty": "3by3", "robots": 1}, "empty"),
        ({"empty": (3, -3), "robots": 1}, "empty"),
        ({"empty": "3x3", "robots": 1, "aodv": "maybe"}, "aodv"),
        ({"empty": "3x3", "robots": 1, "starts": "a;b"}, "starts"),
        ({"empty": "3x3", "robots": 2, "starts": "5,5"}, "starts gives 1 cells for 2 robots"),
        ({"robots": 1}, r"map \(or empty\) is required"),
        ({"empty": "3x3", "map": "x.map", "robots": 1}, "exactly one of map"),
        ({"empty": "3x3"}, "robots"),
        ({"empty": "3x3", "robots": 1, "laser": 2}, "laser_range"),  # the nearest name
    ],
)
def test_bad_params_name_the_parameter(kwargs: dict[str, Any], needle: str) -> None:
    with pytest.raises(InputError, match=needle.replace("-", r"\-")) as err:
        swarmex.run("exploration", **kwargs)
    assert "--" not in str(err.value)  # the keyword, not the command line's flag


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"empty": "3x3", "robots": 1, "starts": "0,0"}, "inside a wall"),
        ({"empty": "3x3", "robots": 1, "starts": "500,5"}, "outside"),
        ({"empty": "3x3", "robots": 1, "cell": 0.5, "laser_range": 0.6}, "--laser-range"),
        ({"map": "/no/such.map", "robots": 1}, "not found"),
        ({"empty": "0.1x0.1", "robots": 1}, "--empty"),
        ({"empty": "1x1", "robots": 40}, "room for (only|at most)"),
    ],
)
def test_world_checks_happen_in_prepare(kwargs: dict[str, Any], needle: str) -> None:
    m = get("exploration")
    params = m.params(kwargs)  # valid without the world
    with pytest.raises(InputError, match=needle):
        m.prepare(params)


def test_params_built_directly_are_checked_by_the_simulator() -> None:
    with pytest.raises(InputError, match="--laser-range"):
        run_exploration(empty_metric(3, 3), ExplorationParams(robots=1, laser_range=-1.0))
    with pytest.raises(InputError, match="--strategy"):
        run_exploration(empty_metric(3, 3), ExplorationParams(robots=1, strategy="auction"))


SMALL = {"empty": "3x3", "robots": 2, "laser_range": 1.0, "comm_range": 2.0, "seed": 1}


def test_on_frame_gets_every_tick_and_leaves_the_record_alone() -> None:
    frames: list[Snapshot] = []
    rec = swarmex.run("exploration", on_frame=frames.append, **SMALL).to_dict()
    assert rec["complete"]
    assert [f.t for f in frames] == list(range(int(rec["makespan"]) + 1))
    last = frames[-1]
    assert isinstance(last, Snapshot) and last.known.shape == (60, 60)
    assert len(last.positions) == 2 and last.known.max() == 2  # walls seen
    assert [list(p) for p in last.positions] == [a["trajectory"][-1][1:] for a in rec["agents"]]
    plain = swarmex.run("exploration", **SMALL).to_dict()
    assert without_wall(rec) == without_wall(plain)


def test_stop_run_ends_the_run_incomplete() -> None:
    seen: list[int] = []

    def stop_at_5(frame: Snapshot) -> None:
        seen.append(frame.t)
        if frame.t == 5:
            raise StopRun

    rec = swarmex.run("exploration", on_frame=stop_at_5, **SMALL).to_dict()
    assert seen == [0, 1, 2, 3, 4, 5]
    assert rec["complete"] is False and rec["makespan"] == 5
    assert all(t <= 5 for a in rec["agents"] for t, _, _ in a["trajectory"])


class Every10:
    def __init__(self) -> None:
        self.ticks: list[int] = []

    def wants(self, t: int) -> bool:
        return t % 10 == 0

    def __call__(self, frame: Snapshot) -> None:
        self.ticks.append(frame.t)


def test_a_callback_that_wants_fewer_frames_gets_only_those() -> None:
    cb = Every10()
    rec = swarmex.run("exploration", on_frame=cb, **SMALL).to_dict()
    assert cb.ticks == list(range(0, int(rec["makespan"]) + 1, 10))


def test_frame_recorder_keeps_at_most_its_limit_evenly_spaced() -> None:
    m = get("exploration")
    params = m.params(SMALL)
    rec = FrameRecorder(limit=8)
    outcome = m.execute(params, m.prepare(params), rec)
    rec.finish(outcome.run)
    ticks = [f.t for f in rec.frames]
    assert len(ticks) <= 9 and ticks[0] == 0 and ticks[-1] == outcome.run.makespan
    assert len({b - a for a, b in zip(ticks[:-2], ticks[1:-1], strict=True)}) == 1


def test_map_takes_a_world_object_and_runs_as_its_file(tmp_path) -> None:
    """A GridWorld read at `cell`, or a MetricGrid, gives the run the file gives (only the
    record's params say "generated"); a MetricGrid's own cell size is not overridden."""
    import swarmex
    from swarmex.errors import InputError
    from swarmex.worlds import load_movingai
    from swarmex.worlds.generators import random_obstacles
    from swarmex.worlds.metric import MetricGrid

    world = random_obstacles(24, 20, 0.15, seed=2)
    path = tmp_path / "w.map"
    rows = ["".join("." if f else "@" for f in row) for row in world.free]
    path.write_text(f"type octile\nheight {len(rows)}\nwidth {len(rows[0])}\nmap\n"
                    + "\n".join(rows) + "\n", encoding="utf-8")
    assert (load_movingai(path).free == world.free).all()
    kw = dict(seed=1, robots=2, max_ticks=60)
    from_file = swarmex.run("exploration", map=path, cell=0.25, **kw).to_dict()
    for given in (dict(map=world, cell=0.25), dict(map=MetricGrid(world, 0.25))):
        rec = swarmex.run("exploration", **given, **kw).to_dict()
        assert rec["agents"] == from_file["agents"] and rec["metrics"] == from_file["metrics"]
        assert rec["params"]["generated"] == world.source
    with pytest.raises(InputError, match="has 0.25 m cells"):
        swarmex.run("exploration", map=MetricGrid(world, 0.25), cell=0.1, **kw)
    with pytest.raises(InputError, match="expected a map file path, a GridWorld"):
        swarmex.run("exploration", map=3, **kw)


def test_a_team_the_map_cannot_hold_is_refused_at_once():
    """10^6 robots on 20 x 20 m took 53 s to be told the map holds 6241; the starts search is
    now linear in the map, and a team beyond one robot per square is refused before it."""
    import time

    import swarmex

    t0 = time.perf_counter()
    with pytest.raises(swarmex.InputError, match="room for at most 6400 robots, not 1000000"):
        swarmex.run("exploration", empty="20x20", robots=1_000_000)
    with pytest.raises(swarmex.InputError, match="room for only 6241 robots, not 6300"):
        swarmex.run("exploration", empty="20x20", robots=6300)
    assert time.perf_counter() - t0 < 20  # each was a minute or more


def test_a_team_whose_maps_cannot_fit_in_memory_is_refused():
    """Each robot keeps its own map: robots x cells. A team accepted by every other check
    grew until the kernel killed it without a word (no swap)."""
    from swarmex.missions.exploration.params import check_memory

    gib = 2**30
    eight = lambda: 8 * gib  # noqa: E731
    check_memory(100, 640_000, available=eight)  # bench_scale's 100 robots on 40 x 40 m
    with pytest.raises(InputError, match=r"100 robots on 25,000,000 cells need about 23.3 GiB"
                                         r" of maps .* more than the 8.0 GiB available"):
        check_memory(100, 25_000_000, available=eight)
    check_memory(10**6, 10**9, available=lambda: None)  # unknown memory: no guess
