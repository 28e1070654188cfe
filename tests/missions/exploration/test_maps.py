"""Metric worlds: --empty sizes, ROS map_server maps, and a real MovingAI map."""

from __future__ import annotations

import re

import numpy as np
import pytest
from PIL import Image

from swarmex.errors import InputError
from swarmex.missions.exploration import ExplorationParams, run_exploration
from swarmex.worlds.metric import empty_metric, load_metric, parse_size
from swarmex.worlds.rosmap import load_rosmap


def test_empty_world_is_the_thesis_grid():
    g = empty_metric(*parse_size("20x20"))
    assert g.shape == (400, 400) and g.cell == 0.05
    assert not g.free[0].any() and not g.free[:, -1].any() and g.free[1:-1, 1:-1].all()
    assert g.describe()["width_m"] == pytest.approx(20.0)
    for bad in ("20", "0x5", "-2x3", "ax3"):
        with pytest.raises(InputError, match="--empty"):
            parse_size(bad)


def write_ros(tmp_path, pixels, negate=0, name="map"):
    Image.fromarray(np.asarray(pixels, dtype=np.uint8)).save(tmp_path / f"{name}.pgm")
    (tmp_path / f"{name}.yaml").write_text(
        f"image: {name}.pgm\nresolution: 0.1\norigin: [-1.0, -2.0, 0.0]\n"
        f"negate: {negate}\noccupied_thresh: 0.65\nfree_thresh: 0.196  # comment\n"
    )
    return tmp_path / f"{name}.yaml"


def test_ros_map_trinary_reading(tmp_path):
    # 254 free (white), 0 occupied (black), 205 unknown (map_saver's grey)
    px = [[254, 254, 0], [205, 254, 254]]
    world, res = load_rosmap(write_ros(tmp_path, px))
    assert res == 0.1
    assert world.free.tolist() == [[True, True, False], [False, True, True]]
    world, _ = load_rosmap(write_ros(tmp_path, px, negate=1, name="neg"))
    assert world.free.tolist() == [[False, False, True], [False, False, False]]  # p = v / 255
    g = load_metric(tmp_path / "map.yaml")
    assert g.cell == 0.1
    with pytest.raises(InputError, match="resolution"):
        load_metric(tmp_path / "map.yaml", cell=0.05)


def test_ros_map_errors(tmp_path):
    (tmp_path / "bad.yaml").write_text("resolution: 0.05\n")
    with pytest.raises(InputError, match="lacks 'image'"):
        load_rosmap(tmp_path / "bad.yaml")
    (tmp_path / "noimg.yaml").write_text("image: nothere.pgm\n")
    with pytest.raises(InputError, match="not found"):
        load_rosmap(tmp_path / "noimg.yaml")
    (tmp_path / "junk.pgm").write_bytes(b"P5 junk")
    (tmp_path / "junk.yaml").write_text("image: junk.pgm\n")
    with pytest.raises(InputError, match="cannot read"):
        load_rosmap(tmp_path / "junk.yaml")
    with pytest.raises(InputError, match="not found"):
        load_rosmap(tmp_path / "absent.yaml")


@pytest.mark.parametrize(("line", "message"), [
    ("negate: 5", "negate must be 0 or 1, got 5"),  # was "the map has no free cell"
    ("mode: foo", "mode must be trinary, scale or raw, got 'foo'"),
    ("origin: [a, b]", "origin must be [x, y, yaw] numbers"),
    ("origin: [1]", "origin must be [x, y, yaw] numbers"),
])
def test_ros_map_fields_map_server_would_refuse_are_refused(tmp_path, line, message):
    path = write_ros(tmp_path, [[254, 254], [254, 0]])
    key = line.split(":")[0]
    kept = [x for x in path.read_text().splitlines() if not x.startswith(key + ":")]
    path.write_text("\n".join([*kept, line]) + "\n")
    with pytest.raises(InputError, match=re.escape(message)):
        load_rosmap(path)
    path.write_text("\n".join([*kept, "mode: scale"]) + "\n")  # the three modes are fine
    assert load_rosmap(path)[0].free.sum() == 3


def test_a_ros_map_given_where_a_movingai_map_or_polygons_go_says_so(tmp_path):
    from swarmex.worlds.movingai import load_movingai
    from swarmex.worlds.polygon import load_polygon_world

    path = write_ros(tmp_path, [[254, 254], [254, 0]])
    with pytest.raises(InputError, match="a ROS map, not a MovingAI .map"):
        load_movingai(path)
    with pytest.raises(InputError, match="a ROS map YAML is not a roadmap environment"):
        load_polygon_world(path)


def test_ros_map_is_explored(tmp_path):
    px = np.full((40, 50), 254)
    px[0, :] = px[-1, :] = px[:, 0] = px[:, -1] = 0
    px[15:25, 20:24] = 0
    g = load_metric(write_ros(tmp_path, px))
    run = run_exploration(g, ExplorationParams(robots=2, laser_range=1.0, comm_range=3.0))
    assert run.complete and run.explored_fraction() >= 0.99


def test_real_movingai_rooms(real_map):
    g = load_metric(real_map("room-32-32-4.map"), cell=0.25)  # 1-cell doors = 25 cm
    run = run_exploration(g, ExplorationParams(robots=4, laser_range=2.0, comm_range=5.0))
    assert run.complete and run.explored_fraction() >= 0.99
