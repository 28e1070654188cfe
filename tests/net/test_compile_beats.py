"""An agent keeps beating while its algorithm's kernels compile.

On a cold cache madgta-s compiles for ~17 s of CPU once the mission data names it (after
the agent has its id); compiled on the agent's main thread that was 17 s without a
heartbeat, and only the server's long init timeout kept the id. The stand-in server here
answers the initialisation like ``swarmex serve`` and counts the agent's heartbeats between
the mission data and C01; the compile is a stand-in too (a slow ``warm_policy``), so the test
does not depend on what numba has cached. A frame the server sends during the compile must
still be read, after it.
"""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
import zmq

import swarmex.net.agent as agent_module
from swarmex.missions.traversal import uniform_agents
from swarmex.net import wire
from swarmex.net.agent import EXIT_DECLARED_GONE, run_agents
from swarmex.net.traversal import Mission
from swarmex.worlds import GridWorld

pytestmark = pytest.mark.timeout(60)

COMPILE = 1.5  # seconds the stand-in compile takes


def test_an_agent_beats_while_its_kernels_compile(monkeypatch: pytest.MonkeyPatch) -> None:
    compiled: list[str] = []

    def slow_warm_policy(algorithm: str) -> None:
        time.sleep(COMPILE)
        compiled.append(algorithm)

    monkeypatch.setattr(agent_module, "warm_policy", slow_warm_policy)
    monkeypatch.setattr(agent_module, "_WARMING", {})
    mission = Mission(GridWorld(np.ones((4, 4), dtype=bool)), uniform_agents([0], 1.0, 1.0),
                      algorithm="madgta-r")
    seen: list[tuple[float, list]] = []  # (when, message) from the agent
    sock = zmq.Context.instance().socket(zmq.ROUTER)
    sock.setsockopt(zmq.LINGER, 0)
    sock.bind("tcp://127.0.0.1:*")
    stop = threading.Event()

    def serve() -> None:
        while not stop.is_set():
            if not sock.poll(50):
                continue
            ident, frame = sock.recv_multipart()
            msg = wire.decode_message(frame)
            seen.append((time.monotonic(), msg))
            if msg[0] == "C00":
                sock.send_multipart([ident, wire.pack(["ID", 1])])
            elif msg[0] == "C22":
                data = {**mission.to_wire(), "you": 1, "started": False, "clock": 0.0}
                sock.send_multipart([ident, wire.pack(["MIS", data, []])])
                # during the compile: the agent must read it afterwards, not lose it
                sock.send_multipart([ident, wire.pack(["LEFT", 1, 0.0])])
            elif msg[0] == "C01":
                return

    server = threading.Thread(target=serve, daemon=True)
    server.start()
    try:
        said: list[str] = []
        code = run_agents(sock.getsockopt_string(zmq.LAST_ENDPOINT), 1, server_timeout=5.0,
                          timeout=30, say=said.append)
    finally:
        stop.set()
        server.join(5)
        sock.close(0)
    assert compiled == ["madgta-r"]
    asked = next(t for t, m in seen if m[0] == "C22")
    c01 = next(t for t, m in seen if m[0] == "C01")
    assert c01 - asked >= COMPILE  # C01 only once the kernels are ready
    beats = [t for t, m in seen if m[0] == "HB" and asked < t < c01]
    # one every 0.25 s (the mission's heartbeat): 6 in 1.5 s; the main thread beat none
    assert len(beats) >= 4, beats
    assert max(np.diff([asked, *beats, c01])) < 0.6
    # the LEFT sent during the compile was read after it: the agent knows it is gone
    assert code == EXIT_DECLARED_GONE, said


def test_one_compile_per_algorithm_and_process(monkeypatch: pytest.MonkeyPatch) -> None:
    """Agents sharing a process (``--count``) share the compile of their algorithm."""
    calls: list[str] = []
    monkeypatch.setattr(agent_module, "warm_policy", lambda a: calls.append(a))
    monkeypatch.setattr(agent_module, "_WARMING", {})
    first = agent_module.warm_in_background("madgta-p")
    assert agent_module.warm_in_background("madgta-p") is first
    first.result(timeout=5)
    assert calls == ["madgta-p"]
    assert agent_module.warm_in_background("madgta").done()  # warm_up did it already
    assert calls == ["madgta-p"]


def test_a_failed_compile_ends_the_agent_with_its_error(monkeypatch: pytest.MonkeyPatch) -> None:
    """An error while compiling is not swallowed by the thread."""
    def broken(algorithm: str) -> None:
        raise RuntimeError("no LLVM today")

    monkeypatch.setattr(agent_module, "warm_policy", broken)
    monkeypatch.setattr(agent_module, "_WARMING", {})
    with pytest.raises(RuntimeError, match="no LLVM today"):
        agent_module.warm_in_background("madgta-k").result(timeout=5)
