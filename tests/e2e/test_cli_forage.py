"""``swarmex forage``: a good run writes a replayable record; bad input exits 2 in one line."""

from __future__ import annotations

import gc
import json
import os
import re

import pytest

from swarmex.cli import main
from swarmex.missions.foraging import replay


def test_forage_writes_a_replayable_record(tmp_path, capsys):
    out = tmp_path / "run.json"
    png = tmp_path / "run.png"
    argv = ["forage", "--grid", "16", "--agents", "8", "--algorithm", "sectors"]
    argv += ["--food-distance", "20-60", "--food-units", "10", "--seed", "3"]
    assert main([*argv, "--json", str(out), "--render", str(png)]) == 0
    rec = json.loads(out.read_text())
    assert rec["mission"] == "foraging" and rec["complete"] is True
    assert rec["params"]["food_units"] == 10 and rec["seed"] == 3
    for key in ("exploration_time", "communication_time", "comm_transport_overlap"):
        assert key in rec["metrics"]
    assert {"transport_time", "food_delivered", "cells_revisited"} <= set(rec["metrics"])
    assert replay(rec) == []
    assert png.stat().st_size > 1000
    # same seed, same record (apart from wall_seconds)
    out2 = tmp_path / "run2.json"
    assert main([*argv, "--json", str(out2)]) == 0
    rec2 = json.loads(out2.read_text())
    rec.pop("wall_seconds"), rec2.pop("wall_seconds")
    assert rec == rec2


def test_forage_gif(tmp_path):
    gif = tmp_path / "run.gif"
    argv = ["forage", "--grid", "8", "--agents", "4", "--algorithm", "spiral", "--food", "1,1"]
    assert main([*argv, "--food-units", "3", "--render", str(gif)]) == 0
    assert gif.read_bytes()[:3] == b"GIF"


STRIPS = ["--grid", "16", "--agents", "4", "--algorithm", "strips"]
BAD = [
    (["--grid", "1", "--agents", "4", "--algorithm", "strips"], "--grid"),
    (["--grid", "16", "--agents", "0", "--algorithm", "strips"], "--agents"),
    (["--grid", "16", "--agents", "3", "--algorithm", "strips"], "multiple"),
    (["--grid", "16", "--agents", "8", "--algorithm", "zigzag"], "power of 4"),
    (["--grid", "16", "--agents", "8", "--algorithm", "hilbert"], "power of 4"),
    (["--grid", "16", "--agents", "12", "--algorithm", "sectors"], "multiple of 8"),
    (["--grid", "16", "--agents", "6", "--algorithm", "spiral"], "power of two"),
    (["--grid", "16", "--agents", "4", "--algorithm", "modified-zigzag"], "8 only"),
    (["--grid", "16", "--agents", "4", "--algorithm", "astar"], "--algorithm must be one of"),
    (["--grid", "100000", "--agents", "4", "--algorithm", "strips"], "--grid must be at most"),
    (["--grid", "1024", "--agents", "80000000", "--algorithm", "sectors"], "--agents"),
    (["--grid", "4", "--agents", "24", "--algorithm", "sectors"], "more robots than"),
    ([*STRIPS, "--food-units", "10**9"], "units"),
    ([*STRIPS, "--food-units", "1000000000"], "--food-units must be at most"),
    ([*STRIPS, "--seed", "-1"], "--seed"),
    ([*STRIPS, "--food", "1,1", "--food-distance", "0-20"], "at most one"),
    ([*STRIPS, "--food-distance", "0-1"], "no cell"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--food", "16,3"], "outside"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--food", "-1,3"], "outside"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--food", "8,8"], "nest"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--food-units", "0"], "units"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--transport", "x"], "transport"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--food-distance", "9"], "LO-HI"),
    (["--grid", "abc", "--agents", "4", "--algorithm", "strips"], "grid"),
    (["--grid", "16", "--agents", "4", "--algorithm", "strips", "--render", "a.txt"], "render"),
]


@pytest.mark.parametrize(("argv", "needle"), BAD)
def test_bad_input_exits_2_with_one_line(argv, needle, capsys):
    assert main(["forage", *argv]) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert needle.lower() in lines[0].lower()


def test_algorithm_names_are_the_builders(capsys):
    """One list: what the parser accepts, its error and --help name exactly the builders."""
    from swarmex.missions.foraging.patterns import ADAPTIVE, ALGORITHMS, BUILDERS

    assert sorted(ALGORITHMS) == sorted([*BUILDERS, *ADAPTIVE])
    assert "twin-strips" not in ALGORITHMS
    assert main(["forage", "--grid", "16", "--agents", "4", "--algorithm", "nosuch"]) == 2
    err = capsys.readouterr().err
    listed = re.search(r"--algorithm must be one of (.*), got 'nosuch'", err)
    assert listed and tuple(listed[1].split(", ")) == ALGORITHMS
    assert main(["forage", "--help"]) == 0
    page = capsys.readouterr().out
    for name in ALGORITHMS:  # whole names, whatever the page's width
        assert re.search(rf"(^|[\s|]){re.escape(name)}([\s|,]|$)", page), name
    # every listed name is accepted by its builder (loop-strips was refused before)
    for name in ALGORITHMS:
        agents = "8" if name in ("modified-zigzag", "sector-loop") else "4"
        argv = ["forage", "--grid", "16", "--agents", agents, "--algorithm", name]
        assert main([*argv, "--food-units", "1"]) == 0, name


UNWRITABLE = "/proc/swarmex-cannot-write"  # writable to os.access as root, yet no file


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="needs a /proc file system")
@pytest.mark.parametrize(
    ("command", "option", "suffix"),
    [(c, o, s) for c in ("forage", "explore") for o, s in
     [("--json", ".json"), ("--render", ".png"), ("--render", ".gif"), ("--render", ".mp4")]],
)
def test_an_output_that_cannot_be_created_exits_2_before_the_run(command, option, suffix,
                                                                  capfd):
    """os.access says yes to root everywhere; the PNG writer raised a traceback after the
    run, the GIF writer printed a second one from imageio's finaliser, and MP4 exited 1."""
    args = (["--grid", "8", "--agents", "4", "--algorithm", "sectors", "--food-units", "2"]
            if command == "forage" else ["--empty", "2x2", "--robots", "1"])
    assert main([command, *args, option, UNWRITABLE + suffix]) == 2
    gc.collect()  # imageio's finaliser, if a writer was left open
    out, err = capfd.readouterr()
    assert err.count("\n") == 1 and "cannot write" in err and "Traceback" not in err
    assert out == ""  # refused before the run: no summary


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="needs a /proc file system")
@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_a_failed_animation_write_is_one_input_error(suffix, capfd):
    """Past the command's check (a full disk, a vanished mount) the writers still fail with
    one InputError line and nothing more on stderr."""
    import numpy as np

    from swarmex.errors import InputError
    from swarmex.viz.animation import write_animation

    frames = [np.zeros((8, 8, 3), dtype=np.uint8)] * 2
    with pytest.raises(InputError) as info:
        write_animation(UNWRITABLE + suffix, frames, fps=4)
    gc.collect()
    assert "\n" not in str(info.value) and "cannot write" in str(info.value)
    assert "Traceback" not in capfd.readouterr().err


@pytest.mark.parametrize("study", ["foraging", "exploration"])
def test_reproduce_bad_out_or_seed_exits_2_with_one_line(study, tmp_path, capsys):
    """An --out that is a file or cannot be made, and a negative --seed, used to raise a
    traceback (FileExistsError, FileNotFoundError, NumPy's 'expected non-negative integer')."""
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    cases = [(["--out", str(a_file)], "not a directory")]
    if os.path.isdir("/proc"):
        cases.append((["--out", "/proc/swarmex-no/dir"], "cannot write"))
    if study == "foraging":
        cases.append((["--out", str(tmp_path / "o"), "--seed", "-1"], "--seed"))
    for args, needle in cases:
        assert main(["reproduce", study, "--quick", *args]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and needle in err and "Traceback" not in err


@pytest.mark.parametrize("study", ["foraging", "exploration"])
def test_reproduce_interrupted_says_where_the_runs_are(study, tmp_path, capsys, monkeypatch):
    """Ctrl-C used to end with status 130 and not a word (Typer swallows it)."""
    import importlib

    def stop(out, *_args, **_kwargs):
        out.mkdir(parents=True, exist_ok=True)
        (out / "runs.jsonl").write_text(journal)
        raise KeyboardInterrupt

    monkeypatch.setattr(importlib.import_module(f"swarmex.studies.{study}"), "reproduce", stop)
    journal = '{"key": "k"}\n'  # one finished run
    assert main(["reproduce", study, "--quick", "--out", str(tmp_path / "o")]) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "interrupted" in err and "runs.jsonl" in err
    journal = ""  # none yet: there is nothing to point to
    assert main(["reproduce", study, "--quick", "--out", str(tmp_path / "p")]) == 130
    assert capsys.readouterr().err == (
        "swarmex: interrupted; no run had finished, so nothing was kept\n")


def test_ctrl_c_inside_a_compiled_kernel_is_a_clean_interrupt(monkeypatch, capsys):
    """Ctrl-C during a numba call surfaces as SystemError ('returned a result with an
    exception set') caused by the KeyboardInterrupt: it used to print a traceback."""
    import swarmex.cli as cli

    def kernel(*_args, **_kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("CPUDispatcher returned a result with an exception set") from exc

    monkeypatch.setattr(cli, "app", kernel)
    assert cli.main(["explore", "--empty", "2x2", "--robots", "1"]) == 130
    assert capsys.readouterr().err == "swarmex: interrupted\n"

    def broken(*_args, **_kwargs):
        raise SystemError("a real bug")

    monkeypatch.setattr(cli, "app", broken)
    with pytest.raises(SystemError):
        cli.main(["explore", "--empty", "2x2", "--robots", "1"])


def test_the_summary_fits_80_columns(capsys, monkeypatch):
    """The phase table's headers were the metric names, cut to 'communicati…' and wrapped
    over three lines in an 80-column terminal or a pipe."""
    from swarmex.cli.app import console

    monkeypatch.setattr(console, "_width", 80)
    argv = ["forage", "--grid", "16", "--agents", "4", "--algorithm", "strips", "--seed", "1"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "…" not in out
    header = next(line for line in out.splitlines() if "exploration" in line)
    for name in ("exploration", "communication", "COMM+TRANS", "transport", "total"):
        assert name in header


def test_ctrl_c_during_a_run_says_so(monkeypatch, capsys):
    """Typer turns a KeyboardInterrupt into a silent status 130; the run now says it was
    interrupted and that nothing was written."""
    from swarmex.missions.foraging.mission import ForagingMission

    def stop(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(ForagingMission, "execute", stop)
    argv = ["forage", "--grid", "8", "--agents", "4", "--algorithm", "sectors"]
    assert main(argv) == 130
    assert capsys.readouterr().err == "swarmex: interrupted; nothing written\n"


def test_a_run_on_a_terminal_shows_robots_told_then_units_home(tmp_path, capsys, monkeypatch):
    """``forage`` had no bar (1024² with 1,024 robots and Sectors: about 10 s in silence); on
    a terminal it shows robots told, then units home, of n + k; the record is the same."""
    import io

    from rich.console import Console

    import swarmex.cli.missions as missions
    from swarmex.experiments.progress import FrameProgress

    argv = ["forage", "--grid", "32", "--agents", "8", "--algorithm", "sectors",
            "--food-units", "5", "--seed", "2", "--json"]
    assert main([*argv, str(tmp_path / "a.json")]) == 0
    screen = io.StringIO()
    monkeypatch.setattr(missions, "err_console", Console(file=screen, force_terminal=True))
    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    assert main([*argv, str(tmp_path / "b.json")]) == 0
    assert "robots told, units home" in screen.getvalue() and "/13" in screen.getvalue()
    a, b = (json.loads((tmp_path / f"{n}.json").read_text()) for n in "ab")
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
    capsys.readouterr()
