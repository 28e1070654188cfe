"""``swarmex run SCENARIO.toml``: scenario keys become the mission command's options."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from swarmex.cli import main
from swarmex.experiments import scenario as scenario_mod


def cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def write(tmp_path, text: str, name: str = "s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def record_of(tmp_path, capsys, body: str, *extra):
    out = tmp_path / "r.json"
    scn = write(tmp_path, 'mission = "traversal"\n' + body)
    code, _, err = cli(["run", scn, "--json", out, *extra], capsys)
    assert code == 0, err
    return json.loads(out.read_text())


@pytest.mark.parametrize(
    "nests",
    ['nests = "0,0;3,2"', 'nests = ["0,0", "3,2"]', "nests = [[0, 0], [3, 2]]"],
)
def test_cell_lists_in_every_spelling(tmp_path, capsys, nests):
    rec = record_of(tmp_path, capsys, f'grid = "4x3"\nagents = 2\n{nests}\n')
    assert rec["params"]["nests"] == [[0, 0], [3, 2]]


def test_underscore_keys_and_overrides_after_the_file(tmp_path, capsys):
    rec = record_of(
        tmp_path, capsys, 'grid = "4x4"\nagents = 2\njob_time = 3.5\nseed = 1\n', "--seed", "7"
    )
    assert rec["params"]["job_time"] == 3.5
    assert rec["seed"] == 7


def test_relative_paths_resolve_against_the_scenario_folder(tmp_path, capsys, monkeypatch):
    folder = tmp_path / "scen"
    (folder / "maps").mkdir(parents=True)
    (folder / "maps" / "m.map").write_text("type octile\nheight 2\nwidth 3\nmap\n...\n.@.\n")
    scn = write(folder, 'mission = "traversal"\nmap = "maps/m.map"\nagents = 2\njson = "o.json"\n')
    monkeypatch.chdir(tmp_path)  # somewhere else: the paths must not depend on the cwd
    code, _, err = cli(["run", scn], capsys)
    assert code == 0, err
    rec = json.loads((folder / "o.json").read_text())
    assert rec["world"]["free_cells"] == 5


BAD = {
    "missing file": None,
    "not toml": "mission = traversal grid\n",
    "no mission": 'grid = "4x4"\n',
    "unknown mission": 'mission = "swimming"\n',
    "mission as a list": 'mission = ["traversal"]\ngrid = "4x4"\nagents = 2\n',  # was a TypeError
    "unknown option": 'mission = "traversal"\ngrid = "4x4"\nagents = 2\ncolour = "red"\n',
    "table value": 'mission = "traversal"\n[grid]\nw = 4\n',
    "bad value inside": 'mission = "traversal"\ngrid = "4x4"\nagents = 2\nnests = "9,9"\n',
    "bad type inside": 'mission = "traversal"\ngrid = "4x4"\nagents = "two"\n',
    "twice": 'mission = "traversal"\njob_time = 1\njob-time = 2\n',
    "not utf-8": b"mission = \xff\n",
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_scenario_exits_2_with_one_line(name, tmp_path, capsys):
    body = BAD[name]
    path = tmp_path / "s.toml"
    if isinstance(body, bytes):
        path.write_bytes(body)
    elif body is not None:
        path.write_text(body)
    code, out, err = cli(["run", path], capsys)
    assert code == 2, (out, err)
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in out + err
    assert err.count("s.toml") == 1  # the message names the file, once


def test_a_bad_value_given_after_the_file_does_not_blame_the_file(tmp_path, capsys):
    scn = write(tmp_path, 'mission = "traversal"\ngrid = "4x4"\nagents = 2\n')
    for override in (["--agents", "0"], ["--agents=0"]):
        code, _, err = cli(["run", scn, *override], capsys)
        assert code == 2 and err == "swarmex: error: --agents must be at least 1, got 0\n"
    bad = write(tmp_path, 'mission = "traversal"\ngrid = "4x4"\nagents = 0\n', "b.toml")
    code, _, err = cli(["run", bad, "--seed", "3"], capsys)  # the file's own value: named
    assert code == 2 and err.startswith(f"swarmex: error: {bad}: --agents must be")


def test_a_sweep_spec_is_sent_to_swarmex_sweep(tmp_path, capsys):
    spec = write(tmp_path, 'mission = "traversal"\ngrid = "4x4"\nagents = [1, 2]\nseeds = 3\n')
    code, _, err = cli(["run", spec], capsys)
    assert code == 2 and f"run it with 'swarmex sweep {spec} --out DIR'" in err


def test_a_mission_whose_command_is_missing(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(scenario_mod.MISSIONS, "teleport", "teleport-nowhere")
    code, _, err = cli(["run", write(tmp_path, 'mission = "teleport"\n')], capsys)
    assert code == 2 and "teleport-nowhere" in err and len(err.strip().splitlines()) == 1


def test_the_monitor_names_a_scenario_file_once(tmp_path):
    from swarmex.cli.commands_monitor import scenario_mission
    from swarmex.errors import InputError

    path = write(tmp_path, 'mission = "traversal"\ngrid = "4x4"\nagents = 2\ncolour = "red"\n')
    with pytest.raises(InputError) as caught:
        scenario_mission(path)
    assert str(caught.value).count(str(path)) == 1 and "--colour" in str(caught.value)


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_roadmap_examples_run(tmp_path, capsys):
    # examples/ had a scenario for every mission but the roadmap, and no roadmap sweep
    out = tmp_path / "r.json"
    code, text, err = cli(
        ["run", EXAMPLES / "roadmap.toml", "--nodes", "60", "--json", out], capsys
    )
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert rec["params"]["planner"] == "wma-rrt-fairshare" and rec["params"]["task"] == "search"
    assert rec["params"]["sensor_range"] == 40.0 and rec["params"]["goal"] == [250.0, 230.0]
    assert "wma-rrt-fairshare search" in text
    from swarmex.experiments.sweep_spec import load_sweep_spec

    spec = load_sweep_spec(EXAMPLES / "sweep-roadmap.toml")
    assert len(spec.runs()) == 30 and spec.axes["algorithm"][0] == "wma-rrt"


def test_the_recall_example_plays_an_annulus_round_its_memory(tmp_path, capsys):
    out = tmp_path / "r.json"
    code, text, err = cli(["run", EXAMPLES / "foraging-recall.toml", "--json", out], capsys)
    assert code == 0, err
    rec = json.loads(out.read_text())
    assert rec["algorithm"] == "recall" and len(rec["params"]["found"]) == 4
    assert rec["pattern"] == "annulus 96-104"  # distances 98-102, widened by 4/3
    assert "recall (annulus 96-104)" in text
