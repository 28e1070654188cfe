"""``--render FILE.gif|.mp4`` on every mission: animations exist, move, and decode.

Each mission runs through the real CLI on its smallest sensible case, once per animation
format. MP4s are read back with imageio's ffmpeg plugin (frame count, even size for yuv420p,
first and last frames differ because agents moved); GIFs with Pillow (several frames, a real
per-frame delay, the final state held). A wrong suffix is rejected before the run: exit 2,
one line, no traceback.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from swarmex.cli import main

ROADMAP_ENV = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [[[40, 30], [70, 30], [70, 60], [40, 60]], [[100, 20], [130, 50], [100, 80]]],
    "goal": [180, 130],
}


def _roadmap_env(tmp: Path) -> Path:
    env = tmp / "env.json"
    env.write_text(json.dumps(ROADMAP_ENV))
    return env


def _forage(tmp: Path) -> list[str]:
    return ["forage", "--grid", "8", "--agents", "4", "--algorithm", "spiral"] + [
        "--food",
        "1,1",
        "--food-units",
        "3",
    ]


def _explore(tmp: Path) -> list[str]:
    return ["explore", "--empty", "2x2", "--robots", "2", "--laser-range", "0.8"] + [
        "--starts",
        "10,10;30,30",
    ]


def _roadmap(tmp: Path) -> list[str]:
    env = str(_roadmap_env(tmp))
    return ["roadmap", "--env", env, "--agents", "3", "--nodes", "30", "--step", "10"] + [
        "--sensor-range",
        "20",
    ]


def _traverse(tmp: Path) -> list[str]:
    return ["traverse", "--grid", "5x3", "--agents", "2"]


MISSIONS = {"forage": _forage, "explore": _explore, "roadmap": _roadmap, "traverse": _traverse}


@pytest.mark.parametrize("mission", sorted(MISSIONS))
def test_mp4_render_decodes_and_moves(mission, tmp_path, capsys):
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg is not installed")
    import imageio.v2 as iio

    out = tmp_path / "out.mp4"
    assert main([*MISSIONS[mission](tmp_path), "--render", str(out)]) == 0, capsys.readouterr()
    assert out.stat().st_size > 0
    reader = iio.get_reader(out, format="FFMPEG")
    try:
        frames = [np.asarray(f) for f in reader]
    finally:
        reader.close()
    assert len(frames) > 1
    h, w = frames[0].shape[:2]
    assert h % 2 == 0 and w % 2 == 0
    assert not np.array_equal(frames[0], frames[-1])  # agents moved, the map/roadmap changed


@pytest.mark.parametrize("mission", sorted(MISSIONS))
def test_gif_render_has_timed_frames(mission, tmp_path, capsys):
    out = tmp_path / "out.gif"
    assert main([*MISSIONS[mission](tmp_path), "--render", str(out)]) == 0, capsys.readouterr()
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames > 1
        first = np.asarray(im.convert("RGB"))
        delays = []
        for i in range(im.n_frames):
            im.seek(i)
            delays.append(im.info.get("duration", 0))
        last = np.asarray(im.convert("RGB"))
    assert not np.array_equal(first, last)
    assert min(delays) >= 20  # a real frame delay, not 0 (which viewers play at their whim)
    assert delays[-1] >= 1000  # the final state is held before the loop restarts


@pytest.mark.parametrize("mission", sorted(MISSIONS))
def test_bad_render_suffix_exits_2_in_one_line(mission, tmp_path, capsys):
    out = tmp_path / "out.avi"
    assert main([*MISSIONS[mission](tmp_path), "--render", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err and "render" in err.lower()
    assert not out.exists()


def _interrupt_after_a_partial_write(monkeypatch) -> None:
    """matplotlib's and Pillow's writers stop with a few bytes written, as a Ctrl-C or a
    full disk leaves them."""
    from matplotlib.figure import Figure
    from PIL.Image import Image as PILImage

    def partial(path, *args, **kwargs):
        Path(path).write_bytes(b"\x89PNG\r\n")
        raise KeyboardInterrupt

    monkeypatch.setattr(Figure, "savefig", lambda self, path, *a, **k: partial(path))
    monkeypatch.setattr(PILImage, "save", lambda self, path, *a, **k: partial(path))


@pytest.mark.parametrize(("mission", "suffix"),
                         [*((m, ".png") for m in sorted(MISSIONS)), ("traverse", ".gif")])
def test_an_interrupted_drawing_keeps_the_previous_file(mission, suffix, tmp_path, capsys,
                                                        monkeypatch):
    # matplotlib and Pillow wrote straight to --render's path: a Ctrl-C while a PNG (or the
    # traversal GIF, which Pillow writes itself; the others are encoded in memory first) was
    # written left a 0-124 byte image in place of the good one
    out = tmp_path / f"keep{suffix}"
    argv = [*MISSIONS[mission](tmp_path), "--render", str(out)]
    assert main(argv) == 0, capsys.readouterr()
    good = out.read_bytes()
    with monkeypatch.context() as m:
        _interrupt_after_a_partial_write(m)
        assert main(argv) == 130
    capsys.readouterr()
    assert out.read_bytes() == good
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []
    assert [p.name for p in tmp_path.iterdir() if "keep" in p.name] == [out.name]


def test_a_roadmap_png_that_cannot_be_written_is_one_input_error(tmp_path, monkeypatch):
    # the other missions' PNGs said "cannot write"; roadmap's was an OSError traceback
    import errno

    from matplotlib.figure import Figure

    import swarmex
    from swarmex.errors import InputError

    rec = swarmex.run("roadmap", env=_roadmap_env(tmp_path), agents=3, nodes=30, step=10,
                      sensor_range=20)

    def full(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", full)
    with pytest.raises(InputError, match="cannot write .*No space left on device"):
        swarmex.render(rec, tmp_path / "r.png")
    assert not (tmp_path / "r.png").exists()


def test_the_roadmap_png_draws_the_paths_and_says_incomplete(tmp_path, monkeypatch):
    # it coloured every edge by branch, untravelled ones too, and drew no agent's path, so an
    # incomplete PRM run's unreached components read as the agents' coverage
    import swarmex.viz.roadmap_plot as rp
    from swarmex.missions.registry import get

    m = get("roadmap")
    p = m.params(env=_roadmap_env(tmp_path), agents=3, nodes=30, step=10, sensor_range=20,
                 planner="prm", step_budget=3)
    world = m.prepare(p)
    frames: list = []
    m.execute(p, world, frames.append)
    drawn = {}
    monkeypatch.setattr(rp, "save_figure", lambda fig, path, **kw: drawn.setdefault("fig", fig))
    from swarmex.viz.render import draw

    outcome = m.execute(p, world)
    assert outcome.record.complete is False
    draw("roadmap", outcome, str(tmp_path / "r.png"), None)
    ax = drawn["fig"].axes[0]
    assert ax.get_title().endswith("· incomplete")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[:3] == ["agent 1", "agent 2", "agent 3"] and "edge never travelled" in labels
    paths = [ln for ln in ax.lines if ln.get_linewidth() == 2.2]  # one per agent
    assert len(paths) == 3


def test_exploration_frames_say_their_step(tmp_path, capsys):
    # the other missions' animations have a title and a clock; exploration's had neither
    out = tmp_path / "e.gif"
    assert main([*_explore(tmp_path), "--render", str(out)]) == 0, capsys.readouterr()
    with Image.open(out) as im:
        frames = []
        for k in (0, im.n_frames - 1):
            im.seek(k)
            frames.append(np.asarray(im.convert("RGB")))
    bands = [f[:16] for f in frames]
    assert all((b < 100).all(axis=2).sum() > 50 for b in bands)  # dark text on the band
    assert not np.array_equal(bands[0], bands[1])  # the step moves on


@pytest.mark.parametrize("suffix", [".png", ".gif"])
def test_a_roadmap_drawing_keeps_slim_frames_and_draws_the_same(suffix, tmp_path):
    # every whole frame holds a copy of the edge traversals: drawing a 20,000-node roadmap
    # kept 3.4 GB of them; the recorder keeps what the drawing reads, the same picture
    from swarmex.missions.base import FrameList
    from swarmex.missions.registry import get
    from swarmex.viz.render import draw, frame_recorder

    m = get("roadmap")
    p = m.params(env=_roadmap_env(tmp_path), agents=3, nodes=30, step=10, sensor_range=20)
    world = m.prepare(p)
    out = {}
    for name, recorder in (("whole", FrameList()),
                           ("slim", frame_recorder("roadmap", f"r{suffix}"))):
        outcome = m.execute(p, world, recorder)
        out[name] = tmp_path / f"{name}{suffix}"
        draw("roadmap", outcome, out[name], recorder)
        if name == "slim":
            assert len(recorder.frames) > 10
            assert not any(hasattr(f, "edge_traversals") for f in recorder.frames)
    assert out["whole"].read_bytes() == out["slim"].read_bytes()
