"""``swarmex traverse`` / ``demo`` / ``run`` end to end: records, replay, bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from swarmex.cli import main
from swarmex.cli.compiling import MESSAGE

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"

TOP_KEYS = {
    "swarmex_version",
    "mission",
    "algorithm",
    "params",
    "seed",
    "world",
    "complete",
    "makespan",
    "time_unit",
    "metrics",
    "agents",
    "wall_seconds",
}
WORLD_KEYS = {"kind", "source", "width", "height", "free_cells"}

GRID = ["--grid", "7x6", "--obstacles", "2,1;2,2;2,3;5,4;5,4"]  # (5,4) twice: harmless


def cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def free_mask(width: int, height: int, blocked) -> np.ndarray:
    """The map, built here without swarmex: True = free, indexed [y, x]."""
    free = np.ones((height, width), dtype=bool)
    for x, y in blocked:
        free[y, x] = False
    return free


def replay(record: dict, free: np.ndarray) -> None:
    """Independent checker of DESIGN.md: moves to 4-adjacent free cells, one job per cell."""
    h, w = free.shape
    jobs = []
    for agent in record["agents"]:
        traj = agent["trajectory"]
        assert traj, "an agent without a position"
        for _t, x, y in traj:
            assert 0 <= x < w and 0 <= y < h and free[int(y), int(x)]
        for (t0, x0, y0), (t1, x1, y1) in zip(traj, traj[1:], strict=False):
            assert t1 >= t0
            assert abs(x1 - x0) + abs(y1 - y0) == 1, f"jump {x0, y0} -> {x1, y1}"
        times = [p[0] for p in traj]
        for t, x, y in agent["jobs"]:
            # the agent stood on the cell when it started the job
            here = traj[int(np.searchsorted(times, t, side="right")) - 1]
            assert (here[1], here[2]) == (x, y)
            jobs.append((int(x), int(y)))
    assert len(jobs) == len(set(jobs)), "a job was done twice"
    assert set(jobs) == {(int(x), int(y)) for y, x in np.argwhere(free)}


def test_traverse_writes_a_record_that_replays(tmp_path, capsys):
    out = tmp_path / "sub" / "run.json"  # missing folders are created
    code, stdout, err = cli(
        ["traverse", *GRID, "--agents", 3, "--nests", "0,0;6,5", "--seed", 4, "--json", out],
        capsys,
    )
    assert code == 0, err
    assert "complete" in stdout and "agent" in stdout
    rec = json.loads(out.read_text())
    assert set(rec) == TOP_KEYS
    assert rec["mission"] == "traversal" and rec["algorithm"] == "madgta"
    assert rec["seed"] == 4 and rec["time_unit"] == "s" and rec["complete"] is True
    assert set(rec["world"]) >= WORLD_KEYS
    free = free_mask(7, 6, [(2, 1), (2, 2), (2, 3), (5, 4)])
    assert (rec["world"]["width"], rec["world"]["height"]) == (7, 6)
    assert rec["world"]["free_cells"] == int(free.sum())
    params = rec["params"]
    for key in (
        "grid",
        "obstacles",
        "agents",
        "nests",
        "travel_time",
        "job_time",
        "algorithm",
        "objective",
        "connectivity",
        "start_interval",
        "altitude",
        "up_speed",
        "down_speed",
        "comm_range",
        "loss",
        "delay",
        "job_failure",
        "seed",
    ):
        assert key in params, key
    # nests shared round-robin: agents 1 and 3 start at (0,0), agent 2 at (6,5)
    assert params["nests"] == [[0, 0], [6, 5], [0, 0]]
    assert [a["trajectory"][0][1:] for a in rec["agents"]] == [[0, 0], [6, 5], [0, 0]]
    assert [a["id"] for a in rec["agents"]] == [1, 2, 3]
    for a in rec["agents"]:
        assert {"id", "metrics", "trajectory", "jobs"} <= set(a)
    replay(rec, free)
    last = max(t for a in rec["agents"] for t, *_ in a["trajectory"] + a["jobs"])
    assert rec["makespan"] >= last


def test_same_seed_same_record(tmp_path, capsys):
    paths = [tmp_path / "a.json", tmp_path / "b.json"]
    for p in paths:
        assert cli(["traverse", *GRID, "--agents", 2, "--seed", 9, "--json", p], capsys)[0] == 0
    a, b = (json.loads(p.read_text()) for p in paths)
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b


def test_default_nest_is_the_first_free_cell_row_major(tmp_path, capsys):
    out = tmp_path / "r.json"
    argv = ["traverse", "--grid", "4x3", "--obstacles", "0,0;1,0", "--agents", 2, "--json", out]
    assert cli(argv, capsys)[0] == 0
    rec = json.loads(out.read_text())
    assert [a["trajectory"][0][1:] for a in rec["agents"]] == [[2, 0], [2, 0]]
    replay(rec, free_mask(4, 3, [(0, 0), (1, 0)]))


def test_map_file_with_extra_obstacles_and_nearest(tmp_path, capsys):
    rows = ["..@..", ".....", "..@.."]
    mapfile = tmp_path / "m.map"
    mapfile.write_text("type octile\nheight 3\nwidth 5\nmap\n" + "\n".join(rows) + "\n")
    out = tmp_path / "r.json"
    argv = [
        "traverse",
        "--map",
        mapfile,
        "--obstacles",
        "4,1",
        "--agents",
        2,
        "--nests",
        "0,0;0,0",
        "--algorithm",
        "nearest",
        "--json",
        out,
    ]
    code, _, err = cli(argv, capsys)
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert rec["algorithm"] == "nearest" and rec["world"]["kind"] == "grid"
    free = np.array([[c == "." for c in row] for row in rows])
    free[1, 4] = False
    replay(rec, free)


def test_console_script_runs_as_a_subprocess(tmp_path):
    # a long path: piped, Rich wrapped every line at 80 columns, splitting the path that a
    # script or a log grep needs whole
    out = tmp_path / ("a_folder_whose_name_is_long_enough_to_pass_eighty_columns" * 2) / "r.json"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "swarmex",
            "traverse",
            "--grid",
            "4x4",
            "--agents",
            "2",
            "--json",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    assert set(json.loads(out.read_text())) == TOP_KEYS
    assert f"wrote {out}\n" in proc.stdout


@pytest.fixture
def bad_map(tmp_path):
    def make(text: str) -> Path:
        p = tmp_path / "bad.map"
        p.write_text(text)
        return p

    return make


BAD = {
    "missing map": ["--map", "no/such.map", "--agents", "2"],
    "neither map nor grid": ["--agents", "2"],
    "both map and grid": ["--map", "MAP:", "--grid", "3x3", "--agents", "2"],
    "malformed map": ["--map", "MAP:this is not a map\n", "--agents", "2"],
    "header height": [
        "--map",
        "MAP:type octile\nheight 3\nwidth 2\nmap\n..\n..\n",
        "--agents",
        "1",
    ],
    "header width": ["--map", "MAP:type octile\nheight 2\nwidth 3\nmap\n..\n..\n", "--agents", "1"],
    "bad terrain": ["--map", "MAP:type octile\nheight 1\nwidth 2\nmap\n.x\n", "--agents", "1"],
    "grid spec": ["--grid", "10by10", "--agents", "2"],
    "grid zero": ["--grid", "0x5", "--agents", "2"],
    "obstacle outside": ["--grid", "5x5", "--obstacles", "5,1", "--agents", "2"],
    "obstacle negative": ["--grid", "5x5", "--obstacles", "-1,1", "--agents", "2"],
    "obstacles malformed": ["--grid", "5x5", "--obstacles", "1;2", "--agents", "2"],
    "nest outside": ["--grid", "5x5", "--agents", "2", "--nests", "0,9"],
    "nests malformed": ["--grid", "5x5", "--agents", "2", "--nests", "a,b"],
    "nests empty": ["--grid", "5x5", "--agents", "2", "--nests", ";"],
    "nest on obstacle": ["--grid", "5x5", "--obstacles", "1,1", "--agents", "2", "--nests", "1,1"],
    "more nests than agents": ["--grid", "5x5", "--agents", "2", "--nests", "0,0;1,1;2,2"],
    "more agents than free cells": ["--grid", "2x2", "--obstacles", "0,0", "--agents", "4"],
    "zero agents": ["--grid", "5x5", "--agents", "0"],
    "agents not a number": ["--grid", "5x5", "--agents", "three"],
    "agents missing": ["--grid", "5x5"],
    "negative travel time": ["--grid", "5x5", "--agents", "2", "--travel-time", "-1"],
    "zero travel time": ["--grid", "5x5", "--agents", "2", "--travel-time", "0"],
    "negative job time": ["--grid", "5x5", "--agents", "2", "--job-time", "-2"],
    "negative altitude": ["--grid", "5x5", "--agents", "2", "--altitude", "-5"],
    "zero up speed": ["--grid", "5x5", "--agents", "2", "--altitude", "5", "--up-speed", "0"],
    "negative down speed": ["--grid", "5x5", "--agents", "2", "--down-speed", "-1"],
    "negative start interval": ["--grid", "5x5", "--agents", "2", "--start-interval", "-1"],
    "unknown algorithm": ["--grid", "5x5", "--agents", "2", "--algorithm", "dijkstra"],
    "unknown objective": ["--grid", "5x5", "--agents", "2", "--objective", "median"],
    "connectivity": ["--grid", "5x5", "--agents", "2", "--connectivity", "6"],
    "loss": ["--grid", "5x5", "--agents", "2", "--loss", "1.5"],
    "negative delay": ["--grid", "5x5", "--agents", "2", "--delay", "-1"],
    "comm range": ["--grid", "5x5", "--agents", "2", "--comm-range", "0"],
    "job failure": ["--grid", "5x5", "--agents", "2", "--job-failure", "1"],
    "negative seed": ["--grid", "5x5", "--agents", "2", "--seed", "-1"],
    # past any vehicle: a job of 1e308 s made the makespan inf (a blank summary)
    "huge job time": ["--grid", "5x5", "--agents", "2", "--job-time", "1e308"],
    "huge travel time": ["--grid", "5x5", "--agents", "2", "--travel-time", "1e300"],
    "huge delay": ["--grid", "5x5", "--agents", "2", "--delay", "1e20"],
    "crawling climb": ["--grid", "5x5", "--agents", "2", "--altitude", "10", "--up-speed",
                       "1e-300"],
    "huge edge": ["--grid", "5x5", "--agents", "2", "--edge-length", "1e300"],
    "json unwritable": ["--grid", "5x5", "--agents", "2", "--json", "FILE:/out.json"],
    "json is a directory": ["--grid", "5x5", "--agents", "2", "--json", "DIR:"],
    "render unwritable": ["--grid", "5x5", "--agents", "2", "--render", "FILE:/x.png"],
    "render extension": ["--grid", "5x5", "--agents", "2", "--render", "TMP:out.jpg"],
    "render no extension": ["--grid", "5x5", "--agents", "2", "--render", "TMP:out"],
    # the record was written, then the picture replaced it
    "json and render one file": ["--grid", "5x5", "--agents", "2", "--json", "TMP:o.png",
                                 "--render", "TMP:o.png"],
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_input_exits_2_with_one_line(name, tmp_path, capsys, bad_map):
    a_file = tmp_path / "plain.txt"
    a_file.write_text("x")
    argv = []
    for arg in BAD[name]:
        if arg.startswith("MAP:"):
            arg = bad_map(arg[4:] or "type octile\nheight 1\nwidth 1\nmap\n.\n")
        elif arg.startswith("FILE:"):  # below a regular file: never writable, even for root
            arg = f"{a_file}{arg[5:]}"
        elif arg.startswith("DIR:"):
            arg = str(tmp_path)
        elif arg.startswith("TMP:"):
            arg = str(tmp_path / arg[4:])
        argv.append(arg)
    code, out, err = cli(["traverse", *argv], capsys)
    assert code == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("swarmex: error: ")
    assert "Traceback" not in err + out
    assert not list(tmp_path.glob("*.png")) and not (tmp_path / "out.json").exists()


@pytest.mark.parametrize(("name", "needle"), [
    ("json and render one file", "--json and --render name the same file"),
    ("huge job time", "--job-time must be at most 1e+09"),
    ("huge travel time", "--travel-time must be at most 1e+09"),
    ("huge delay", "--delay must be at most 1e+09"),
    ("crawling climb", "--up-speed must be at least 0.001"),
    ("huge edge", "--edge-length must be at most 1e+06"),
])
def test_the_bounds_refuse_for_their_own_reason(name, needle, tmp_path, capsys):
    # the table above checks one line and status 2; these rows check that line's reason
    argv = [str(tmp_path / a[4:]) if a.startswith("TMP:") else a for a in BAD[name]]
    code, _, err = cli(["traverse", *argv], capsys)
    assert code == 2 and needle in err, err


def test_bad_input_names_the_problem(capsys):
    code, _, err = cli(["traverse", "--grid", "5x5", "--agents", "2", "--nests", "0,9"], capsys)
    assert code == 2 and "--nests" in err and "(0,9)" in err and "outside" in err
    code, _, err = cli(
        ["traverse", "--grid", "3x3", "--obstacles", "1,1", "--agents", "1", "--nests", "1,1"],
        capsys,
    )
    assert code == 2 and "obstacle" in err


def test_demo_writes_a_png(tmp_path, capsys):
    out = tmp_path / "demo.png"
    code, stdout, err = cli(["demo", "--out", out], capsys)
    assert code == 0, err
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert "demo.png" in stdout.replace("\n", "") and "complete" in stdout


def test_demo_bad_seed_exits_2_with_one_line(tmp_path, capsys):
    code, out, err = cli(["demo", "--seed", "-1", "--out", tmp_path / "d.png"], capsys)
    assert code == 2, (out, err)
    assert err.strip().splitlines() == ["swarmex: error: --seed must be at least 0, got -1"]
    assert not (tmp_path / "d.png").exists()


def test_run_example_scenario(tmp_path, capsys):
    out = tmp_path / "r.json"
    code, stdout, err = cli(["run", EXAMPLES / "traversal.toml", "--json", out], capsys)
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert rec["params"]["grid"] == "10x10" and rec["params"]["agents"] == 3
    blocked = [tuple(c) for c in rec["params"]["obstacles"]]
    assert len(blocked) == 8
    replay(rec, free_mask(10, 10, blocked))


PRINTED = [  # seed 000 §3.2.4, thesis node numbers
    "1-1*-2-2*-7-7*-6-6*-7-8-8*-9-9*-4-4*",
    "11-11*-12-12*-17-17*-16-16*-21-21*-22-22*-23-18-18*",
    "23-23*-24-24*-25-25*-20-20*-15-15*-10-10*-5-5*",
]


def test_thesis_example_scenario_prints_the_thesis_paths(tmp_path, capsys):
    out = tmp_path / "r.json"
    code, _, err = cli(["run", EXAMPLES / "traversal-thesis-example.toml", "--json", out], capsys)
    assert code == 0, err
    rec = json.loads(out.read_text())

    def tid(x, y):  # thesis node: 1 bottom-left, row-major upwards
        return int((4 - y) * 5 + x + 1)

    paths = []
    for a in rec["agents"]:
        times = [t for t, _, _ in a["trajectory"]]
        # the visit during which each job started gets the thesis's starred repeat
        starred = {int(np.searchsorted(times, t, side="right")) - 1 for t, _, _ in a["jobs"]}
        steps = []
        for i, (_, x, y) in enumerate(a["trajectory"]):
            k = tid(x, y)
            steps += [f"{k}", f"{k}*"] if i in starred else [f"{k}"]
        paths.append("-".join(steps))
    assert paths == PRINTED


@pytest.mark.parametrize("objective", ["sum", "makespan"])
def test_optimal_dispatch(objective, tmp_path, capsys):
    pytest.importorskip("swarmex.missions.traversal.optimal")
    out = tmp_path / "r.json"
    argv = [
        "traverse",
        "--grid",
        "4x3",
        "--obstacles",
        "1,1",
        "--agents",
        2,
        "--algorithm",
        "optimal",
        "--objective",
        objective,
        "--json",
        out,
    ]
    code, _, err = cli(argv, capsys)
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert set(rec) >= TOP_KEYS and rec["algorithm"] == "optimal"  # plus the solver's report
    assert rec["params"]["objective"] == objective
    replay(rec, free_mask(4, 3, [(1, 1)]))


def test_an_objective_only_optimal_reads_is_noted_not_refused(capsys):
    # a sweep of madgta against optimal at objective=makespan must run, so madgta is not
    # refused it; but a single madgta run used to take the makespan silently
    argv = ["traverse", "--grid", "4x3", "--agents", 2, "--objective", "makespan"]
    code, out, err = cli(argv, capsys)
    assert code == 0, err
    assert ("note: --objective is ignored: only optimal minimises an objective (makespan);"
            " madgta plays its own rule") in err
    assert "note:" not in out
    for quiet in (argv[:5] + ["--objective", "sum"], argv + ["--algorithm", "optimal"]):
        code, _, err = cli(quiet, capsys)
        assert code == 0 and "note:" not in err, (quiet, err)
    import swarmex

    with pytest.warns(UserWarning, match="objective is ignored: .* madgta-f plays its own rule"):
        swarmex.run("traversal", grid="4x3", agents=2, objective="makespan",
                    algorithm="madgta-f@ils=2")
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        swarmex.run("traversal", grid="4x3", agents=2, objective="makespan",
                    algorithm="optimal")
        swarmex.run("traversal", grid="4x3", agents=2)


def test_a_radio_or_failing_jobs_are_noted_not_refused_with_optimal(capsys):
    # an offline plan reads neither; refusing them failed a sweep's optimal rows when it held
    # loss fixed while comparing madgta with the optimum
    argv = ["traverse", "--grid", "4x3", "--agents", 2, "--algorithm", "optimal",
            "--loss", "0.2", "--comm-range", "3", "--delay", "1", "--job-failure", "0.1"]
    code, _, err = cli(argv, capsys)
    assert code == 0, err
    for flag in ("--loss", "--comm-range", "--delay", "--job-failure"):
        assert f"note: {flag} is ignored: optimal is an offline plan" in err, flag
    code, _, err = cli(argv[:7], capsys)  # a perfect radio: nothing to say
    assert code == 0 and "note:" not in err, err
    import swarmex

    with pytest.warns(UserWarning, match="loss is ignored: optimal is an offline plan"):
        lossy = swarmex.run("traversal", grid="4x3", agents=2, algorithm="optimal", loss=0.2)
    plain = swarmex.run("traversal", grid="4x3", agents=2, algorithm="optimal")
    assert lossy.makespan == plain.makespan and lossy.metrics["messages"] == 0


def test_madgta_plus_dispatch(tmp_path, capsys):
    from swarmex.missions.traversal.policies import POLICIES

    if "madgta+" not in POLICIES:
        pytest.skip("madgta+ is not registered by variants.py yet")
    out = tmp_path / "r.json"
    code, _, err = cli(
        ["traverse", *GRID, "--agents", 3, "--algorithm", "madgta+", "--json", out], capsys
    )
    assert code == 0, err
    replay(json.loads(out.read_text()), free_mask(7, 6, [(2, 1), (2, 2), (2, 3), (5, 4)]))


def test_madgta_h_dispatch_with_a_mixed_fleet(tmp_path, capsys):
    """``--algorithm madgta-h`` with a fleet of mixed speeds and job times: the record
    replays, names the algorithm, and equals swarmex.run's; its leave messages are counted."""
    import swarmex

    fleet = tmp_path / "fleet.csv"
    fleet.write_text("id,travel_time,job_time\n1,1.0,5\n2,2.0,10\n3,1.5,6\n")
    out = tmp_path / "r.json"
    code, _, err = cli(
        ["traverse", *GRID, "--agents", 3, "--fleet", fleet, "--algorithm", "madgta-h",
         "--json", out, "--seed", 2], capsys
    )
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert rec["algorithm"] == "madgta-h" and rec["complete"]
    replay(rec, free_mask(7, 6, [(2, 1), (2, 2), (2, 3), (5, 4)]))
    ref = swarmex.run("traversal", grid="7x6", obstacles="2,1;2,2;2,3;5,4", agents=3,
                      fleet=str(fleet), algorithm="madgta-h", seed=2).to_dict()
    assert rec["metrics"] == ref["metrics"]
    plus = swarmex.run("traversal", grid="7x6", obstacles="2,1;2,2;2,3;5,4", agents=3,
                       fleet=str(fleet), algorithm="madgta+", seed=2).to_dict()
    assert rec["metrics"]["total_time_all"] < plus["metrics"]["total_time_all"]


@pytest.mark.parametrize("algorithm", ["madgta-r", "madgta-p", "madgta-k", "madgta-f",
                                       "madgta-f@ils=4,keep=false"])
def test_madgta_r_dispatch(tmp_path, capsys, algorithm):
    """``--algorithm madgta-r`` (and madgta-p, madgta-k, madgta-f): the record replays, names the
    algorithm and equals swarmex.run's."""
    import swarmex

    out = tmp_path / "r.json"
    code, _, err = cli(
        ["traverse", *GRID, "--agents", 4, "--algorithm", algorithm, "--json", out,
         "--seed", 3], capsys
    )
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert rec["algorithm"] == algorithm and rec["complete"]
    replay(rec, free_mask(7, 6, [(2, 1), (2, 2), (2, 3), (5, 4)]))
    ref = swarmex.run("traversal", grid="7x6", obstacles="2,1;2,2;2,3;5,4", agents=4,
                      algorithm=algorithm, seed=3).to_dict()
    assert rec["metrics"] == ref["metrics"]


@pytest.mark.parametrize("algorithm", ["madgta", "madgta+", "madgta-h", "nearest",
                                       "madgta-r", "madgta-p", "madgta-k", "madgta-f",
                                       "madgta-p@ils=4", "madgta+@claim_radius=3"])
def test_only_light_policies_run_interpreted_on_small_maps(algorithm):
    """A one-shot run on a small map keeps numba unloaded (kernels interpreted) only for the
    policies whose kernels do little; the simulating ones always compile. Interpreted,
    madgta-p's team plan took 85 s on a 12x12 grid with 4 agents (0.3 s compiled)."""
    from swarmex.cli.commands_traversal import small
    from swarmex.missions.registry import get
    from swarmex.missions.traversal.params import TraversalParams
    from swarmex.missions.traversal.policies import POLICIES

    params = TraversalParams(grid=(12, 12), agents=4, algorithm=algorithm)
    prepared = get("traversal").prepare(params)
    name = algorithm.partition("@")[0]
    simulating = name in ("madgta-r", "madgta-p", "madgta-k", "madgta-f")
    assert POLICIES[name].simulates is simulating
    assert small(params, prepared) is not simulating


def test_help_prints_option_help_verbatim(capsys, monkeypatch):
    """Typer reads option help as Rich markup: ``[[agents]]`` used to print as ``[]``."""
    monkeypatch.setenv("COLUMNS", "400")  # one line per option: no wrapping inside words
    code, out, _ = cli(["traverse", "--help"], capsys)
    assert code == 0
    assert "a TOML file of [[agents]] tables" in out


def test_ctrl_c_says_interrupted_and_exits_130(tmp_path, capsys, monkeypatch):
    """Typer swallowed the KeyboardInterrupt into a silent exit 130."""
    from swarmex.missions.registry import get

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(get("traversal"), "execute", interrupted)
    code, out, err = cli(["traverse", "--grid", "5x5", "--agents", "2",
                          "--json", tmp_path / "r.json"], capsys)
    assert code == 130
    assert err.strip().splitlines() == ["swarmex: interrupted; nothing written"]
    assert "Traceback" not in out + err and not (tmp_path / "r.json").exists()


def test_readme_describes_the_demo_that_runs():
    """The README said three agents; the demo runs DEMO_AGENTS."""
    from swarmex.missions.traversal.mission import DEMO_AGENTS, demo_world

    words = {3: "three", 4: "four", 5: "five", 6: "six"}
    section = (REPO / "README.md").read_text().split("### `swarmex demo`")[1].split("###")[0]
    world = demo_world().world
    assert f"MADGTA with {words[DEMO_AGENTS]} agents" in section
    assert f"{world.width}×{world.height}" in section


def test_progress_bar_on_a_terminal_only_and_the_same_record(tmp_path, capsys, monkeypatch):
    """A long traverse printed nothing until the end (madgta-k on den520d: 200 s). On a
    terminal a bar counts the jobs; off one (here: capsys) nothing; the record is the same."""
    import io

    from rich.console import Console

    from swarmex.cli import missions
    from swarmex.experiments.progress import FrameProgress

    argv = ["traverse", "--grid", "9x8", "--obstacles", "3,3;4,4", "--agents", "3",
            "--seed", "4", "--render"]
    code, _, err = cli([*argv, tmp_path / "a.png", "--json", tmp_path / "a.json"], capsys)
    # off a terminal no bar; the one-line compile notice may come first, if an earlier test
    # of this process loaded numba and the kernels compile on a cold cache
    assert code == 0 and [ln for ln in err.splitlines() if MESSAGE not in ln] == []
    screen = io.StringIO()
    monkeypatch.setattr(missions, "err_console", Console(file=screen, force_terminal=True))
    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    code, _, err = cli([*argv, tmp_path / "b.png", "--json", tmp_path / "b.json"], capsys)
    assert code == 0
    assert "jobs" in screen.getvalue() and "/70" in screen.getvalue()  # 9x8 minus 2 walls
    a, b = (json.loads((tmp_path / f"{n}.json").read_text()) for n in "ab")
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()


def test_the_progress_bar_keeps_the_animation_frames(tmp_path, capsys, monkeypatch):
    """On a terminal the bar wraps the --render recorder; the animation must still get every
    frame (the render reads the recorder, not the wrapper), byte for byte as in a pipe."""
    from rich.console import Console

    import swarmex.cli.missions as missions
    from swarmex.experiments.progress import FrameProgress

    argv = ["traverse", "--grid", "8x8", "--agents", "3", "--seed", "1", "--render"]
    assert cli([*argv, tmp_path / "pipe.gif"], capsys)[0] == 0
    monkeypatch.setattr(missions, "err_console", Console(stderr=True, force_terminal=True))
    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    started = []
    real_call = FrameProgress.__call__

    def spy(self, frame):
        real_call(self, frame)
        started.append(self.started)

    monkeypatch.setattr(FrameProgress, "__call__", spy)
    assert cli([*argv, tmp_path / "tty.gif"], capsys)[0] == 0
    assert any(started)  # the bar really ran
    assert (tmp_path / "tty.gif").read_bytes() == (tmp_path / "pipe.gif").read_bytes()


def test_free_cells_the_nests_cannot_reach_are_noted(capsys):
    # "complete · nodes_missed 0" on a nest walled into a corner said nothing of the 13 cells
    code, _, err = cli(["traverse", "--grid", "4x4", "--agents", 2, "--obstacles", "0,1;1,0"],
                       capsys)
    assert code == 0
    assert err == ("note: 13 of the 14 free cells cannot be reached from the nests; the run"
                   " covers the other ones\n")
    code, _, err = cli(["traverse", "--grid", "4x4", "--agents", 2], capsys)
    assert code == 0 and "note:" not in err
