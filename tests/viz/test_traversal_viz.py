"""Traversal pictures: files are written, readable, and animations stay within their frame bound."""

from __future__ import annotations

import imageio.v3 as iio
import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.traversal import run_traversal, traversal_record, uniform_agents
from swarmex.viz import frame_times, traversal_gif, traversal_png
from swarmex.viz.traversal import MAX_FRAMES
from swarmex.worlds import random_obstacles


@pytest.fixture(scope="module")
def small_run():
    world = random_obstacles(8, 8, 0.15, seed=3)
    nest = int(np.flatnonzero(~world.blocked)[0])
    return world, run_traversal(world, uniform_agents([nest] * 3, 2.0, 9.0), seed=1)


def snake_record(world, agents: int = 4) -> dict:
    """A cheap synthetic record covering every free cell of a big grid (no simulation)."""
    cells = np.argwhere(world.free)[:, ::-1]  # (x, y)
    out = []
    for i, part in enumerate(np.array_split(cells, agents)):
        t = np.arange(len(part), dtype=float) * 3.0 + 0.5 * i
        rows = np.column_stack([t, part]).tolist()
        out.append({"id": i + 1, "metrics": {}, "trajectory": rows, "jobs": rows})
    return {"algorithm": "synthetic", "agents": out, "complete": True, "time_unit": "s"}


def frame_count(path) -> int:
    return iio.improps(path, index=None).shape[0]


def test_png_from_a_run_and_from_its_record(small_run, tmp_path):
    world, run = small_run
    a = traversal_png(run, world, tmp_path / "run.png")
    b = traversal_png(traversal_record(run, {}).to_dict(), world, tmp_path / "rec.png")
    for p in (a, b):
        img = iio.imread(p)
        assert img.ndim == 3 and img.shape[0] > 200 and img.shape[1] > 200
        assert len(np.unique(img.reshape(-1, img.shape[-1]), axis=0)) > 5  # not blank


def test_gif_frames_are_bounded(small_run, tmp_path):
    world, run = small_run
    path = traversal_gif(run, world, tmp_path / "run.gif", max_frames=25)
    n = frame_count(path)
    assert 2 <= n <= 25
    # frames differ over time: agents move and jobs appear
    frames = iio.imread(path, index=None)
    assert not np.array_equal(frames[0], frames[-1])


def test_default_frame_count_is_bounded_however_long_the_mission():
    rec = {"agents": [{"trajectory": [[t, 0, 0] for t in range(10_000)], "jobs": []}]}
    times = frame_times(rec)
    assert len(times) == MAX_FRAMES <= 150
    assert times[0] == 0 and times[-1] == 9_999
    assert len(frame_times(rec, max_frames=7)) == 7


def test_big_grid_draws_as_an_image(tmp_path):
    world = random_obstacles(256, 257, 0.25, seed=1)  # den520d's size
    rec = snake_record(world)
    png = traversal_png(rec, world, tmp_path / "big.png")
    assert iio.imread(png).shape[0] > 200
    gif = traversal_gif(rec, world, tmp_path / "big.gif", max_frames=12)
    assert 2 <= frame_count(gif) <= 12


def test_wrong_suffix_is_an_input_error(small_run, tmp_path):
    world, run = small_run
    with pytest.raises(InputError):
        traversal_png(run, world, tmp_path / "x.gif")
    with pytest.raises(InputError):
        traversal_gif(run, world, tmp_path / "x.png")


def test_a_title_names_the_map_file_not_its_whole_path():
    from swarmex.viz.traversal import _title

    rec = {"world": {"source": "/work/shared/maps/den520d.map"}, "agents": [{}, {}],
           "algorithm": "madgta"}
    assert _title(rec, outcome=False) == "madgta · 2 agents · den520d.map"
    rec = {"world": {"source": "grid 8x8"}, "agents": [{}], "algorithm": "nearest"}
    assert _title(rec, outcome=False) == "nearest · 1 agent · grid 8x8"
