"""The monitor draws every mission's real world, rebuilt from the record alone.

Each test runs a small mission through the CLI (``--json``), turns the record into the event
stream with the monitor's own code (``record_world`` + ``record_events``) and checks the world
event against an independent reading of the same world: the map file's text parsed here, the
JSON environment's polygons unioned here, the foraging nest and food found where the robots
actually drop and pick up food. Messages are checked against what the record can support.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from swarmex.cli import main
from swarmex.cli.commands_monitor import record_world
from swarmex.engine.record import read_record
from swarmex.viz.monitor.events import record_events

# a 12×10 MovingAI map: a wall ring (its inside is free: a polygon with a hole) and a post
MAP_ROWS = [
    "............",
    "............",
    "..@@@@@@....",
    "..@....@....",
    "..@....@..@.",
    "..@....@....",
    "..@@@@@@....",
    "............",
    "............",
    "............",
]
ENV = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [
        [[40, 30], [70, 30], [70, 60], [40, 60]],
        [[100, 20], [130, 50], [100, 80]],
        [[60, 50], [90, 50], [90, 70], [60, 70]],  # overlaps the square: one union part
    ],
    "goal": [180, 130],
}


def write_map(path: Path, rows: list[str]) -> Path:
    header = f"type octile\nheight {len(rows)}\nwidth {len(rows[0])}\nmap\n"
    path.write_text(header + "\n".join(rows) + "\n")
    return path


def map_free(rows: list[str]) -> np.ndarray:
    """The map text read here, independently of the loaders: '.' is free, '@' blocked."""
    return np.array([[c == "." for c in row] for row in rows])


def cells_of(world: dict) -> np.ndarray:
    return np.array([[c == "." for c in row] for row in world["cells"]])


def run(tmp_path: Path, *argv: str) -> dict:
    out = tmp_path / f"record-{len(list(tmp_path.glob('record-*')))}.json"
    assert main([*argv, "--json", str(out)]) == 0
    return read_record(out)


def stream(record: dict, base: Path | None = None) -> list[dict]:
    return record_events(record, speed=1.0, world=record_world(record, base))


def messages(events: list[dict]) -> list[dict]:
    return [e for e in events if e["type"] == "message"]


def position(record: dict, agent_id: int, t: float) -> tuple[int, int]:
    agent = next(a for a in record["agents"] if a["id"] == agent_id)
    return next((x, y) for s, x, y, *_ in agent["trajectory"] if s == t)


# ---------------------------------------------------------------------------- traversal


def test_traversal_map_file_is_drawn_and_found_beside_the_record(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_map(tmp_path / "small.map", MAP_ROWS)
    argv = ["traverse", "--map", "small.map", "--agents", "2", "--obstacles", "0,9"]
    record = run(tmp_path, *argv, "--seed", "1")
    expected = map_free(MAP_ROWS)
    expected[9, 0] = False  # --obstacles
    world = stream(record)[1]
    assert world["type"] == "world" and world["kind"] == "grid"
    assert np.array_equal(cells_of(world), expected)
    events = stream(record)
    assert events[0]["messages"] == "events"
    assert len(messages(events)) == record["metrics"]["messages"] == events[-1]["messages"]
    # replayed from another directory: the relative map path is looked up beside the record
    monkeypatch.chdir(tmp_path.parent)
    assert record_world(record)["cells"] is None  # not found: the bounds only
    assert np.array_equal(cells_of(record_world(record, tmp_path)), expected)
    # the map file changed size since the run: not the world it used, so the bounds only
    write_map(tmp_path / "small.map", [row + "." for row in MAP_ROWS])
    assert record_world(record, tmp_path)["cells"] is None


def test_the_header_names_the_map_file_not_its_folders(tmp_path):
    # the whole path of a map deep in a tree pushed the header's buttons off the page
    deep = tmp_path / "some" / "deep" / "folder"
    deep.mkdir(parents=True)
    write_map(deep / "small.map", MAP_ROWS)
    record = run(tmp_path, "traverse", "--map", str(deep / "small.map"), "--agents", "2")
    assert record["world"]["source"] == str(deep / "small.map")  # the record keeps the path
    assert stream(record)[0]["title"] == "traversal · madgta · small.map"


# ---------------------------------------------------------------------------- foraging


@pytest.mark.parametrize(
    ("algorithm", "agents", "grid", "food"),
    [("spiral", 4, 8, ["--food", "1,1"]), ("sectors", 8, 16, ["--food-distance", "20-60"])],
)
def test_foraging_grid_nest_and_food(tmp_path, algorithm, agents, grid, food):
    argv = ["forage", "--grid", str(grid), "--agents", str(agents), "--algorithm", algorithm]
    record = run(tmp_path, *argv, *food, "--food-units", "4", "--seed", "3")
    events = stream(record)
    world = events[1]
    assert (world["width"], world["height"]) == (grid, grid)
    assert cells_of(world).shape == (grid, grid) and cells_of(world).all()  # an empty grid
    marks = {m["kind"]: (m["x"], m["y"]) for m in world["marks"]}
    assert set(marks) == {"nest", "food"}
    # independent: food is picked up at the food mark and dropped at the nest mark
    jobs = [j for a in record["agents"] for j in a["jobs"]]
    assert {(x, y) for _, x, y, kind in jobs if kind == "pickup"} == {marks["food"]}
    assert {(x, y) for _, x, y, kind in jobs if kind == "drop"} == {marks["nest"]}
    assert marks["nest"] == (grid // 2, grid // 2)  # the thesis's centre cell
    if food[0] == "--food":
        assert marks["food"] == tuple(int(v) for v in food[1].split(","))
    else:  # drawn from the seed, as the command does
        from swarmex.missions.foraging.food import sample_food

        assert marks["food"] == sample_food(grid, food[1], np.random.default_rng(3))[0]


def test_foraging_messages_follow_the_informing_rule(tmp_path):
    argv = ["forage", "--grid", "16", "--agents", "8", "--algorithm", "sectors"]
    record = run(tmp_path, *argv, "--food", "3,12", "--food-units", "3", "--seed", "0")
    events = stream(record)
    sent = messages(events)
    assert events[0]["messages"] == "events" and events[-1]["messages"] == len(sent) > 0
    food = tuple(record["params"]["food"])
    informed = {a["id"]: a["metrics"]["informed_at"] for a in record["agents"]}
    told = [
        a["id"]
        for a in record["agents"]
        if informed[a["id"]] is not None and position(record, a["id"], informed[a["id"]]) != food
    ]
    # every robot that did not stand on the food was told once, at the round it learned it
    assert sorted(m["to"] for m in sent) == sorted(told)
    for m in sent:
        assert m["kind"] == "food" and (m["x"], m["y"]) == food
        assert m["t"] == informed[m["to"]]
        assert informed[m["agent"]] is not None and informed[m["agent"]] <= m["t"]
        (sx, sy), (rx, ry) = position(record, m["agent"], m["t"]), position(record, m["to"], m["t"])
        assert abs(sx - rx) + abs(sy - ry) <= 1
    finders = {a["id"] for a in record["agents"] if a["metrics"]["finder"]}
    assert finders and not finders & {m["to"] for m in sent}
    times = [e["t"] for e in events if "t" in e]
    assert times == sorted(times)


# ---------------------------------------------------------------------------- exploration


def test_exploration_empty_world_is_the_walled_rectangle(tmp_path):
    argv = ["explore", "--empty", "3x2", "--robots", "2", "--laser-range", "1"]
    record = run(tmp_path, *argv, "--comm-range", "2", "--seed", "3")
    events = stream(record)
    expected = np.zeros((40, 60), dtype=bool)  # 2 x 3 m at 5 cm, one ring of wall cells
    expected[1:-1, 1:-1] = True
    assert np.array_equal(cells_of(events[1]), expected)
    # no send times in the record: no invented messages, the totals at the end
    assert events[0]["messages"] == "totals" and not messages(events)
    assert events[-1]["messages"] == record["metrics"]["messages_sent"] > 0
    shown = {a["id"]: a["metrics"]["messages_sent"] for a in events[-1]["agents"]}
    assert sum(shown.values()) == record["metrics"]["messages_sent"]


def test_exploration_map_file_is_the_true_occupancy(tmp_path):
    path = write_map(tmp_path / "rooms.map", MAP_ROWS)
    argv = ["explore", "--map", str(path), "--cell", "0.25", "--robots", "2"]
    record = run(tmp_path, *argv, "--laser-range", "1.5", "--starts", "0,0;11,9", "--seed", "1")
    cells = cells_of(stream(record)[1])
    assert np.array_equal(cells, map_free(MAP_ROWS))
    for a in record["agents"]:  # and every cell a robot stood on is free in the drawing
        assert all(cells[y, x] for _, x, y in a["trajectory"])
    # the map file changed size since the run: not the world it used, so the bounds only
    write_map(path, [row + "." for row in MAP_ROWS])
    assert record_world(record)["cells"] is None


# ---------------------------------------------------------------------------- roadmap


def xor_of(rings: list[list[list[float]]]):
    """The region the page fills: the even-odd rule over all rings is their symmetric
    difference."""
    region = Polygon()
    for ring in rings:
        region = shapely.symmetric_difference(region, Polygon(ring))
    return region


@pytest.mark.parametrize("planner", ["wma-rrt", "prm"])
def test_roadmap_polygons_roadmap_and_goal(tmp_path, planner):
    env = tmp_path / "env.json"
    env.write_text(json.dumps(ENV))
    argv = ["roadmap", "--env", str(env), "--agents", "3", "--nodes", "80", "--step", "10"]
    record = run(tmp_path, *argv, "--sensor-range", "20", "--planner", planner, "--seed", "2")
    events = stream(record)
    world = events[1]
    assert world["kind"] == "polygons" and world["cells"] is None
    assert world["bounds"] == ENV["bounds"] and world["y_up"] is True
    truth = shapely.union_all([Polygon(p) for p in ENV["obstacles"]])  # read here
    assert xor_of(world["polygons"]).symmetric_difference(truth).area < 1e-6
    assert len(world["polygons"]) == 2  # the overlapping pair is one part
    roadmap = record["roadmap"]
    assert len(world["edges"]) == len(roadmap["edges"]) + len(roadmap["legs"])
    nodes = np.array(roadmap["nodes"])
    for (i, j), seg in zip(roadmap["edges"], world["edges"], strict=False):
        assert seg == [*nodes[i], *nodes[j]]
    legs = world["edges"][len(roadmap["edges"]) :]  # then the entry legs and the goal's
    assert legs == [[*a, *b] for a, b in roadmap["legs"]]
    assert world["marks"] == [{"kind": "goal", "x": 180.0, "y": 130.0}]
    assert events[0]["messages"] == "none" and not messages(events)
    assert events[-1]["messages"] is None


def test_roadmap_on_a_map_keeps_holes_and_rows_down(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_map(tmp_path / "ring.map", MAP_ROWS)
    argv = ["roadmap", "--env", "ring.map", "--agents", "2", "--nodes", "40", "--step", "1.5"]
    record = run(tmp_path, *argv, "--sensor-range", "3", "--seed", "0")
    world = record_world(record)
    assert world["y_up"] is False and world["bounds"] == [0.0, 0.0, 12.0, 10.0]
    blocked = [
        box(x, y, x + 1, y + 1)
        for y, row in enumerate(MAP_ROWS)
        for x, c in enumerate(row)
        if c == "@"
    ]
    region = xor_of(world["polygons"])
    assert region.symmetric_difference(shapely.union_all(blocked)).area < 1e-9
    assert len(world["polygons"]) == 3  # the ring's outside and its hole, the post
    assert not region.contains(shapely.Point(4.5, 4.5))  # inside the ring: free (a hole)
    # replayed elsewhere: found beside the record, else the bounds only
    monkeypatch.chdir(tmp_path.parent)
    assert "polygons" not in record_world(record)
    assert record_world(record, tmp_path)["polygons"] == world["polygons"]
