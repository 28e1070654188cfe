"""``swarmex explore`` end to end: a record on disk, pictures, and one-line errors."""

from __future__ import annotations

import io
import json

import pytest

from swarmex.cli import main
from swarmex.cli.compiling import MESSAGE


def test_explore_writes_record_and_png(tmp_path, capsys):
    rec, png = tmp_path / "run.json", tmp_path / "run.png"
    rc = main(["explore", "--empty", "3x3", "--robots", "2", "--laser-range", "1",
               "--comm-range", "2", "--strategy", "minpos", "--seed", "3",
               "--json", str(rec), "--render", str(png)])
    assert rc == 0
    d = json.loads(rec.read_text())
    assert d["mission"] == "exploration" and d["algorithm"] == "minpos" and d["seed"] == 3
    assert d["complete"] and d["metrics"]["explored_fraction"] >= 0.99
    assert d["world"]["width"] == 60 and d["world"]["cell_m"] == 0.05
    assert d["params"]["laser_range"] == 1.0 and len(d["params"]["starts"]) == 2
    assert png.stat().st_size > 1000
    assert "complete=True" in capsys.readouterr().out


def test_explore_gif_and_starts(tmp_path):
    gif = tmp_path / "run.gif"
    rc = main(["explore", "--empty", "2x2", "--robots", "2", "--laser-range", "0.8",
               "--starts", "10,10;30,30", "--render", str(gif)])
    assert rc == 0 and gif.read_bytes()[:3] == b"GIF"


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--empty", "3x3", "--robots", "1", "--laser-range", "-1"], "--laser-range"),
        (["--empty", "3x3", "--robots", "1", "--comm-range", "-2"], "--comm-range"),
        (["--empty", "3x3", "--robots", "0"], "--robots"),
        (["--empty", "3x3", "--robots", "1", "--starts", "0,0"], "inside a wall"),
        (["--empty", "3x3", "--robots", "2", "--starts", "5,5"], "1 cells for 2 robots"),
        (["--empty", "3x3", "--robots", "1", "--starts", "500,5"], "outside"),
        (["--empty", "3x3", "--robots", "1", "--starts", "a;b"], "--starts"),
        (["--empty", "3by3", "--robots", "1"], "--empty"),
        (["--empty", "3x3", "--robots", "1", "--cell", "0"], "--cell"),
        (["--empty", "3x3", "--robots", "1", "--strategy", "auction"], "--strategy"),
        (["--map", "/no/such.map", "--robots", "1"], "not found"),
        (["--robots", "1"], "--map (or --empty) is required"),
        (["--empty", "3x3", "--robots", "1", "--render", "x.bmp"], "--render"),
        (["--empty", "3x3"], "--robots"),
        (["--empty", "3x3", "--robots", "many"], "robots"),
        (["--empty", "3x3", "--robots", "1", "--seed", "-1"], "--seed"),
        (["--empty", "3x3", "--robots", "1", "--time-scale", "0.01"], "needs --processes"),
        (["--empty", "1000x1000", "--robots", "1"], "20000x20000 = 400,000,000 cells; at most"),
        (["--empty", "3x3", "--robots", "1", "--comm-range", "nan"], "a number or inf, got"),
        (["--empty", "3x3", "--robots", "1", "--robot-radius", "2"],
         "fits in no free cell"),
        (["--empty", "3x3", "--robots", "1", "--beams", "100000000"],
         "--beams must be at most 100000"),  # 22 s and 1.7 GB on a 3 m room
        # at once (it inflated the walls by π·2000² offsets first: minutes, no output)
        (["--empty", "3x3", "--robots", "1", "--robot-radius", "100"],
         "fits in no free cell"),
    ],
)
def test_bad_input_exits_2_with_one_line(args, needle, capsys):
    assert main(["explore", *args]) == 2
    # on a cold numba cache (a fresh xdist worker) a check that runs a kernel first says
    # "compiling kernels", once per process: a notice, not part of the error
    err = "".join(line for line in capsys.readouterr().err.splitlines(keepends=True)
                  if MESSAGE not in line)
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_unreadable_map_files(tmp_path, capsys):
    bad = tmp_path / "bad.map"
    bad.write_text("type octile\nheight 2\nwidth 2\nmap\n..\n")
    assert main(["explore", "--map", str(bad), "--robots", "1"]) == 2
    assert "height 2 but the map has 1 rows" in capsys.readouterr().err
    y = tmp_path / "m.yaml"
    y.write_text("image: m.pgm\nresolution: 0.05\n")
    assert main(["explore", "--map", str(y), "--robots", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "m.pgm" in err


def test_maps_with_no_room_to_move(tmp_path, capsys):
    """A map of walls only, and a map whose passages are narrower than the robot (a MovingAI
    map read at the default 5 cm cells), are refused before the run: they used to raise a
    traceback, or run zero steps and report the mission complete."""
    walls = tmp_path / "walls.map"
    walls.write_text("type octile\nheight 3\nwidth 3\nmap\n@@@\n@@@\n@@@\n")
    assert main(["explore", "--map", str(walls), "--robots", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no free cell" in err and "Traceback" not in err
    narrow = tmp_path / "narrow.map"  # one-cell corridors: 5 cm, for a robot 20 cm wide
    narrow.write_text("type octile\nheight 5\nwidth 5\nmap\n@@@@@\n@...@\n@.@.@\n@...@\n@@@@@\n")
    assert main(["explore", "--map", str(narrow), "--robots", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--cell" in err and "Traceback" not in err
    assert main(["explore", "--map", str(narrow), "--cell", "0.5", "--robots", "1"]) == 0


def test_routing_and_negotiation_options_reach_the_run(tmp_path):
    """--no-aodv, --conflict-yield and --plan-pause land in the record's params, and a
    planning pause makes the same mission slower."""
    base = ["explore", "--empty", "6x6", "--robots", "3", "--comm-range", "2", "--seed", "1"]
    made = {}
    for name, extra in [
        ("default", []),
        ("no-aodv", ["--no-aodv"]),
        ("paused", ["--conflict-yield", "--plan-pause", "3"]),
    ]:
        out = tmp_path / f"{name}.json"
        assert main([*base, *extra, "--json", str(out)]) == 0
        made[name] = json.loads(out.read_text())
    assert made["default"]["params"]["aodv"] is True
    assert made["no-aodv"]["params"]["aodv"] is False
    paused = made["paused"]["params"]
    assert paused["conflict_yield"] is True and paused["plan_pause"] == 3
    assert made["paused"]["makespan"] > made["default"]["makespan"]



class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("render", [None, "run.gif"])
def test_a_long_run_shows_its_progress_on_a_terminal_and_runs_the_same(render, tmp_path,
                                                                        monkeypatch, capsys):
    """An exploration printed nothing until its summary (20 robots on 40 × 40 m: 15 s). On a
    terminal it shows a bar of the free cells mapped of the reachable ones (erased at the
    end); the record and the animation are the same, and nothing is shown in a pipe."""
    from rich.console import Console

    from swarmex.cli import missions
    from swarmex.experiments.progress import FrameProgress

    base = ["explore", "--empty", "4x4", "--robots", "2", "--seed", "2"]
    plain, shown = tmp_path / "plain.json", tmp_path / "shown.json"
    extra = [] if render is None else ["--render", str(tmp_path / f"a{render}")]
    assert main([*base, "--json", str(plain), *extra]) == 0
    assert "mapped" not in capsys.readouterr().err  # a pipe: nothing
    screen = io.StringIO()
    monkeypatch.setattr(missions, "err_console", Console(file=screen, force_terminal=True))
    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    extra = [] if render is None else ["--render", str(tmp_path / f"b{render}")]
    assert main([*base, "--json", str(shown), *extra]) == 0
    # 4 x 4 m at 5 cm, walls included: 78 x 78 free cells, all reachable
    assert "free cells mapped" in screen.getvalue() and "/6084" in screen.getvalue()
    a, b = json.loads(plain.read_text()), json.loads(shown.read_text())
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
    if render is not None:
        assert (tmp_path / f"a{render}").read_bytes() == (tmp_path / f"b{render}").read_bytes()


def test_ctrl_c_during_processes_says_so(monkeypatch, capsys):
    """--processes is run beside the simulator's path; Ctrl-C there ended with a silent 130."""
    import swarmex.cli.shared as shared

    def stop(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(shared, "run_mesh", stop)
    assert main(["explore", "--empty", "3x3", "--robots", "1", "--processes"]) == 130
    assert capsys.readouterr().err.endswith("swarmex: interrupted; nothing written\n")


def test_a_huge_radio_range_is_an_unlimited_one():
    """``--comm-range 1e300`` died in an OverflowError squaring the range."""
    assert main(["explore", "--empty", "3x3", "--robots", "2", "--comm-range", "1e300",
                 "--max-ticks", "5"]) == 0


def test_a_scenario_may_ask_for_processes_as_the_command_line_does(tmp_path, capsys):
    """``processes = true`` in a scenario was "no option --processes", while ``swarmex run
    s.toml --processes`` worked."""
    scn = tmp_path / "mesh.toml"
    scn.write_text('mission = "exploration"\nempty = "3x3"\nrobots = 2\nprocesses = true\n'
                   'time-scale = 0.01\nmax_ticks = 40\njson = "mesh.json"\n', encoding="utf-8")
    assert main(["run", str(scn)]) == 0
    record = json.loads((tmp_path / "mesh.json").read_text(encoding="utf-8"))
    assert "processes" in record["params"] and record["complete"]
    scn.write_text('mission = "exploration"\nempty = "3x3"\nrobots = 2\nprocesses = "yes"\n',
                   encoding="utf-8")
    capsys.readouterr()
    assert main(["run", str(scn)]) == 2
    assert "--processes must be bool, got 'yes'" in capsys.readouterr().err
