"""PolygonWorld: loaders, and collision checks against independent routes."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Point

from swarmex.errors import InputError
from swarmex.sensing.visibility import line_of_sight
from swarmex.worlds.polygon import PolygonWorld, load_polygon_world, parse_polygon_json

ENV = {
    "bounds": [0, 0, 100, 80],
    "obstacles": [
        [[10, 10], [30, 10], [30, 30], [10, 30]],
        [[50, 20], [70, 40], [50, 60]],
        [[60, 0], [120, 0], [120, 8], [60, 8]],  # sticks out of the bounds: clipped
        [[20, 50], [40, 50], [40, 52], [22, 52], [22, 70], [20, 70]],
    ],
    "goal": [90, 70],
}


@pytest.fixture(scope="module")
def world() -> PolygonWorld:
    return parse_polygon_json(json.dumps(ENV), "test")


def brute_points_free(world: PolygonWorld, xy: np.ndarray) -> np.ndarray:
    xmin, ymin, xmax, ymax = world.bounds
    out = []
    for x, y in xy:
        inside = xmin <= x <= xmax and ymin <= y <= ymax
        out.append(inside and not any(p.intersects(Point(x, y)) for p in world.obstacles))
    return np.array(out)


def brute_segments_free(world: PolygonWorld, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ok = brute_points_free(world, a) & brute_points_free(world, b)
    for i, (p, q) in enumerate(zip(a, b, strict=True)):
        if ok[i]:
            line = LineString([p, q])
            ok[i] = not any(poly.intersects(line) for poly in world.obstacles)
    return ok


def test_parse_clips_and_keeps_goal(world):
    assert world.bounds == (0, 0, 100, 80)
    assert len(world.obstacles) == 4
    assert max(p.bounds[2] for p in world.obstacles) <= 100
    assert world.goal == (90.0, 70.0)
    assert world.free_area == pytest.approx(100 * 80 - shapely.union_all(world.obstacles).area)
    assert world.describe()["kind"] == "polygons"


def test_points_free_matches_per_obstacle_checks(world):
    rng = np.random.default_rng(0)
    xy = rng.uniform([-10, -10], [110, 90], size=(2000, 2))
    xy = np.vstack([xy, [[10, 10], [30, 20], [0, 0], [100, 80], [50, 40]]])  # edges, corners
    assert np.array_equal(world.points_free(xy), brute_points_free(world, xy))


def test_segments_free_three_routes_agree(world):
    rng = np.random.default_rng(1)
    a = rng.uniform([-5, -5], [105, 85], size=(1500, 2))
    b = a + rng.normal(0, 25, size=a.shape)
    want = brute_segments_free(world, a, b)
    assert np.array_equal(world.segments_free(a, b), want)
    assert np.array_equal(world.segments_free_by_tree(a, b), want)
    for i in range(0, 1500, 37):
        assert world.segment_free(*a[i], *b[i]) == want[i]
    assert want.any() and not want.all()


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.5, 99.5), min_size=4, max_size=4))
def test_line_of_sight_kernel_matches_shapely(world, c):
    a, b = np.array([c[:2]]), np.array([c[2:]])
    if not (world.points_free(a)[0] and world.points_free(b)[0]):
        return
    assert line_of_sight(world.edges, a, b)[0] == world.segments_free(a, b)[0]


def test_touching_a_corner_is_a_collision(world):
    # the segment grazes the square's corner (30, 30): closed obstacles block it
    assert not world.segment_free(20, 40, 40, 20)
    assert not line_of_sight(world.edges, np.array([[20, 40]]), np.array([[40, 20]]))[0]


def test_sampling_is_free_and_seeded(world):
    a = world.sample_free(np.random.default_rng(5), 500)
    b = world.sample_free(np.random.default_rng(5), 500)
    assert a.shape == (500, 2) and np.array_equal(a, b)
    assert world.points_free(a).all()


def test_clearance(world):
    c = world.clearance(np.array([[5.0, 20.0], [20.0, 20.0], [45.0, 40.0]]))
    assert c[0] == pytest.approx(5.0)  # 5 to the bound and to the square
    assert c[1] == 0.0  # inside the square
    assert c[2] > 0


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("{not json", "malformed JSON"),
        ('{"obstacles": []}', "bounds"),
        ('{"bounds": [0, 0, 10]}', "bounds"),
        ('{"bounds": [0, 0, -1, 10], "obstacles": []}', "xmin < xmax"),
        # GEOS overflowed on it later, a traceback
        ('{"bounds": [0, 0, 1e308, 1e308], "obstacles": []}', "within"),
        ('{"bounds": [0, 0, 10, 10], "obstacles": [[[1, 1], [2, 2]]]}', "at least 3"),
        ('{"bounds": [0, 0, 10, 10], "obstacles": [[[1, 1], [5, 5], [5, 1], [1, 5]]]}',
         "not a valid polygon"),
        ('{"bounds": [0, 0, 10, 10], "obstacles": [[[1, 1], [2, "x"], [3, 1]]]}', "pair"),
    ],
)
def test_bad_json_is_an_input_error(text, needle):
    with pytest.raises(InputError, match=needle):
        parse_polygon_json(text, "bad.json")


def test_movingai_and_image_cells_become_squares(tmp_path):
    rows = ["....", ".@@.", "..@.", "...."]
    mp = tmp_path / "m.map"
    mp.write_text("type octile\nheight 4\nwidth 4\nmap\n" + "\n".join(rows) + "\n")
    w = load_polygon_world(mp)
    assert w.y_down and w.bounds == (0, 0, 4, 4)
    assert w.free_area == pytest.approx(13.0)
    assert not w.points_free(np.array([[1.5, 1.5]]))[0]  # cell (x=1, y=1) is '@'
    assert w.points_free(np.array([[1.5, 2.5]]))[0]  # cell (x=1, y=2) is '.'
    import imageio.v3 as iio

    img = np.full((4, 4), 255, dtype=np.uint8)
    img[1, 1:3] = 0
    img[2, 2] = 0
    png = tmp_path / "m.png"
    iio.imwrite(png, img)
    wi = load_polygon_world(png)
    assert wi.free_area == pytest.approx(13.0)
    assert shapely.equals(shapely.union_all(wi.obstacles), shapely.union_all(w.obstacles))


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        load_polygon_world(tmp_path / "nope.json")


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # imageio tries every plugin
def test_an_unreadable_image_is_one_line(tmp_path):
    # imageio's message goes on with lines of plugins to pip install; bad input is one line
    png = tmp_path / "bad.png"
    png.write_bytes(b"not a png")
    with pytest.raises(InputError, match="cannot read image") as caught:
        load_polygon_world(png)
    assert "\n" not in str(caught.value)
