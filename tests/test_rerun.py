"""``swarmex.rerun`` and ``swarmex rerun``: a record runs again into the same record.

The check is independent of the mission code's own bookkeeping: the first run's whole JSON
(trajectories, jobs, every metric) must come back byte for byte, ``wall_seconds`` aside,
from nothing but the record. The cases are the ones where a record's params are not the
options a user passes (derived nests and starts, a drawn food cell, an ``--empty`` world kept
only in ``record.world``, a radio range of None, ``raster_cells``, a fleet, GPS worlds).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError

MAPS = Path(__file__).resolve().parents[2] / "shared" / "maps"
ENV = {"bounds": [0, 0, 200, 150], "obstacles": [[[40, 30], [70, 30], [70, 60], [40, 60]]],
       "goal": [175, 130]}
MIXED = [{"id": 1, "travel_time": 1.0, "job_time": 5.0},
         {"id": 2, "travel_time": 2.0, "job_time": 10.0}]

CASES: list[tuple[str, dict[str, Any]]] = [
    ("traversal", dict(grid="5x4", agents=2)),
    ("traversal", dict(grid="6x6", agents=2, obstacles="1,1;2,2", nests="0,0;5,5",
                       comm_range=3, loss=0.2)),
    ("traversal", dict(grid="6x5", fleet=MIXED, algorithm="madgta-h")),
    # a policy's options travel in the algorithm spec, spelled one way in the record
    ("traversal", dict(grid="6x6", agents=3, obstacles="2,2;3,3",
                       algorithm="madgta-f@keep=false,ils=4")),
    ("traversal", dict(grid="3x3", agents=2, algorithm="optimal")),
    ("traversal", dict(center="43.2,-79.9", radius=50, nodes_on_edge=3, agents=2)),
    # a metric fleet: the record fills in both travel_time and travel_speed per row, and
    # 5 / (5 / 4.9) is not 4.9, so the row's given field must be the one passed back
    ("traversal", dict(grid="6x6", edge_length=5.0, fleet=[
        {"id": 1, "travel_speed": 3.0}, {"id": 2, "travel_time": 4.9}, {"id": 3}])),
    ("traversal", dict(center="43.2,-79.9", radius=50, nodes_on_edge=3, agents=2,
                       fleet=[{"id": 1, "travel_speed": 3.0}, {"id": 2, "travel_time": 7.0}])),
    ("foraging", dict(grid=16, agents=4, algorithm="strips")),
    ("foraging", dict(grid=16, agents=4, algorithm="sectors", food_distance="20-40")),
    ("exploration", dict(empty="6x6", robots=2)),
    ("exploration", dict(empty="5x4", robots=2, comm_range="inf", cell=0.1)),
    ("roadmap", dict(agents=2, nodes=40, step=15, sensor_range="inf", raster=64)),
    ("roadmap", dict(agents=2, nodes=40, step=15, sensor_range=20, task="search")),
]


def same(a: swarmex.ResultRecord, b: swarmex.ResultRecord) -> bool:
    x, y = a.to_dict(), b.to_dict()
    x.pop("wall_seconds")
    y.pop("wall_seconds")
    return json.dumps(x, sort_keys=True) == json.dumps(y, sort_keys=True)


@pytest.mark.parametrize(("mission", "kw"), CASES, ids=[f"{m}-{i}" for i, (m, _) in
                                                        enumerate(CASES)])
def test_a_record_runs_again_into_itself(mission: str, kw: dict[str, Any],
                                         tmp_path: Path) -> None:
    if mission == "roadmap":
        env = tmp_path / "env.json"
        env.write_text(json.dumps(ENV), encoding="utf-8")
        kw = {**kw, "env": env}
    if "center" in kw:
        pytest.importorskip("pyproj", reason="GPS worlds need the geo extra")
    first = swarmex.run(mission, seed=3, **kw)
    assert same(swarmex.rerun(first), first)


def test_a_map_file_record_and_a_record_file(tmp_path: Path) -> None:
    if not (MAPS / "room-32-32-4.map").exists():
        pytest.skip(f"benchmark maps not found in {MAPS}")
    first = swarmex.run("exploration", seed=1, map=str(MAPS / "room-32-32-4.map"), cell=0.25,
                        robots=2, max_ticks=40)
    path = tmp_path / "rec.json"
    path.write_text(json.dumps(first.to_dict()), encoding="utf-8")
    assert same(swarmex.rerun(path), first)
    assert same(swarmex.rerun(str(path)), first)


def test_overrides_change_the_run_and_name_a_world_object() -> None:
    from swarmex.worlds import random_obstacles

    first = swarmex.run("traversal", seed=0, grid="5x4", agents=2)
    more = swarmex.rerun(first, agents=3)
    assert len(more.agents) == 3 and more.seed == 0
    other = swarmex.rerun(first, seed=5)  # was a TypeError: seed given twice to run
    assert same(other, swarmex.run("traversal", seed=5, grid="5x4", agents=2))

    world = random_obstacles(6, 6, 0.1, seed=1)
    on_object = swarmex.run("traversal", seed=2, map=world, agents=2)
    with pytest.raises(InputError, match="pass it again"):
        swarmex.rerun(on_object)
    assert same(swarmex.rerun(on_object, map=world), on_object)

    explored = swarmex.run("exploration", seed=2, map=world, cell=0.25, robots=2,
                           max_ticks=40)
    with pytest.raises(InputError, match="pass it again"):
        swarmex.rerun(explored)
    assert same(swarmex.rerun(explored, map=world), explored)


def test_cli_says_same_or_where_it_differs(tmp_path: Path, capsys) -> None:
    rec = tmp_path / "r.json"
    assert main(["traverse", "--grid", "5x5", "--agents", "2", "--seed", "4",
                 "--json", str(rec)]) == 0
    capsys.readouterr()
    out = tmp_path / "again.json"
    assert main(["rerun", str(rec), "--json", str(out)]) == 0
    said = capsys.readouterr().out
    assert "the same record" in said and f"wrote {out}" in said.replace("\n", "")
    assert json.loads(out.read_text())["metrics"] == json.loads(rec.read_text())["metrics"]

    data = json.loads(rec.read_text())
    data["metrics"]["total_time_all"] += 1
    data["agents"][0]["trajectory"][1][0] += 1
    tampered = tmp_path / "t.json"
    tampered.write_text(json.dumps(data), encoding="utf-8")
    assert main(["rerun", str(tampered)]) == 1
    line = capsys.readouterr().out
    assert "differs" in line and "metrics.total_time_all" in line
    assert "agents[0].trajectory[1]" in line

    assert main(["rerun", str(tmp_path / "missing.json")]) == 2
    assert "record not found" in capsys.readouterr().err
    binary = tmp_path / "bin.json"
    binary.write_bytes(b"\x7fELF\x02\x01\x01\x00\xd0\xc0")
    failed = tmp_path / "0123.error.json"  # what a sweep writes for a failed run
    failed.write_text(json.dumps({"run": "0123", "mission": "traversal", "params": {},
                                  "seed": 0, "error": "40 agents but the map has only 9",
                                  "traceback": "..."}), encoding="utf-8")
    empty = tmp_path / "empty"
    empty.mkdir()
    for path, said in ((empty, "a folder with no record"), (binary, "not UTF-8 text"),
                       (failed, "failed sweep run's error file")):
        assert main(["rerun", str(path)]) == 2  # was a traceback (IsADirectory, Unicode)
        assert said in capsys.readouterr().err


def test_cli_checks_several_records_and_a_sweep_folder(tmp_path: Path, capsys) -> None:
    """``swarmex rerun A.json B.json`` and ``swarmex rerun SWEEP/runs``: one line per record,
    a count, exit 1 if any differs; every file is read before the first run, so a bad one
    stops the check before any work; a failed run's error file in a sweep folder is skipped."""
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = [1, 2]\nseeds = [0, 1]\n',
                    encoding="utf-8")
    out = tmp_path / "sweep"
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out)]) == 0
    runs = out / "runs"
    (runs / "0123.error.json").write_text(json.dumps({"run": "0123", "error": "x"}),
                                          encoding="utf-8")
    capsys.readouterr()
    assert main(["rerun", str(runs)]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 5 and lines[-1] == "4 of 4 records the same"
    assert all("the same record" in line and ".json: rerun traversal" in line
               for line in lines[:4])

    files = sorted(runs.glob("????????????????.json"))
    data = json.loads(files[1].read_text())
    data["metrics"]["total_time_all"] += 1
    tampered = tmp_path / "t.json"
    tampered.write_text(json.dumps(data), encoding="utf-8")
    assert main(["rerun", str(files[0]), str(tampered)]) == 1
    lines = capsys.readouterr().out.strip().splitlines()
    assert "the same record" in lines[0] and "differs" in lines[1]
    assert lines[-1] == "1 of 2 records the same"

    assert main(["rerun", str(files[0]), str(files[1]), "--json", str(tmp_path / "o.json")]) == 2
    assert "--json writes one record; 2 records were given" in capsys.readouterr().err
    assert main(["rerun", str(files[0]), str(tmp_path / "missing.json")]) == 2
    captured = capsys.readouterr()
    assert "record not found" in captured.err and "rerun traversal" not in captured.out


def test_overrides_replace_the_recorded_alternatives_and_derived_values(tmp_path: Path) -> None:
    """An override of the world or the team must not keep what the record derived from the
    old one (per-agent nests and starts, a drawn food cell), nor pass the record's ``grid``
    beside a new ``map``: ``swarmex.rerun(rec, agents=8)`` is the documented use."""
    mapfile = tmp_path / "m.map"
    mapfile.write_text("type octile\nheight 3\nwidth 4\nmap\n@...\n....\n....\n",
                       encoding="utf-8")
    on_grid = swarmex.run("traversal", seed=1, grid="5x5", agents=2)
    on_map = swarmex.rerun(on_grid, map=mapfile)
    assert on_map.params["grid"] is None and on_map.world["width"] == 4
    assert on_map.params["nests"] == [[1, 0], [1, 0]]  # the new map's first free cell
    assert swarmex.rerun(on_map, grid="3x3").world["source"] == "grid 3x3"

    fleet = [{"id": 1, "job_time": 4.0}, {"id": 2}]
    mixed = swarmex.run("traversal", seed=1, grid="5x5", fleet=fleet, edge_length=2.0)
    slower = swarmex.rerun(mixed, job_time=20.0)
    assert [r["job_time"] for r in slower.params["fleet"]] == [4.0, 20.0]

    drawn = swarmex.run("foraging", seed=2, grid=16, agents=4, algorithm="strips",
                        food_distance="20-40")
    assert swarmex.rerun(drawn, food=(3, 3)).params["food"] == [3, 3]
    placed = swarmex.rerun(drawn, food=(3, 3))
    assert swarmex.rerun(placed, food_distance="20-40").params["food"] == drawn.params["food"]

    explored = swarmex.run("exploration", seed=1, empty="5x5", robots=2, max_ticks=20)
    assert len(swarmex.rerun(explored, robots=3).agents) == 3

    env = tmp_path / "env.json"
    env.write_text(json.dumps(ENV), encoding="utf-8")
    road = swarmex.run("roadmap", seed=1, env=env, agents=2, nodes=30, step=15,
                       sensor_range="inf", raster=64)
    assert len(swarmex.rerun(road, agents=3).agents) == 3


def test_a_record_with_a_relative_map_reruns_from_another_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys
) -> None:
    """A record names its map as the run was given it, relative to the folder the run
    started in (``swarmex run`` and sweeps too); rerun from elsewhere, the record file's
    folder and those above it are searched, and the new record still names it the same."""
    project = tmp_path / "project"
    (project / "maps").mkdir(parents=True)
    (project / "out").mkdir()
    (project / "maps" / "m.map").write_text(
        "type octile\nheight 4\nwidth 5\nmap\n.....\n.@@..\n.....\n.....\n", encoding="utf-8")
    monkeypatch.chdir(project)
    first = swarmex.run("traversal", seed=2, map="maps/m.map", agents=2)
    record = project / "out" / "rec.json"
    record.write_text(json.dumps(first.to_dict()), encoding="utf-8")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    assert same(swarmex.rerun(record), first)
    assert main(["rerun", str(record)]) == 0
    assert "the same record" in capsys.readouterr().out
    with pytest.raises(InputError, match="'maps/m.map' is not found from here"):
        swarmex.rerun(first)  # no file, so no folder to search: say where it was looked for


def test_a_roadmap_on_a_world_object_asks_for_it() -> None:
    from shapely import box

    from swarmex.worlds.polygon import PolygonWorld

    world = PolygonWorld((0, 0, 200, 150), [box(40, 30, 70, 60)])
    first = swarmex.run("roadmap", seed=1, env=world, agents=2, nodes=30, step=15,
                        sensor_range="inf", raster=64)
    with pytest.raises(InputError, match=r"env=world"):
        swarmex.rerun(first)
    assert same(swarmex.rerun(first, env=world), first)


def test_cli_on_a_networked_record_compares_what_the_simulator_has(tmp_path: Path,
                                                                   capsys) -> None:
    """A ``swarmex serve`` record with ``--rng shared`` is the simulated run plus the wire's
    own parts (docs/net.md): the rerun, which is the simulator's, must not be called a
    difference for those, and a networked run that is another run must say why."""
    sim = swarmex.run("traversal", seed=0, grid="5x5", agents=2).to_dict()
    served = {**sim, "params": {**sim["params"], "network": {"time_scale": 0.01,
                                                             "rng": "shared"}},
              "metrics": {**sim["metrics"], "message_bytes": 8444},
              "departed_agents": [], "vehicles": [{"id": 1, "kind": "simulated"}],
              "network": {"transport": "zeromq", "rng_mode": "shared", "left": [],
                          "joined": [], "inject_loss": 0.0}}
    path = tmp_path / "served.json"
    path.write_text(json.dumps(served), encoding="utf-8")
    assert main(["rerun", str(path)]) == 0
    assert "the simulator's run is the same" in capsys.readouterr().out

    served["network"]["rng_mode"] = "own"
    served["agents"][0]["jobs"][1][0] += 1
    path.write_text(json.dumps(served), encoding="utf-8")
    assert main(["rerun", str(path)]) == 1
    line = capsys.readouterr().out
    assert "agents[0].jobs[1]" in line and "--rng own" in line
    assert "network" not in line.split("(")[0]  # the network's parts are not differences


def test_cli_on_a_process_mesh_record_says_why_it_differs(tmp_path: Path, capsys) -> None:
    """An ``explore --processes`` record ran in real time: its rerun (the simulator's) is
    another run, and the line must say so rather than list "params.processes (gone)"."""
    sim = swarmex.run("exploration", seed=0, empty="3x3", robots=2).to_dict()
    mesh = {**sim, "params": {**sim["params"], "processes": {"time_scale": 0.01}},
            "makespan": sim["makespan"] + 1.0}
    path = tmp_path / "mesh.json"
    path.write_text(json.dumps(mesh), encoding="utf-8")
    assert main(["rerun", str(path)]) == 1
    line = capsys.readouterr().out
    assert "makespan" in line and "a process-mesh record" in line
    assert "params.processes" not in line


def test_render_of_a_networked_record_warns_only_when_rerun_would_differ(tmp_path: Path,
                                                                         capsys) -> None:
    """``swarmex render`` of a ``--rng shared`` serve record said "came out differently"
    while ``swarmex rerun`` said "the simulator's run is the same": render compared the
    network's own parts too."""
    sim = swarmex.run("traversal", seed=0, grid="5x5", agents=2).to_dict()
    served = {**sim, "params": {**sim["params"], "network": {"rng": "shared"}},
              "metrics": {**sim["metrics"], "message_bytes": 8444},
              "departed_agents": [], "vehicles": [{"id": 1, "kind": "simulated"}],
              "network": {"transport": "zeromq", "rng_mode": "shared"}}
    path = tmp_path / "served.json"
    path.write_text(json.dumps(served), encoding="utf-8")
    assert main(["render", str(path), str(tmp_path / "a.png")]) == 0
    assert "came out differently" not in capsys.readouterr().err
    served["metrics"]["total_time_all"] += 1
    path.write_text(json.dumps(served), encoding="utf-8")
    with pytest.warns(RuntimeWarning, match="came out differently"):
        swarmex.render(path, tmp_path / "b.png")


@pytest.mark.parametrize(("key", "value", "message"), [
    ("params", "abc", "'params' must be a JSON object"),
    ("metrics", [1], "'metrics' must be a JSON object"),
    ("mission", 3, "'mission' must be a string"),
    ("agents", [{"id": 1, "metrics": "x"}], r"agents\[0\] needs an object 'metrics'"),
])
def test_cli_on_a_malformed_record_says_one_line(key: str, value: object, message: str,
                                                 tmp_path: Path, capsys) -> None:
    """A hand-edited record with a field of the wrong kind is bad input (status 2, one
    line), not a traceback from deep in the rerun ('str' object has no attribute 'items')."""
    data = swarmex.run("traversal", seed=0, grid="4x4", agents=2).to_dict()
    data[key] = value
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    assert main(["rerun", str(path)]) == 2
    err = capsys.readouterr().err
    assert re.search(message, err) and "Traceback" not in err and err.count("\n") == 1


@pytest.mark.parametrize(("mission", "kw"), [CASES[0], CASES[8]], ids=["traversal", "foraging"])
def test_a_record_without_its_trace_reruns_without_it(mission: str, kw: dict[str, Any],
                                                      tmp_path: Path, capsys) -> None:
    """``trace=False`` records (the reproduction studies') are the same run without the
    trajectories and jobs (foraging's per-agent ``moves`` is None): rerun as they were made,
    not called different for the trace they never had."""
    first = swarmex.run(mission, seed=1, trace=False, **kw)
    assert same(swarmex.rerun(first), first)
    assert swarmex.rerun(first, trace=True).agents[0].trajectory  # asked for: the trace
    path = tmp_path / "r.json"
    path.write_text(json.dumps(first.to_dict()), encoding="utf-8")
    assert main(["rerun", str(path)]) == 0
    assert "the same record" in capsys.readouterr().out


def test_cli_on_a_record_its_caller_stopped_says_why_it_differs(tmp_path: Path,
                                                                capsys) -> None:
    """A run stopped by ``StopRun`` from ``on_frame`` is an incomplete record whose
    parameters do not say where it stopped: its rerun completes, and the line says so."""
    def stop(frame: Any) -> None:
        if frame.t > 20:
            raise swarmex.StopRun

    partial = swarmex.run("traversal", seed=1, grid="5x5", agents=2, on_frame=stop)
    assert not partial.complete
    path = tmp_path / "partial.json"
    path.write_text(json.dumps(partial.to_dict()), encoding="utf-8")
    assert main(["rerun", str(path)]) == 1
    line = capsys.readouterr().out
    assert "complete: False → True" in line and "stopped early by its caller" in line


def test_cli_rerun_says_when_it_compiles(tmp_path: Path, capsys, monkeypatch) -> None:
    """``swarmex rerun`` runs inside the compile notice, as every mission command does: a
    first rerun after an install compiled its kernels for seconds without a word."""
    import contextlib

    import swarmex.cli.commands_rerun as cmd

    entered: list[bool] = []

    @contextlib.contextmanager
    def notice(console: Any):
        entered.append(True)
        yield

    monkeypatch.setattr(cmd, "compile_notice", notice)
    from swarmex.engine.record import write_record

    path = write_record(swarmex.run("traversal", grid="3x3", agents=1), tmp_path / "r.json")
    assert main(["rerun", str(path)]) == 0
    assert entered == [True]
    assert "the same record" in capsys.readouterr().out


def test_a_bad_record_among_several_is_named(tmp_path: Path, capsys) -> None:
    """``swarmex rerun A.json B.json`` with B not a record said "not a swarmex record: no
    'mission', …" without saying which file; ``ResultRecord.read`` now names it."""
    good = tmp_path / "good.json"
    swarmex.run("traversal", seed=0, grid="4x4", agents=1).write(good)
    bad = tmp_path / "bad.json"
    bad.write_text("{}", encoding="utf-8")
    assert main(["rerun", str(good), str(bad)]) == 2
    assert f"{bad}: not a swarmex record" in capsys.readouterr().err
    with pytest.raises(InputError, match="bad.json: not a swarmex record"):
        swarmex.ResultRecord.read(bad)


def test_a_record_whose_map_is_gone_stops_the_rerun_before_any_run(tmp_path: Path,
                                                                   capsys) -> None:
    # only unreadable JSON was caught up front: the records before a missing map reran,
    # printed their lines, and the command then exited 2 without its "N of M" count
    import numpy as np

    from swarmex.worlds import GridWorld

    good = tmp_path / "good.json"
    swarmex.run("traversal", seed=0, grid="4x4", agents=1).write(good)
    gone = tmp_path / "gone.json"
    rec = swarmex.run("traversal", seed=0, grid="4x4", agents=1).to_dict()
    rec["params"]["map"], rec["params"]["grid"] = "nowhere/m.map", None
    gone.write_text(json.dumps(rec), encoding="utf-8")
    objected = tmp_path / "object.json"
    swarmex.run("traversal", seed=0, map=GridWorld(np.ones((3, 3), dtype=bool)),
                agents=1).write(objected)
    for last, said in ((gone, "'nowhere/m.map' is not found"),
                       (objected, "was given as an object")):
        assert main(["rerun", str(good), str(last)]) == 2
        out, err = capsys.readouterr()
        assert out == ""  # nothing reran
        assert err.count("\n") == 1 and f"{last}: " in err and said in err, err


def test_cli_rerun_and_render_of_a_small_run_compile_nothing(tmp_path: Path) -> None:
    """``swarmex traverse`` keeps a small run's kernels interpreted while numba is cold; its
    record's ``swarmex rerun`` and ``swarmex render`` used to compile them (7-12 s, with the
    compile notice) for the same record. A fresh cache folder makes numba cold."""
    import os
    import subprocess
    import sys

    src = Path(swarmex.__file__).resolve().parents[1]
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(tmp_path / "cold")}

    def swarmex_cli(*argv: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "swarmex", *argv], env=env, cwd=tmp_path,
                              capture_output=True, text=True, timeout=120, check=True)

    swarmex_cli("traverse", "--grid", "6x6", "--obstacles", "2,2", "--agents", "2",
                "--json", "a.json")
    again = swarmex_cli("rerun", "a.json")
    assert "the same record" in again.stdout and again.stderr == ""
    drawn = swarmex_cli("render", "a.json", "a.png")
    assert "wrote" in drawn.stdout and drawn.stderr == ""
    assert not list((tmp_path / "cold").rglob("*.nbi"))  # nothing compiled, nothing cached


def test_cli_rerun_and_render_show_the_commands_progress_bar(tmp_path: Path, capsys,
                                                             monkeypatch) -> None:
    """``swarmex rerun`` and ``render`` of a long run were minutes of silence where the
    command that made the record showed a bar: on a terminal they show it too, and the
    record and the drawing are the same as without it."""
    import io

    from rich.console import Console

    from swarmex.cli import missions
    from swarmex.experiments.progress import FrameProgress

    rec, plain = tmp_path / "r.json", tmp_path / "plain.png"
    assert main(["traverse", "--grid", "9x8", "--agents", "3", "--seed", "4",
                 "--json", str(rec)]) == 0
    assert main(["render", str(rec), str(plain)]) == 0
    capsys.readouterr()
    screen = io.StringIO()
    monkeypatch.setattr(missions, "err_console", Console(file=screen, force_terminal=True))
    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    assert main(["rerun", str(rec)]) == 0
    assert "the same record" in capsys.readouterr().out
    assert "jobs" in screen.getvalue() and "/72" in screen.getvalue()
    screen.truncate(0)
    assert main(["render", str(rec), str(tmp_path / "bar.png")]) == 0
    assert "/72" in screen.getvalue()
    assert (tmp_path / "bar.png").read_bytes() == plain.read_bytes()
