"""``swarmex roadmap``: good runs write replayable records; bad input exits 2 in one line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from swarmex.cli import main
from swarmex.missions.roadmap import replay_problems
from swarmex.worlds.polygon import load_polygon_world

ENV = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [[[40, 30], [70, 30], [70, 60], [40, 60]],
                  [[100, 20], [130, 50], [100, 80]]],
    "goal": [180, 130],
}


@pytest.fixture
def env(tmp_path) -> Path:
    p = tmp_path / "env.json"
    p.write_text(json.dumps(ENV))
    return p


def base(env: Path, *extra: str) -> list[str]:
    return ["roadmap", "--env", str(env), "--agents", "3", "--nodes", "120", "--step", "10",
            "--sensor-range", "20", *extra]


@pytest.mark.parametrize("planner", ["wma-rrt", "prm", "wma-rrt-takeover", "wma-rrt-fairshare"])
@pytest.mark.parametrize("task", ["coverage", "search"])
def test_run_writes_a_replayable_record(env, tmp_path, capsys, planner, task):
    out = tmp_path / "run.json"
    argv = base(env, "--planner", planner, "--task", task, "--seed", "2", "--json", str(out))
    assert main(argv) == 0
    summary = capsys.readouterr().out.splitlines()[0]  # one line, even in a pipe
    assert summary.startswith(f"{planner} {task}: complete=") and " path=" in summary
    rec = json.loads(out.read_text())
    assert rec["mission"] == "roadmap" and rec["algorithm"] == planner
    assert rec["world"]["kind"] == "polygons" and rec["time_unit"] == "step"
    assert rec["params"]["nodes"] == 120 and rec["seed"] == 2
    assert rec["metrics"]["tree_nodes"] == (121 if planner != "prm" else 120)
    if planner != "prm":
        assert rec["complete"] is True
    assert replay_problems(rec, load_polygon_world(env)) == []
    out2 = tmp_path / "run2.json"
    assert main([*argv[:-1], str(out2)]) == 0
    rec2 = json.loads(out2.read_text())
    rec.pop("wall_seconds"), rec2.pop("wall_seconds")
    assert rec == rec2


def test_explicit_starts_goal_and_renders(env, tmp_path):
    png, gif = tmp_path / "r.png", tmp_path / "r.gif"
    argv = base(env, "--task", "search", "--starts", "10,10;16,10;13,15", "--goal", "150,120",
                "--sensor-range", "inf", "--render", str(png))
    assert main(argv) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
    short = base(env, "--render", str(gif))
    short[short.index("--nodes") + 1] = "30"
    assert main(short) == 0
    assert gif.read_bytes()[:3] == b"GIF"


def _full_env(tmp_path: Path) -> Path:
    p = tmp_path / "full.json"
    p.write_text('{"bounds": [0, 0, 100, 100], "obstacles": [[[0, 0], [100, 0], [100, 100], '
                 '[0, 100]]]}')
    return p


def _bad_env(tmp_path: Path) -> Path:
    p = tmp_path / "bad.json"
    p.write_text('{"bounds": [0, 0, 100, 100], "obstacles": [[[1, 1], [2, 2]')
    return p


BAD = [
    (lambda e, t: base(t / "missing.json"), "not found"),
    (lambda e, t: base(_bad_env(t)), "malformed JSON"),
    # was reported as no room for the start cluster, or as a start inside an obstacle
    (lambda e, t: base(_full_env(t)), "full.json: no free space"),
    (lambda e, t: base(_full_env(t), "--starts", "1,1;2,2;3,3"), "full.json: no free space"),
    (lambda e, t: base(e, "--starts", "50,45;10,10;12,12"), "inside an obstacle"),
    (lambda e, t: base(e, "--starts", "10,10;12,12"), "2 positions for --agents 3"),
    (lambda e, t: base(e, "--starts", "10;12,12;5,5"), "--starts"),
    (lambda e, t: base(e, "--starts", "10,10;12,12;500,5"), "outside the bounds"),
    (lambda e, t: base(e, "--task", "search", "--goal", "300,10"), "outside the bounds"),
    (lambda e, t: base(e, "--task", "search", "--goal", "50,45"), "inside an obstacle"),
    (lambda e, t: [*base(e)[:6], "2", *base(e)[7:]], "fewer than --agents"),
    (lambda e, t: [*base(e)[:8], "0", *base(e)[9:]], "--step"),
    (lambda e, t: [*base(e)[:8], "-5", *base(e)[9:]], "--step"),
    (lambda e, t: [*base(e)[:10], "0", *base(e)[11:]], "--sensor-range"),
    (lambda e, t: [*base(e)[:10], "far", *base(e)[11:]], "--sensor-range"),
    (lambda e, t: [*base(e)[:4], "0", *base(e)[5:]], "--agents"),
    (lambda e, t: base(e, "--planner", "rrt*"), "--planner"),
    (lambda e, t: base(e, "--task", "sweep"), "--task"),
    (lambda e, t: base(e, "--render", str(t / "x.svg")), "--render"),
    (lambda e, t: base(e, "--step-budget", "0"), "--step-budget"),
    # numpy refused these with a traceback: a negative seed, a raster too large to allocate
    (lambda e, t: base(e, "--seed", "-1"), "--seed must be at least 0"),
    # too many agents for the default cluster: the message says what to do
    (lambda e, t: [*base(e)[:4], "200", "--nodes", "300", *base(e)[7:]],
     "give their positions with --starts"),
    (lambda e, t: base(e, "--raster", "100000"), "--raster must be at most"),
    (lambda e, t: ["roadmap", "--env", str(e), "--agents", "x", "--nodes", "5", "--step", "1",
                   "--sensor-range", "1"], "agents"),
]


@pytest.mark.parametrize(("make", "needle"), BAD)
def test_bad_input_exits_2_with_one_line(env, tmp_path, capsys, make, needle):
    assert main(make(env, tmp_path)) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("swarmex: error:")
    assert needle in err and "Traceback" not in err


def test_search_without_goal(tmp_path, capsys):
    p = tmp_path / "nogoal.json"
    p.write_text(json.dumps({"bounds": [0, 0, 100, 100], "obstacles": []}))
    assert main(base(p, "--task", "search")) == 2
    assert "needs a goal" in capsys.readouterr().err


def test_ctrl_c_exits_130_with_one_line(env, tmp_path, capsys, monkeypatch):
    # Typer turned Ctrl-C into a silent exit 130: nothing said the run was interrupted, nor
    # that a reproduction's finished runs were kept
    import swarmex.studies.roadmap as study
    from swarmex.missions.registry import get

    def ctrl_c(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(type(get("roadmap")), "execute", ctrl_c)
    assert main(base(env)) == 130
    assert capsys.readouterr().err == "swarmex: interrupted; nothing written\n"
    monkeypatch.setattr(study, "reproduce", ctrl_c)
    assert main(["reproduce", "roadmap", "--quick", "--out", str(tmp_path / "rep")]) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "finished runs are saved in" in err and "resume" in err


def test_reproduce_into_a_file_is_one_line(tmp_path, capsys):
    # mkdir's FileExistsError came out as a traceback
    afile = tmp_path / "afile"
    afile.write_text("")
    assert main(["reproduce", "roadmap", "--quick", "--out", str(afile)]) == 2
    err = capsys.readouterr().err
    assert "exists and is not a directory" in err and err.count("\n") == 1
    assert main(["reproduce", "roadmap", "--quick", "--out", str(afile / "sub")]) == 2
    err = capsys.readouterr().err
    assert "--out: cannot create" in err and err.count("\n") == 1


def test_a_goal_the_coverage_task_ignores_is_noted_not_refused(env, tmp_path, capsys):
    # a sweep over the task at one goal must still run, so the goal is not refused; but a
    # single coverage run given --goal used to take it silently, as if it steered the run
    short = base(env, "--goal", "150,120")
    short[short.index("--nodes") + 1] = "30"
    assert main(short) == 0
    err = capsys.readouterr().err
    assert "note: --goal is ignored: only the search task reads a goal, not coverage" in err
    assert main([*short, "--task", "search"]) == 0
    assert "note:" not in capsys.readouterr().err
    import swarmex

    with pytest.warns(UserWarning, match="goal is ignored"):
        swarmex.run("roadmap", env=env, agents=3, nodes=30, step=10, sensor_range=20,
                    goal=(150, 120))


def test_reproduce_takes_its_worker_count(tmp_path, capsys, monkeypatch):
    # it always ran 2 processes: on a shared 2-core machine it could not be held to 1, as the
    # other three studies can
    import swarmex.studies.roadmap as study

    seen = {}
    monkeypatch.setattr(study, "reproduce", lambda out, **kw: seen.update(kw))
    assert main(["reproduce", "roadmap", "--quick", "--out", str(tmp_path / "r"),
                 "--workers", "1"]) == 0
    assert seen["workers"] == 1  # (a bad count: tests/e2e/test_cli_reproduce_workers.py)


@pytest.mark.parametrize("mission", ["traversal", "foraging", "exploration", "roadmap"])
def test_every_reproduction_writes_under_reproduction_by_default(mission):
    from swarmex.cli.app import reproduce_app

    command = next(c for c in reproduce_app.registered_commands if c.name == mission)
    import inspect

    default = inspect.signature(command.callback).parameters["out"].default.default
    assert default == Path("reproduction") / mission
