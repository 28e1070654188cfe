"""Agents exit when the server goes away (every receive has a timeout).

The server here is a stand-in in this process: it answers the initialisation like ``swarmex
serve`` (C00, C22, C01–C03, GO) and then falls silent, as a crashed server would."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable, Iterator

import numpy as np
import pytest
import zmq

from swarmex.missions.traversal import uniform_agents
from swarmex.net import wire
from swarmex.net.agent import EXIT_SERVER_GONE, run_agents
from swarmex.net.traversal import Mission
from swarmex.worlds import GridWorld

pytestmark = pytest.mark.timeout(60)


def _two_agent_mission() -> Mission:
    return Mission(GridWorld(np.ones((4, 4), dtype=bool)), uniform_agents([0, 0], 1.0, 1.0))


def _initialise(sock: zmq.Socket, mission: Mission) -> bytes | None:
    """Answer one frame of agent 1's initialisation (C00, C22, C01-C03) as the server does,
    GO after C03: the agent's connection once it has GO, else None."""
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
            return ident
    return None


def _server_that_dies(sock: zmq.Socket, stop: threading.Event) -> None:
    mission = _two_agent_mission()
    while not stop.is_set():
        if sock.poll(100) and _initialise(sock, mission) is not None:
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


@contextlib.contextmanager
def _copter() -> Iterator[tuple]:
    """An emulated copter (100x) on a thread, and the MAVLink vehicle flying it."""
    emulator = pytest.importorskip("swarmex.net.uav_emulator")
    from swarmex.net.agent import open_vehicle
    from swarmex.net.vehicle import Safety

    cfg = emulator.EmulatorConfig(speedup=100.0, timeout=40.0)
    emu = emulator.Emulator("127.0.0.1", 0, cfg, say=lambda s: None)
    thread = threading.Thread(target=emu.run, daemon=True)
    thread.start()
    try:
        safety = Safety(link_timeout=2.0)
        yield emulator, emu, thread, open_vehicle(f"udp:127.0.0.1:{emu.port}", safety), safety
    finally:
        cfg.timeout = 0.0
        thread.join(5)


def test_a_flying_copter_is_brought_down_before_the_agent_leaves_a_silent_server():
    """The server falling silent used to end the agent at once (exit 3) with its copter
    hovering in GUIDED: only the autopilot's GCS failsafe brought it back, and a ground
    station watching through a router keeps that from firing. Now it lands first."""
    said: list[str] = []
    with _copter() as (_emulator, emu, _thread, vehicle, safety):
        with _stand_in(_server_that_dies) as endpoint:
            code = run_agents(endpoint, 1, server_timeout=1.5, timeout=30, say=said.append,
                              vehicle=vehicle, safety=safety, warn=said.append)
        copter = emu.copter
        assert code == EXIT_SERVER_GONE, said
        assert copter.first_takeoff is not None, said  # it flew
        assert not copter.armed and copter.landed, said  # and is down, disarmed
        assert any("the server went silent; vehicle landed" in s for s in said), said


def test_a_copter_a_pilot_took_over_is_left_to_the_pilot():
    """The agent used to answer a pilot's LOITER (or an autopilot's failsafe LAND) with RTL
    0.2 s later, and resend it every second: it took the copter from whoever had it."""
    import time

    from swarmex.net.agent import EXIT_HANDED_BACK

    said: list[str] = []
    modes: list[int] = []
    with _copter() as (emulator, emu, thread, vehicle, safety):

        def pilot() -> None:  # flips the switch once airborne, then watches the mode
            end = time.monotonic() + 20
            while emu.copter.alt < 3.0 and time.monotonic() < end:
                time.sleep(0.01)
            emu.copter.set_mode(emulator.LOITER)
            while time.monotonic() < end and thread.is_alive():
                modes.append(emu.copter.mode)
                time.sleep(0.01)

        threading.Thread(target=pilot, daemon=True).start()
        with _stand_in(_server_that_dies) as endpoint:
            code = run_agents(endpoint, 1, server_timeout=20.0, timeout=30, say=said.append,
                              vehicle=vehicle, safety=safety, warn=said.append)
        assert code == EXIT_HANDED_BACK, said
        assert any("LOITER" in s and "handing id 1 back" in s for s in said), said
        assert any("vehicle left to a pilot (mode LOITER)" in s for s in said), said
        time.sleep(0.3)  # anything the agent sent has arrived
        assert modes and set(modes) == {emulator.LOITER}, set(modes)


def _server_that_ends(last: list, airborne: Callable[[], bool]):
    """A stand-in that initialises one agent of two, starts the mission, and once
    ``airborne()`` sends ``last`` (``END``: its Ctrl-C, SIGTERM or --timeout; ``LEFT`` for
    the agent: it declared it gone), then beats on as a live server would."""
    import time

    def serve(sock: zmq.Socket, stop: threading.Event) -> None:
        mission = _two_agent_mission()
        agent: bytes | None = None
        sent = False
        end = time.monotonic() + 30
        while not stop.is_set() and time.monotonic() < end:
            if agent is not None and not sent and airborne():
                sock.send_multipart([agent, wire.pack(last)])
                sent = True
            if agent is not None and sent:
                sock.send_multipart([agent, wire.pack(["HB", 0.0])])
            if sock.poll(50):
                agent = _initialise(sock, mission) or agent

    return serve


@pytest.mark.parametrize(("last", "code", "why"), [
    (["END"], 1, "the mission ended before I finished"),
    (["LEFT", 1, 3.0], 5, "the server declared me gone"),
], ids=["end", "left-for-me"])
def test_a_flying_copter_is_brought_down_when_the_server_ends_or_drops_the_agent(last, code,
                                                                                  why):
    """END (the server's Ctrl-C, SIGTERM or --timeout) and LEFT for this agent ended a
    vehicle agent at once, its copter hovering in GUIDED until the autopilot's GCS failsafe
    (which a ground station watching through a router keeps from firing): both now land
    it first, as a silent server and the agent's own --timeout do."""
    from swarmex.net.agent import run_agents

    said: list[str] = []
    with _copter() as (_emulator, emu, _thread, vehicle, safety):
        serve = _server_that_ends(last, lambda: emu.copter.alt > 2.0)
        with _stand_in(serve) as endpoint:
            got = run_agents(endpoint, 1, server_timeout=20.0, timeout=30, say=said.append,
                             vehicle=vehicle, safety=safety, warn=said.append)
        copter = emu.copter
        assert got == code, said
        assert copter.first_takeoff is not None, said
        assert not copter.armed and copter.landed, said
        assert any(f"{why}; vehicle landed" in s for s in said), said
