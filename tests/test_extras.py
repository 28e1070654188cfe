"""A missing optional extra costs one line naming what to install, never a traceback."""

from __future__ import annotations

import sys

import pytest

from swarmex.cli import main


@pytest.mark.parametrize(
    ("module", "argv", "extra"),
    [
        ("imageio_ffmpeg",
         ["traverse", "--grid", "3x3", "--agents", "1", "--render", "{tmp}/a.mp4"],
         "video"),
        ("starlette", ["monitor", "--scenario", "{tmp}/s.toml"], "monitor"),
        ("ray", ["sweep", "{tmp}/s.toml", "--backend", "ray", "--out", "{tmp}/o"], "ray"),
        ("pyproj",
         ["traverse", "--center", "43.2,-79.9", "--radius", "50", "--nodes-on-edge", "3",
          "--agents", "1"],
         "geo"),
        ("pymavlink", ["uav-emulator", "--listen", "udp:127.0.0.1:0"], "uav"),
        ("ompl.base",
         ["roadmap", "--env", "{tmp}/env.json", "--agents", "1", "--nodes", "10", "--step",
          "10", "--sensor-range", "20", "--planner", "ompl-prm"],
         "ompl"),
        ("pymavlink",
         ["agent", "--connect", "tcp://127.0.0.1:9", "--vehicle", "udp:127.0.0.1:14550"],
         "uav"),
        ("websockets",
         ["watch", "--connect", "tcp://127.0.0.1:9", "--forward", "ws://127.0.0.1:9/ingest",
          "--timeout", "1"],
         "monitor"),
        ("websockets",
         ["mesh", "--empty", "4x4", "--robots", "1", "--monitor", "ws://127.0.0.1:9/ingest"],
         "monitor"),
    ],
)
def test_missing_extra_is_one_line(module, argv, extra, tmp_path, capsys, monkeypatch):
    (tmp_path / "s.toml").write_text('mission = "traversal"\ngrid = "3x3"\nagents = 1\n')
    (tmp_path / "env.json").write_text('{"bounds": [0, 0, 100, 100], "obstacles": []}')
    monkeypatch.setitem(sys.modules, module, None)  # import of it now raises ImportError
    code = main([a.format(tmp=tmp_path) for a in argv])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and f"pip install 'swarmex[{extra}]'" in err, err


def test_missing_envs_extra_is_an_import_error(monkeypatch):
    """From Python, a missing extra is an ImportError naming the extra: ``try: import
    swarmex.envs except ImportError`` is how a caller falls back (an InputError alone, a
    ValueError, slipped past that ``except`` as a traceback)."""
    import importlib

    monkeypatch.setitem(sys.modules, "pettingzoo", None)
    for name in [m for m in sys.modules if m == "swarmex.envs" or m.startswith("swarmex.envs.")]:
        monkeypatch.delitem(sys.modules, name)
    with pytest.raises(ImportError, match=r"pip install 'swarmex\[envs\]'") as info:
        importlib.import_module("swarmex.envs.foraging_v0")
    assert info.value.name == "pettingzoo"


def test_ingest_forwarder_without_the_extra_fails_in_the_caller(monkeypatch):
    """The forwarder's sender thread imported websockets: without it, the thread died with
    a traceback and the events were dropped; the constructor now says which extra."""
    from swarmex.net.events import IngestForwarder

    monkeypatch.setitem(sys.modules, "websockets", None)
    monkeypatch.setitem(sys.modules, "websockets.sync.client", None)
    with pytest.raises(ImportError, match=r"pip install 'swarmex\[monitor\]'"):
        IngestForwarder("ws://127.0.0.1:9/ingest", connect_timeout=0.1)


@pytest.mark.parametrize("command", [
    ["traverse", "--grid", "3x3", "--agents", "1"],
    ["forage", "--grid", "8", "--agents", "4", "--algorithm", "strips"],
])
def test_mp4_without_the_video_extra_fails_before_the_run(command, tmp_path, capsys,
                                                           monkeypatch):
    """The video extra is checked with the other output options: the run used to go to the
    end (its summary printed) and only then fail, with nothing written."""
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    code = main([*command, "--render", str(tmp_path / "a.mp4")])
    out, err = capsys.readouterr()
    assert code == 2 and "swarmex[video]" in err
    assert out == ""  # no run, no summary


def test_mp4_without_the_video_extra_names_no_option_render_lacks(tmp_path, capsys,
                                                                  monkeypatch):
    # `swarmex render REC out.mp4` blamed "--render .mp4", an option render does not have
    assert main(["traverse", "--grid", "3x3", "--agents", "1", "--json",
                 str(tmp_path / "r.json")]) == 0
    capsys.readouterr()
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    assert main(["render", str(tmp_path / "r.json"), str(tmp_path / "a.mp4")]) == 2
    err = capsys.readouterr().err
    assert err == ("swarmex: error: an .mp4 animation needs imageio_ffmpeg:"
                   " pip install 'swarmex[video]'\n")
