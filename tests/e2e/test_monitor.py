"""The live monitor: event stream vs record, WebSocket pacing, ingest, and a real browser.

Every server here listens on 127.0.0.1 on a free port and stops by itself (``linger``); the
browser test drives Debian's chromium with Playwright and skips, saying why, when either is
missing (``playwright install`` downloads are not used).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import queue
import shutil
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from swarmex.cli import main
from swarmex.cli.commands_monitor import free_cells, record_world
from swarmex.engine.record import read_record
from swarmex.viz.monitor.events import SCHEMA, record_events
from swarmex.viz.monitor.hub import replay
from swarmex.viz.monitor.server import MonitorServer

websockets = pytest.importorskip("websockets", reason="websockets is not installed")
from websockets.sync.client import connect  # noqa: E402

SCENARIO = """
mission = "traversal"
grid = "8x6"
obstacles = ["3,1", "3,2", "3,3", "5,4"]
agents = 3
nests = ["0,0"]
seed = 2
"""
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


@pytest.fixture(scope="module")
def record(tmp_path_factory) -> dict:
    path = tmp_path_factory.mktemp("monitor") / "record.json"
    argv = ["traverse", "--grid", "8x6", "--obstacles", "3,1;3,2;3,3;5,4", "--agents", "3"]
    assert main([*argv, "--nests", "0,0", "--seed", "2", "--json", str(path)]) == 0
    return read_record(path)


def by_agent(events: list[dict], kind: str) -> dict[int, list[list[float]]]:
    out: dict[int, list[list[float]]] = {}
    for e in events:
        if e["type"] == kind:
            out.setdefault(e["agent"], []).append([e["t"], e["x"], e["y"]])
    return out


def check_against_record(events: list[dict], record: dict) -> None:
    """The stream says exactly what the record says: paths, jobs, messages, the end."""
    assert events[0]["type"] == "hello" and events[0]["schema"] == SCHEMA
    assert events[0]["agents"] == [a["id"] for a in record["agents"]]
    moves, jobs = by_agent(events, "move"), by_agent(events, "job")
    for a in record["agents"]:
        assert moves[a["id"]] == a["trajectory"]
        assert jobs.get(a["id"], []) == a["jobs"]
    assert sum(e["type"] == "message" for e in events) == record["metrics"]["messages"]
    times = [e["t"] for e in events if "t" in e]
    assert times == sorted(times)
    end = events[-1]
    assert end["type"] == "end"
    assert (end["complete"], end["makespan"]) == (record["complete"], record["makespan"])
    assert end["metrics"] == record["metrics"]


# ---------------------------------------------------------------------------- the stream


def test_record_events_match_the_record(record):
    free = free_cells(record)
    events = record_events(record, free, speed=10.0)
    check_against_record(events, record)
    world = events[1]
    assert world["type"] == "world" and (world["width"], world["height"]) == (8, 6)
    cells = np.array([[c == "." for c in row] for row in world["cells"]])
    expected = np.ones((6, 8), dtype=bool)
    for x, y in [(3, 1), (3, 2), (3, 3), (5, 4)]:
        expected[y, x] = False
    assert np.array_equal(cells, expected)


def test_a_record_without_its_world_parameters_replays_with_the_bounds():
    """A foraging-style record lacking the parameters its map is rebuilt from (no grid, no
    food): the bounds, moves and jobs (with their kind), and no invented messages."""
    record = {
        "mission": "foraging",
        "algorithm": "spiral",
        "time_unit": "step",
        "complete": True,
        "makespan": 3.0,
        "metrics": {"total_time": 3},
        "world": {"kind": "grid", "source": "empty 4x4", "width": 4, "height": 4},
        "agents": [
            {
                "id": 0,
                "metrics": {},
                "trajectory": [[0, 1, 1], [1, 2, 1], [2, 2, 2]],
                "jobs": [[2, 2, 2, "pickup"], [3, 1, 1, "drop"]],
            },
        ],
    }
    events = record_events(record, speed=1.0, world=record_world(record))
    assert events[1]["cells"] is None and "marks" not in events[1]
    assert (events[1]["width"], events[1]["height"]) == (4, 4)
    assert [e["kind"] for e in events if e["type"] == "job"] == ["pickup", "drop"]
    assert not [e for e in events if e["type"] == "message"]
    assert events[-1]["type"] == "end" and events[-1]["t"] == 3


def test_replay_at_infinite_speed_publishes_everything_at_once(record):
    from swarmex.viz.monitor.hub import EventHub

    events = record_events(record, free_cells(record), float("inf"))

    async def go() -> list[dict]:
        hub = EventHub()
        q = hub.subscribe()
        await asyncio.wait_for(replay(hub, events, float("inf"), wait_for_viewer=False), 5)
        got: list[dict] = []
        while not q.empty():
            got += q.get_nowait()
        return got

    assert asyncio.run(go()) == events


class ServerThread:
    """A monitor server on its own thread and event loop, stopped by the test or by linger."""

    def __init__(self, record: dict | None, speed: float | None = None, linger: float = 5.0):
        self.server = MonitorServer(0, record)
        producer = None
        if record is not None:
            events = record_events(record, free_cells(record), speed)

            def producer(hub):
                return replay(hub, events, speed, wait_for_viewer=True)

        self.thread = threading.Thread(
            target=lambda: asyncio.run(self.server.run(producer, linger)), daemon=True
        )

    def __enter__(self) -> MonitorServer:
        self.thread.start()
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            try:
                urllib.request.urlopen(self.server.url, timeout=1).read()
                return self.server
            except OSError:
                time.sleep(0.05)
        raise AssertionError("the monitor server did not start")

    def __exit__(self, *exc) -> None:
        self.server.stop()
        self.thread.join(timeout=10)
        assert not self.thread.is_alive()


def receive_until_end(ws, timeout: float = 20.0) -> tuple[list[dict], list[float]]:
    """All events up to the end event, and the wall time at which each frame arrived."""
    events, stamps = [], []
    deadline = time.monotonic() + timeout
    while True:
        batch = json.loads(ws.recv(timeout=max(0.1, deadline - time.monotonic())))
        events += batch
        stamps += [time.monotonic()] * len(batch)
        if any(e["type"] == "end" for e in batch):
            return events, stamps


def test_websocket_stream_is_paced_and_matches_the_record(record):
    duration = 1.5  # wall seconds the mission should take to play
    speed = record["makespan"] / duration
    with ServerThread(record, speed) as server:
        ws_url = f"ws://127.0.0.1:{server.port}/ws"
        with connect(ws_url, open_timeout=5) as ws:
            events, stamps = receive_until_end(ws)
        kept = [e for e in events if e["type"] != "clock"]
        check_against_record(kept, record)
        first_move = next(i for i, e in enumerate(events) if e["type"] == "move")
        assert stamps[-1] - stamps[first_move] > 0.6 * duration  # paced, not dumped
        # a viewer joining after the end gets the whole history at once
        with connect(ws_url, open_timeout=5) as late:
            again, _ = receive_until_end(late, timeout=5)
        assert again == kept
        page = urllib.request.urlopen(server.url, timeout=5).read().decode()
        assert "<canvas" in page and "/monitor.js" in page
        script = urllib.request.urlopen(server.url + "monitor.js", timeout=5).read().decode()
        assert "monitorSnapshot" in script
        served = json.loads(urllib.request.urlopen(server.url + "record", timeout=5).read())
        assert served == record


def test_ingest_feeds_the_same_page_stream():
    """A networked runtime publishes on /ingest; viewers see its events, in order."""
    with ServerThread(None, linger=0.5) as server:
        base = f"ws://127.0.0.1:{server.port}"
        feed = [
            {
                "type": "hello",
                "schema": SCHEMA,
                "mission": "traversal",
                "source": "network",
                "agents": [1, 2],
                "time_unit": "s",
                "speed": None,
            },
            {"type": "move", "t": 0.0, "agent": 1, "x": 0, "y": 0},
            {"type": "message", "t": 0.5, "agent": 1, "to": None, "kind": "pos", "x": 0, "y": 0},
        ]
        with connect(base + "/ws", open_timeout=5) as viewer, connect(base + "/ingest") as src:
            src.send(json.dumps(feed[0]))  # one event per frame or a list: both accepted
            # a frame that is not JSON, and an event at no time, are dropped: the producer's
            # socket used to be closed on the first, and the second came back as t: null
            src.send("not json")
            src.send(json.dumps([{"type": "move", "t": float("nan"), "agent": 1, "x": 0,
                                  "y": 0}]))
            src.send(json.dumps(feed[1:]))
            got: list[dict] = []
            while len(got) < 3:
                got += json.loads(viewer.recv(timeout=5))
            assert got == feed
            # a new hello starts a new mission: late viewers get history from it only
            src.send(json.dumps([{**feed[0], "agents": [7]}, {"type": "end", "t": 1.0}]))
            while got[-1]["type"] != "end":
                got += json.loads(viewer.recv(timeout=5))
            with connect(base + "/ws", open_timeout=5) as late:
                history = json.loads(late.recv(timeout=5))
        assert [e["type"] for e in history] == ["hello", "end"]
        assert history[0]["agents"] == [7]
        config = json.loads(urllib.request.urlopen(
            f"http://127.0.0.1:{server.port}/config", timeout=5).read())
        assert config["ingest_dropped"] == 2


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--speed", "0"], "--speed must be > 0"),
        (["--scenario", "nope.toml"], "scenario file not found"),
        (["--record", "nope.json"], "record not found"),
        (["--scenario", "a.toml", "--record", "b.json"], "at most one of"),
        (["--connect", "tcp://127.0.0.1:9", "--record", "b.json"], "at most one of"),
        (["--port", "70000"], "--port must be"),
        # the reader thread died with a ZMQError traceback and the page waited for nothing
        (["--connect", "foo"], "--connect: expected tcp://HOST:PORT"),
        (["--connect", "tcp://127.0.0.1"], "--connect: expected tcp://HOST:PORT"),
        # --json was ignored with --connect, and an unwritable one failed after the run with
        # status 0; a snapshot folder that cannot be made was a traceback
        (["--connect", "tcp://127.0.0.1:9", "--json", "r.json"], "--json with --connect"),
        (["--connect", "tcp://127.0.0.1:99999"], "--connect: expected tcp://HOST:PORT"),
        (["--scenario", "examples/traversal.toml", "--json", "/proc/x.json"],
         "--json: cannot write /proc/x.json"),
        (["--scenario", "examples/traversal.toml", "--snapshot-every", "1", "/proc/snaps"],
         "--snapshot-every: cannot make /proc/snaps"),
    ],
)
def test_monitor_bad_input_exits_2(argv, message, capsys):
    assert main(["monitor", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


# ---------------------------------------------------------------------------- a browser


def start_monitor_with(args: list[str]) -> tuple[subprocess.Popen, str]:
    """``swarmex monitor ARGS`` in a subprocess; returns it and the page's URL."""
    cmd = [sys.executable, "-m", "swarmex", "monitor", *args]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(x) for x in proc.stdout], daemon=True).start()
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            line = lines.get(timeout=1)
        except queue.Empty:
            assert proc.poll() is None, "swarmex monitor exited early"
            continue
        if "http://127.0.0.1:" in line:
            url = line[line.index("http://") :].split()[0]
            return proc, url
    proc.kill()
    raise AssertionError("swarmex monitor printed no address")


@contextlib.contextmanager
def monitor_page(args: list[str]) -> Iterator[tuple[Any, list[str]]]:
    """A headless Chromium page on ``swarmex monitor ARGS`` (skips without Playwright or
    chromium); yields the page and the page's JavaScript errors. Browser and monitor are
    closed on the way out, whatever happens."""
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="playwright is not installed (pip install playwright)"
    )
    if CHROMIUM is None:
        pytest.skip("chromium is not installed (apt-get install chromium; .ci/run does it)")
    proc, url = start_monitor_with(args)
    try:
        with sync_api.sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            try:
                page = browser.new_page(viewport={"width": 1000, "height": 600})
                errors: list[str] = []
                page.on("pageerror", lambda e: errors.append(str(e)))
                page.goto(url, timeout=15000)
                yield page, errors
            finally:
                browser.close()
    finally:
        proc.terminate()
        proc.wait(timeout=15)


def test_browser_shows_agents_moving_and_the_final_state(tmp_path):
    speed = 50.0  # the 185 s mission plays in about 3.7 s
    scenario = tmp_path / "mission.toml"
    scenario.write_text(SCENARIO)
    rec_path = tmp_path / "streamed.json"
    args = ["--scenario", str(scenario), "--speed", str(speed), "--linger", "20"]
    with monitor_page([*args, "--json", str(rec_path)]) as (page, errors):
        page.wait_for_function(
            "() => { const s = monitorSnapshot();"
            " return s.agents.length === 3 && s.agents.every(a => a.x !== null)"
            " && s.t > 10; }",
            timeout=20000,
        )
        first = page.evaluate("monitorSnapshot()")
        page.wait_for_timeout(1000)
        second = page.evaluate("monitorSnapshot()")
        assert not first["ended"], "the mission ended before the page saw it move"
        assert second["t"] > first["t"]
        assert sum(a["path"] for a in second["agents"]) > sum(
            a["path"] for a in first["agents"]
        )
        page.wait_for_function("monitorSnapshot().ended", timeout=30000)
        final = page.evaluate("monitorSnapshot()")
        dark = page.evaluate(COLOUR_PIXELS, [40, 40, 40])
        shot = page.screenshot(path=str(tmp_path / "monitor.png"))
    assert not errors
    # the 4 obstacle cells are painted (grid lines cross them: a little under 4 full cells)
    assert 0.6 * 4 * final["cellPixels"] ** 2 < dark <= 4 * final["cellPixels"] ** 2 + 1
    record = read_record(rec_path)
    assert final["status"] == "ended" and final["draws"] > 0
    assert (final["complete"], final["makespan"]) == (record["complete"], record["makespan"])
    assert final["world"] == {"width": 8, "height": 6, "rows": 6}
    assert final["messages"] == record["metrics"]["messages"]
    assert final["jobs"] == sum(len(a["jobs"]) for a in record["agents"])
    for shown, a in zip(final["agents"], record["agents"], strict=True):
        assert shown["id"] == a["id"]
        assert [shown["x"], shown["y"]] == a["trajectory"][-1][1:]
        assert shown["path"] == len(a["trajectory"])
        assert shown["jobs"] == len(a["jobs"])
    assert len(shot) > 5000  # a real picture of the map, paths and agents


OBSTACLE_PIXELS = """() => {
  const c = document.getElementById("map");
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  let n = 0;
  for (let i = 0; i < d.length; i += 4) {
    if (d[i] === 40 && d[i + 1] === 40 && d[i + 2] === 40) n += 1;  // blocked: rgb(40,40,40)
  }
  return n / (c.width * c.height);
}"""


def test_browser_draws_a_roadmap_world_and_says_messages_are_na(tmp_path):
    """A roadmap record: its polygons are painted (obstacle pixels on the canvas), the
    roadmap and goal arrive, and the page says n/a for a rate it cannot know."""
    env = tmp_path / "env.json"
    obstacles = [[[40, 30], [100, 30], [100, 90], [40, 90]]]  # 3600 of 30000 m²: 12 %
    env.write_text(json.dumps({"bounds": [0, 0, 200, 150], "obstacles": obstacles}))
    rec = tmp_path / "roadmap.json"
    argv = ["roadmap", "--env", str(env), "--agents", "2", "--nodes", "40", "--step", "10"]
    assert main([*argv, "--sensor-range", "20", "--seed", "1", "--json", str(rec)]) == 0
    with monitor_page(["--record", str(rec), "--speed", "inf", "--linger", "15"]) as (
        page,
        errors,
    ):
        page.wait_for_function("monitorSnapshot().ended", timeout=15000)
        page.wait_for_timeout(300)  # the panel refreshes every 200 ms
        final = page.evaluate("monitorSnapshot()")
        painted = page.evaluate(OBSTACLE_PIXELS)
        rate = page.inner_text("#rate")
    record = read_record(rec)
    assert not errors
    assert final["mission"] == "roadmap" and final["map"]["polygons"] == 1
    assert final["map"]["edges"] == len(record["roadmap"]["edges"]) + len(record["roadmap"]["legs"])
    assert final["map"]["yUp"] is True
    assert 0.02 < painted < 0.2  # the square, not nothing and not the whole canvas
    assert final["messageMode"] == "none" and rate == "n/a"


def test_browser_says_which_agents_fly_what_in_a_hybrid_mission():
    """Issue 15: a hybrid mission's hello names each agent's vehicle, and a spare's join
    names its own; the page shows them beside the agents."""
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="playwright is not installed (pip install playwright)"
    )
    if CHROMIUM is None:
        pytest.skip("chromium is not installed (apt-get install chromium; .ci/run does it)")
    hello = {"type": "hello", "schema": SCHEMA, "mission": "traversal", "source": "network",
             "agents": [1, 2, 3], "time_unit": "s", "speed": None,
             "vehicles": [{"id": 1, "kind": "mavlink"}, {"id": 2, "kind": "simulated"},
                          {"id": 3, "kind": "simulated"}]}
    feed = [hello, {"type": "move", "t": 0.0, "agent": 1, "x": 0, "y": 0},
            {"type": "job", "t": 0.5, "agent": 2, "x": 1, "y": 0},
            {"type": "message", "t": 0.5, "agent": 2, "to": None, "kind": "job", "x": 1,
             "y": 0},
            # agent 2 is declared gone: its job at (1, 0) reverts to not done
            {"type": "message", "t": 1.0, "agent": 2, "to": None, "kind": "left", "x": 1,
             "y": 0},
            {"type": "message", "t": 2.0, "agent": 2, "to": None, "kind": "join",
             "vehicle": "mavlink"}]  # a MAVLink spare took id 2
    with ServerThread(None, linger=5.0) as server, sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1000, "height": 600})
            errors: list[str] = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(f"http://127.0.0.1:{server.port}/", timeout=15000)
            with connect(f"ws://127.0.0.1:{server.port}/ingest") as src:
                src.send(json.dumps(feed))
                page.wait_for_function(
                    "() => monitorSnapshot().agents.length === 3"
                    " && monitorSnapshot().agents[1].vehicle === 'mavlink'",
                    timeout=15000,
                )
                page.wait_for_function(  # the agents' table is redrawn on the next frame
                    "() => document.body.innerText.includes('mavlink')", timeout=15000
                )
            snap = page.evaluate("monitorSnapshot()")
            text = page.inner_text("body")
        finally:
            browser.close()
    assert not errors
    assert [a["vehicle"] for a in snap["agents"]] == ["mavlink", "mavlink", "simulated"]
    assert "mavlink" in text and "simulated" in text
    # the left un-painted the abandoned job, and only the mission's message is counted (the
    # record's count): left and join are the protocol's status
    assert snap["jobs"] == 0 and snap["messages"] == 1


COLOUR_PIXELS = """([r, g, b]) => {
  const c = document.getElementById("map");
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  let n = 0;
  for (let i = 0; i < d.length; i += 4) {
    if (d[i] === r && d[i + 1] === g && d[i + 2] === b) n += 1;
  }
  return n;
}"""
FRONTIER_RGB, UNKNOWN_RGB = [255, 152, 0], [176, 190, 197]
EXPLORATION_SCENARIO = """
mission = "exploration"
empty = "3x3"
cell = 0.1
robots = 2
laser_range = 0.8
starts = "5,5;25,25"
seed = 1
"""


def test_browser_draws_the_exploration_map_as_it_grows(tmp_path):
    """Issue 16 item 4: the live exploration view veils unknown cells and lights the frontier
    as the merged map grows; checked by pixel counts against the streamed state (cells times
    pixels per cell), mid-run and at the end, and the --snapshot-every PNGs are written."""
    scenario = tmp_path / "explore.toml"
    scenario.write_text(EXPLORATION_SCENARIO)
    shots = tmp_path / "shots"
    args = ["--scenario", str(scenario), "--speed", "10", "--linger", "20",
            "--snapshot-every", "0.5", str(shots)]
    with monitor_page(args) as (page, errors):
        page.wait_for_function(
            "() => { const s = monitorSnapshot(); return s.known && s.known.frontier > 10"
            " && !s.ended; }", timeout=60000)
        page.wait_for_timeout(250)  # a drawn frame of that state
        mid = page.evaluate("monitorSnapshot()")
        mid_orange = page.evaluate(COLOUR_PIXELS, FRONTIER_RGB)
        mid_veil = page.evaluate(COLOUR_PIXELS, UNKNOWN_RGB)
        page.wait_for_function("monitorSnapshot().ended", timeout=60000)
        page.wait_for_timeout(700)
        final = page.evaluate("monitorSnapshot()")
        end_orange = page.evaluate(COLOUR_PIXELS, FRONTIER_RGB)
        end_veil = page.evaluate(COLOUR_PIXELS, UNKNOWN_RGB)
        jobs_shown = page.is_visible("#jobs-row")
    assert not errors
    cell = mid["cellPixels"] ** 2
    cells = 30 * 30
    unknown_mid = cells - mid["known"]["free"] - mid["known"]["occupied"]
    # frontier cells are lit (robots and goal crosses hide a few), unknown ones veiled
    frontier_px = mid["known"]["frontier"] * cell
    assert 0.5 * frontier_px < mid_orange < 1.2 * frontier_px
    assert 0.6 * unknown_mid * cell < mid_veil < 1.2 * unknown_mid * cell
    assert final["complete"] and final["known"]["frontier"] == 0 and end_orange == 0
    unknown_end = cells - final["known"]["free"] - final["known"]["occupied"]
    assert end_veil <= 1.2 * unknown_end * cell + 1
    assert not jobs_shown  # no meaningless jobs column in exploration
    pngs = sorted(shots.glob("snapshot-*.png"))
    assert pngs and all(p.read_bytes()[:4] == b"\x89PNG" for p in pngs)


def test_browser_draws_the_roadmap_weights_live(tmp_path):
    """A live roadmap run: the travelled edges arrive as weights and are drawn in blue."""
    env = tmp_path / "env.json"
    env.write_text(json.dumps({"bounds": [0, 0, 200, 150],
                               "obstacles": [[[40, 30], [100, 30], [100, 90], [40, 90]]]}))
    scenario = tmp_path / "roadmap.toml"
    scenario.write_text(f'mission = "roadmap"\nenv = "{env}"\nagents = 2\nnodes = 40\n'
                        'step = 10\nsensor_range = 20\nseed = 1\n')
    rec = tmp_path / "rec.json"
    args = ["--scenario", str(scenario), "--speed", "inf", "--linger", "15", "--json", str(rec)]
    with monitor_page(args) as (page, errors):
        page.wait_for_function("monitorSnapshot().ended", timeout=30000)
        page.wait_for_timeout(300)
        final = page.evaluate("monitorSnapshot()")
        weight_px = sum(page.evaluate(COLOUR_PIXELS, rgb)  # the three weight colours, exact
                        for rgb in ([100, 181, 246], [25, 118, 210], [13, 71, 161]))
    assert not errors
    record = read_record(rec)
    assert final["travelledEdges"] == record["metrics"]["edges_traversed"] > 0
    # travelled edges are drawn in the weight colours (antialiased lines: their exact colour
    # shows inside the stroke, beside the agents' thinner paths drawn over them)
    assert weight_px > 2 * final["travelledEdges"]


def test_browser_draws_informed_and_carrying_foragers(tmp_path):
    """Live foraging: robots that know where the food is are ringed in gold and carriers
    marked in green while they carry; pixel counts follow the streamed state."""
    scenario = tmp_path / "forage.toml"
    scenario.write_text('mission = "foraging"\ngrid = 8\nagents = 4\nalgorithm = "spiral"\n'
                        'food = "1,1"\nfood_units = 6\nseed = 0\n')
    gold, green = [255, 193, 7], [0, 200, 83]
    with monitor_page(["--scenario", str(scenario), "--speed", "10", "--linger", "15"]) as (
        page, errors,
    ):
        page.wait_for_function(
            "() => monitorSnapshot().agents.some(a => a.carrying)", timeout=60000)
        page.wait_for_timeout(250)
        mid = page.evaluate("monitorSnapshot()")
        mid_gold = page.evaluate(COLOUR_PIXELS, gold)
        mid_green = page.evaluate(COLOUR_PIXELS, green)
        page.wait_for_function("monitorSnapshot().ended", timeout=60000)
        page.wait_for_timeout(400)
        final = page.evaluate("monitorSnapshot()")
        end_green = page.evaluate(COLOUR_PIXELS, green)
    assert not errors
    informed = sum(a["informed"] for a in mid["agents"])
    carrying = sum(a["carrying"] for a in mid["agents"])
    assert informed >= 1 and carrying >= 1
    assert mid_gold > 20 * informed and mid_green > 10 * carrying
    assert all(a["informed"] for a in final["agents"])
    assert not any(a["carrying"] for a in final["agents"]) and end_green == 0


def test_the_address_line_says_what_the_server_does():
    from swarmex.cli.commands_monitor import address_note

    # a scenario runs in this process: it was announced as "waiting for events on /ingest"
    assert address_note(5, wait=True, has_mission=True, connect=None) == (
        "waiting for the first viewer"
    )
    assert address_note(5, wait=False, has_mission=True, connect=None) == "streaming"
    assert address_note(5, wait=True, has_mission=False, connect=None) == (
        "waiting for events on ws://127.0.0.1:5/ingest"
    )
    assert address_note(5, wait=True, has_mission=False, connect="tcp://h:1") == (
        "showing the mission at tcp://h:1"
    )


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ('{"agents": 3}', "'agents' must be a list"),
        ('{"agents": [{"id": 0, "trajectory": [[0, 1]]}]}', "[t, x, y] rows"),
        ('{"agents": [], "makespan": "long"}', "'makespan' must be a number"),
    ],
)
def test_a_json_that_is_not_a_record_is_one_line(tmp_path, capsys, text, needle):
    # these were tracebacks from the summary line or the event builder
    path = tmp_path / "r.json"
    path.write_text(text)
    assert main(["monitor", "--record", str(path), "--no-wait", "--linger", "0"]) == 2
    err = capsys.readouterr().err
    assert needle in err and "not a result record" in err and err.count("\n") == 1
