"""Agents exit when the server goes away (every receive has a timeout).

The server here is a stand-in in this process: it answers the initialisation like ``swarmex
serve`` (C00, C22, C01–C03, GO) and then falls silent, as a crashed server would."""

from __future__ import annotations

import threading

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


def test_agent_exits_when_the_server_falls_silent():
    sock = zmq.Context.instance().socket(zmq.ROUTER)
    sock.setsockopt(zmq.LINGER, 0)
    sock.bind("tcp://127.0.0.1:*")
    stop = threading.Event()
    server = threading.Thread(target=_server_that_dies, args=(sock, stop), daemon=True)
    server.start()
    said: list[str] = []
    try:
        code = run_agents(sock.getsockopt_string(zmq.LAST_ENDPOINT), 1, server_timeout=1.0,
                          timeout=30, say=said.append)
    finally:
        stop.set()
        server.join(5)
        sock.close(0)
    assert code == EXIT_SERVER_GONE
    assert any("server went silent" in s for s in said)
