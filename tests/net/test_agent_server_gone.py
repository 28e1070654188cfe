"""Agents exit when the server goes away (every receive has a timeout).

The server here is a stand-in in this process: it answers the initialisation like ``swarmex
serve`` (C00, C22, C01–C03, GO) and then falls silent, as a crashed server would."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

import numpy as np
import pytest
import zmq

from swarmex.missions.traversal import uniform_agents
from swarmex.net import wire
from swarmex.net.agent import EXIT_SERVER_GONE, run_agents
from swarmex.net.traversal import Mission
from swarmex.worlds import GridWorld

pytestmark = pytest.mark.timeout(60)


def _server_that_dies(sock: zmq.Socket, stop: threading.Event) -> None:
    mission = Mission(GridWorld(np.ones((4, 4), dtype=bool)), uniform_agents([0, 0], 1.0, 1.0))
    while not stop.is_set():
        if not sock.poll(100):
            continue
        ident, frame = sock.recv_multipart()
        msg = wire.decode_message(frame)
        if msg[0] == "C00":
            sock.send_multipart([ident, wire.pack(["ID", 1])])
        elif msg[0] == "C22":
            data = {**mission.to_wire(), "you": 1, "started": False, "clock": 0.0}
            sock.send_multipart([ident, wire.pack(["MIS", data, []])])
        elif msg[0] in ("C01", "C02", "C03"):
            sock.send_multipart([ident, wire.pack(["ACK", msg[0], 1])])
            if msg[0] == "C03":
                sock.send_multipart([ident, wire.pack(["GO", 0.0])])
                return  # and never another word: the agent waits for rival 2, then gives up


@contextlib.contextmanager
def _stand_in(serve) -> Iterator[str]:
    """``serve(sock, stop)`` on a loopback ROUTER in a thread, for the block: its endpoint."""
    sock = zmq.Context.instance().socket(zmq.ROUTER)
    sock.setsockopt(zmq.LINGER, 0)
    sock.bind("tcp://127.0.0.1:*")
    stop = threading.Event()
    server = threading.Thread(target=serve, args=(sock, stop), daemon=True)
    server.start()
    try:
        yield sock.getsockopt_string(zmq.LAST_ENDPOINT)
    finally:
        stop.set()
        server.join(5)
        sock.close(0)


def test_agent_exits_when_the_server_falls_silent():
    said: list[str] = []
    with _stand_in(_server_that_dies) as endpoint:
        code = run_agents(endpoint, 1, server_timeout=1.0, timeout=30, say=said.append)
    assert code == EXIT_SERVER_GONE
    assert any("server went silent" in s for s in said)


def _server_that_keeps_talking(sock: zmq.Socket, stop: threading.Event) -> None:
    """Two agents' initialisation, then a frame to each every 0.1 s (junk they drop, but a
    word from a live server) until ``stop``."""
    import time

    mission = Mission(GridWorld(np.ones((4, 4), dtype=bool)), uniform_agents([0, 0], 1.0, 1.0))
    idents: dict[bytes, int] = {}
    went = False
    next_word = 0.0
    while not stop.is_set():
        if went and time.monotonic() >= next_word:
            next_word = time.monotonic() + 0.1
            for ident in idents:
                sock.send_multipart([ident, b"junk"])
        if not sock.poll(20):
            continue
        ident, frame = sock.recv_multipart()
        msg = wire.decode_message(frame)
        if msg[0] == "C00":
            idents.setdefault(ident, len(idents) + 1)
            sock.send_multipart([ident, wire.pack(["ID", idents[ident]])])
        elif msg[0] == "C22":
            data = {**mission.to_wire(), "you": idents[ident], "started": False, "clock": 0.0}
            sock.send_multipart([ident, wire.pack(["MIS", data, []])])
        elif msg[0] in ("C01", "C02", "C03"):
            sock.send_multipart([ident, wire.pack(["ACK", msg[0], idents[ident]])])
            if msg[0] == "C03" and len(idents) == 2:
                for other in idents:
                    sock.send_multipart([other, wire.pack(["GO", 0.0])])
                went = True


def test_one_agent_busy_with_a_frame_is_not_its_neighbours_silent_server(monkeypatch):
    # agents in one process read their sockets in turn: while one handled a frame for longer
    # than the server timeout (a kernel compiled on a cold cache under CI load), the other's
    # frames waited unread and it declared the live server gone (a red CI run, madgta-s on
    # the wire)
    import time

    from swarmex.net.agent import AgentClient

    slept: list[int] = []
    made: list[AgentClient] = []
    init, on_frame = AgentClient.__init__, AgentClient.on_frame

    def remembered(self, *args, **kwargs):
        init(self, *args, **kwargs)
        made.append(self)

    def slow(self, frame, now):
        on_frame(self, frame, now)
        if self.state == "mission" and not slept and self is made[-1]:
            slept.append(1)
            time.sleep(1.6)  # the server timeout is 1 s

    monkeypatch.setattr(AgentClient, "__init__", remembered)
    monkeypatch.setattr(AgentClient, "on_frame", slow)
    said: list[str] = []
    with _stand_in(_server_that_keeps_talking) as endpoint:
        run_agents(endpoint, 2, server_timeout=1.0, timeout=4, say=said.append,
                   warn=said.append)
    assert slept, said  # the slow frame came mid-mission
    assert not any("went silent" in s for s in said), said
