"""``swarmex.render(record, path)`` and ``swarmex render RECORD.json OUT``: a run drawn from
Python or from a record file after the fact.

Checked by an independent route: the command line's ``--render`` draws the run as it
happens, from the frames it kept then; the library runs the record again and draws from
the frames of that run. The two files must be byte for byte the same, for every mission, as
a picture and as an animation. A record that no longer comes out the same is drawn with a
warning; a bad path or record is one clear error before any run.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from PIL import Image

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError

ROADMAP_ENV = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [[[40, 30], [70, 30], [70, 60], [40, 60]]],
    "goal": [175, 130],
}


def command(mission: str, tmp: Path) -> list[str]:
    if mission == "traversal":
        return ["traverse", "--grid", "6x5", "--agents", "2"]
    if mission == "foraging":
        return ["forage", "--grid", "8", "--agents", "4", "--algorithm", "spiral",
                "--food-units", "3"]
    if mission == "exploration":
        return ["explore", "--empty", "5x5", "--robots", "2"]
    env = tmp / "env.json"
    env.write_text(json.dumps(ROADMAP_ENV), encoding="utf-8")
    return ["roadmap", "--env", str(env), "--agents", "2", "--nodes", "30", "--step", "15",
            "--sensor-range", "2eps"]


@pytest.mark.parametrize("suffix", [".png", ".gif"])
@pytest.mark.parametrize("mission", ["traversal", "foraging", "exploration", "roadmap"])
def test_python_draws_what_the_command_line_drew(mission: str, suffix: str,
                                                 tmp_path: Path) -> None:
    record, drawn = tmp_path / "r.json", tmp_path / f"cli{suffix}"
    assert main([*command(mission, tmp_path), "--seed", "3", "--json", str(record),
                 "--render", str(drawn)]) == 0
    again = swarmex.render(record, tmp_path / f"lib{suffix}")  # from the file
    assert again == tmp_path / f"lib{suffix}"
    assert again.read_bytes() == drawn.read_bytes()
    rec = swarmex.ResultRecord.from_dict(json.loads(record.read_text()))
    assert swarmex.render(rec, tmp_path / f"obj{suffix}").read_bytes() == drawn.read_bytes()
    with Image.open(again) as image:
        assert image.size[0] > 100 and image.size[1] > 100
        assert (getattr(image, "n_frames", 1) > 1) == (suffix == ".gif")


def test_the_render_command_writes_the_drawing_and_refuses_bad_input(tmp_path: Path,
                                                                     capsys) -> None:
    record = tmp_path / "r.json"
    assert main(["traverse", "--grid", "5x4", "--agents", "2", "--json", str(record)]) == 0
    capsys.readouterr()
    out = tmp_path / "deep" / "x.png"
    assert main(["render", str(record), str(out)]) == 0
    assert out.stat().st_size > 1000 and f"wrote {out}" in capsys.readouterr().out
    for args, said in (([str(record), str(tmp_path / "x.jpg")], "unsupported file type '.jpg'"),
                       ([str(tmp_path / "nope.json"), str(out)], "record not found")):
        assert main(["render", *args]) == 2
        err = capsys.readouterr().err
        assert said in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    with pytest.raises(InputError, match="swarmex.render's path must end in .png, .gif or .mp4"):
        swarmex.render(record, tmp_path / "x.svg")


def test_a_record_that_comes_out_differently_is_drawn_with_a_warning(tmp_path: Path,
                                                                     capsys) -> None:
    rec = swarmex.run("traversal", grid="5x4", agents=2, seed=2).to_dict()
    rec["metrics"]["total_time_all"] += 1  # as if another version had made it
    with pytest.warns(RuntimeWarning, match="came out differently today"):
        assert swarmex.render(rec, tmp_path / "a.png").exists()
    path = tmp_path / "t.json"
    path.write_text(json.dumps(rec), encoding="utf-8")
    assert main(["render", str(path), str(tmp_path / "b.png")]) == 0
    assert "came out differently today" in capsys.readouterr().err
    assert (tmp_path / "b.png").read_bytes() == (tmp_path / "a.png").read_bytes()


def test_the_warning_says_why_the_run_came_out_differently(tmp_path: Path, capsys) -> None:
    # a run its caller stopped, and a world given again, were both blamed on "another
    # swarmex version"
    frames = [0]

    def stop(frame) -> None:
        frames[0] += 1
        if frames[0] == 10:
            raise swarmex.StopRun

    partial = swarmex.run("traversal", grid="6x6", agents=2, seed=1, on_frame=stop)
    assert not partial.complete
    with pytest.warns(RuntimeWarning, match=r"stopped early by its caller \(StopRun"):
        swarmex.render(partial, tmp_path / "p.png")
    path = tmp_path / "p.json"
    partial.write(path)
    assert main(["render", str(path), str(tmp_path / "q.png")]) == 0
    assert "stopped early by its caller" in capsys.readouterr().err
    whole = swarmex.run("traversal", grid="6x6", agents=2, seed=1)
    with pytest.warns(RuntimeWarning, match="grid given again is not the record's"):
        swarmex.render(whole, tmp_path / "g.png", grid="5x5")
    edited = whole.to_dict()
    edited["metrics"]["total_time_all"] += 1
    # the same version: the note says where (it blamed "another swarmex version")
    with pytest.warns(RuntimeWarning, match=r"it differs in metrics\.total_time_all"):
        swarmex.render(edited, tmp_path / "e.png")
    edited["swarmex_version"] = "0.0.1"
    with pytest.warns(RuntimeWarning, match="recorded by swarmex 0.0.1"):
        swarmex.render(edited, tmp_path / "v.png")


def test_a_run_on_a_world_object_is_drawn_with_the_world_given_again(tmp_path: Path) -> None:
    """A record of a run on a GridWorld cannot name its world: the error says how to give it
    to render (not only to rerun), and render takes it (it used to take no world at all, so
    such a record could not be drawn). Other parameters are refused: they would draw another
    run than the record's."""
    import warnings

    from swarmex.worlds.generators import random_obstacles

    world = random_obstacles(6, 6, 0.1, seed=1)
    rec = swarmex.run("traversal", seed=2, map=world, agents=2)
    with pytest.raises(InputError, match=r"swarmex\.render\(record, out, map=world\)"):
        swarmex.render(rec, tmp_path / "a.png")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the same run: no "came out differently" warning
        assert swarmex.render(rec, tmp_path / "a.png", map=world).stat().st_size > 0
    with pytest.raises(InputError, match="only the world again .*not 'agents'"):
        swarmex.render(rec, tmp_path / "b.png", map=world, agents=3)
    assert not (tmp_path / "b.png").exists()


def test_an_output_that_cannot_be_made_fails_before_the_rerun(tmp_path: Path,
                                                               monkeypatch) -> None:
    """``swarmex.render(rec, "file.json/x.png")`` ran the whole record again and then said
    "cannot write …: File exists"; it must fail first, naming the file in the way."""
    import swarmex.experiments.rerun as rerun_module

    rec = swarmex.run("traversal", seed=0, grid="4x4", agents=1)
    blocker = tmp_path / "rec.json"
    rec.write(blocker)

    def no_run(*args, **kwargs):
        raise AssertionError("the run started")

    monkeypatch.setattr(rerun_module, "rerun_outcome", no_run)
    with pytest.raises(InputError, match=r"rec\.json is a file, not a folder"):
        swarmex.render(rec, blocker / "sub" / "x.png")
    (tmp_path / "d.png").mkdir()
    with pytest.raises(InputError, match="it is a folder"):
        swarmex.render(rec, tmp_path / "d.png")


def test_a_roadmap_on_a_polygon_world_object_says_so(tmp_path: Path) -> None:
    """Its record says ``"env": "generated"``: the error was "the record's env 'generated'
    is not found from here (a relative path is …)", as if a file had moved."""
    from shapely.geometry import Polygon

    from swarmex.worlds.polygon import PolygonWorld

    world = PolygonWorld((0, 0, 200, 150), [Polygon([(40, 30), (70, 30), (70, 60), (40, 60)])])
    rec = swarmex.run("roadmap", env=world, agents=2, nodes=30, step=15, sensor_range="2eps")
    with pytest.raises(InputError, match=r"env was given as an object .*env=world"):
        swarmex.render(rec, tmp_path / "a.png")
    assert swarmex.render(rec, tmp_path / "a.png", env=world).exists()
