"""The networked runtime feeds the web monitor (``swarmex.viz.monitor``) without changes:
through :func:`~swarmex.net.events.network_producer` (a ``monitor --connect`` producer) and
through :class:`~swarmex.net.events.IngestForwarder` (``serve --monitor ws://…/ingest``)."""

from __future__ import annotations

import asyncio
import json
import threading
import time
import urllib.request

import pytest
import zmq

from swarmex.net import events as ev
from swarmex.net import wire

pytest.importorskip("websockets")
monitor_server = pytest.importorskip("swarmex.viz.monitor.server")
from websockets.sync.client import connect  # noqa: E402

pytestmark = pytest.mark.timeout(60)

FEED = [
    ev.hello("traversal", "madgta", [1, 2], "traversal · test", None),
    ev.world(None, 3, 2, "grid 3x2"),
    ev.move(0.0, 1, 0.0, 0.0),
    ev.job(0.0, 1, 0.0, 0.0),
    ev.message(0.0, 1, "job", 0.0, 0.0),
    {"type": "end", "t": 1.0, "complete": True, "makespan": 1.0, "time_unit": "s",
     "metrics": {}, "agents": []},
]


class FakeMissionServer:
    """What ``swarmex serve`` does for viewers: MON in, the event history out as EV frames."""

    def __init__(self, bind: str = "tcp://127.0.0.1:*", feed: list | None = None) -> None:
        self.feed = FEED if feed is None else feed
        self.sock = zmq.Context.instance().socket(zmq.ROUTER)
        self.sock.setsockopt(zmq.LINGER, 0)
        self.sock.bind(bind)
        self.address = self.sock.getsockopt_string(zmq.LAST_ENDPOINT)
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            if self.sock.poll(100):
                ident, frame = self.sock.recv_multipart()
                if wire.unpack(frame) == ["MON"]:
                    self.sock.send_multipart([ident, wire.pack(["EV", ev.dumps(self.feed[:3])])])
                    if self.feed[3:]:
                        self.sock.send_multipart(
                            [ident, wire.pack(["EV", ev.dumps(self.feed[3:])])])
                    return


def _monitor(producer=None):
    server = monitor_server.MonitorServer(0, None)
    thread = threading.Thread(target=lambda: asyncio.run(server.run(producer, 0.5)),
                              daemon=True)
    thread.start()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            urllib.request.urlopen(server.url, timeout=1).read()
            return server, thread
        except OSError:
            time.sleep(0.05)
    raise AssertionError("the monitor did not start")


def _receive(port: int) -> list[dict]:
    got: list[dict] = []
    with connect(f"ws://127.0.0.1:{port}/ws", open_timeout=5) as viewer:
        while not got or got[-1]["type"] != "end":
            got += json.loads(viewer.recv(timeout=10))
    return got


def test_monitor_connect_producer_relays_a_live_mission():
    fake = FakeMissionServer()
    server, thread = _monitor(ev.network_producer(fake.address, timeout=10))
    try:
        assert _receive(server.port) == json.loads(ev.dumps(FEED))
    finally:
        server.stop()
        thread.join(10)
        fake.sock.close(0)


def test_ingest_forwarder_feeds_the_page():
    server, thread = _monitor()
    try:
        fwd = ev.IngestForwarder(f"ws://127.0.0.1:{server.port}/ingest")
        results: list[list[dict]] = []
        viewer = threading.Thread(target=lambda: results.append(_receive(server.port)))
        viewer.start()
        time.sleep(0.3)
        fwd.send(FEED[:2])
        fwd.send(FEED[2:])
        fwd.close()
        viewer.join(15)
        assert fwd.sent == 2 and fwd.dropped == 0
        assert results and results[0] == json.loads(ev.dumps(FEED))
    finally:
        server.stop()
        thread.join(10)


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_monitor_started_before_its_mission_waits_for_it():
    """``monitor --connect`` gave up after 10 s without a word when the server was not up
    yet (the usual start order), and then showed an empty page for ever."""
    address = f"tcp://127.0.0.1:{_free_port()}"
    said: list[str] = []
    server, thread = _monitor(ev.network_producer(address, timeout=0.5, say=said.append))
    fake = None
    try:
        time.sleep(1.5)  # three times the silence that ends a mission's stream
        fake = FakeMissionServer(address)
        assert _receive(server.port) == json.loads(ev.dumps(FEED))
        assert said == [f"swarmex monitor: receiving the mission at {address}"]
    finally:
        server.stop()
        thread.join(10)
        if fake is not None:
            fake.sock.close(0)


def test_a_mission_that_falls_silent_is_reported_and_ends_the_wait():
    fake = FakeMissionServer(feed=FEED[:3])  # no end event: the server died
    said: list[str] = []
    lost = threading.Event()
    server, thread = _monitor(ev.network_producer(fake.address, timeout=0.5, say=said.append,
                                                  on_lost=lost.set))
    try:
        assert lost.wait(10)
        assert said[-1] == (f"swarmex monitor: the mission at {fake.address} fell silent before"
                            " its end (nothing for 0.5 s); the page keeps what it showed")
    finally:
        server.stop()
        thread.join(10)
        fake.sock.close(0)


def test_events_that_reach_no_monitor_are_said():
    """``serve --monitor`` and ``watch --forward`` to a monitor that is not there threw the
    events away without a word (``watch`` even exited 0)."""
    url = f"ws://127.0.0.1:{_free_port()}/ingest"
    warned: list[str] = []
    fwd = ev.IngestForwarder(url, connect_timeout=0.3, warn=warned.append)
    fwd.send(FEED[:2])
    fwd.send(FEED[2:])
    time.sleep(0.6)
    fwd.close()
    assert len(warned) == 1 and warned[0].startswith(
        f"swarmex: the monitor at {url} is unreachable (")
    assert fwd.sent == 0 and fwd.shortfall().startswith(
        f"2 of 2 event batches did not reach the monitor at {url} (")


def test_watch_forwarding_to_no_monitor_fails(capfd):
    from swarmex.cli import main

    fake = FakeMissionServer()
    try:
        code = main(["watch", "--connect", fake.address, "--forward",
                     f"ws://127.0.0.1:{_free_port()}/ingest", "--timeout", "5"])
    finally:
        fake.sock.close(0)
    err = capfd.readouterr().err
    assert code == 1 and "is unreachable" in err and "did not reach the monitor" in err
