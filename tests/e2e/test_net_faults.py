"""``swarmex serve`` / ``swarmex agent`` faults end to end: real processes on 127.0.0.1.

As in test_net_traversal.py, the server binds a free port and prints it, every wait is
bounded, and leftovers are killed (by their own pid) when a test ends.
"""

from __future__ import annotations

import json
import signal
import time

import pytest

from tests.e2e.test_cli_traversal import free_mask, replay
from tests.e2e.test_net_traversal import GRID, JOINED, MISSION, OBSTACLES, Viewer
from tests.net.netproc import Procs, endpoint

pytestmark = pytest.mark.timeout(150)


def test_a_waiting_spare_takes_over_from_the_last_agent(tmp_path):
    """With the default --spare-wait 0 the server ended the mission, incomplete, in the very
    pass that declared its last agent gone, and the spare already waiting for an id printed
    "the mission ended without needing a spare" (exit 0). It takes the id now."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = procs.start(
            "server", "serve", *GRID, "--agents", 1, "--seed", 3, "--port", 0,
            "--time-scale", 0.03, "--heartbeat", 0.2, "--dead-after", 1.0,
            "--timeout", MISSION, "--json", rec_path,
        )
        address = endpoint(server)
        viewer = Viewer(address)
        victim = procs.start("victim", "agent", "--connect", address, "--id", 1)
        spare = procs.start("spare", "agent", "--connect", address, "--spare",
                            "--connect-timeout", 1, "--server-timeout", 20)
        server.wait_line("mission started", JOINED)
        spare.wait_line(r"waiting for a vacant id \(as long as the mission runs\)", 30)
        end = time.monotonic() + 30.0
        while viewer.jobs_of(1) < 2:
            assert time.monotonic() < end, "agent 1 never did two jobs"
            time.sleep(0.05)
        victim.popen.send_signal(signal.SIGKILL)
        server.wait_line(r"agent 1 fell silent", 10)
        server.wait_line(r"a spare took id 1", 10)
        assert server.wait(60) == 0, server.output
        assert spare.wait(15) == 0, spare.output
        assert "without needing a spare" not in spare.output
        viewer.stop = True
    net = json.loads(rec_path.read_text())
    assert net["complete"]
    n = net["network"]
    assert [d["id"] for d in n["left"]] == [1] and [d["id"] for d in n["joined"]] == [1]
    replay({**net, "agents": net["agents"] + net["departed_agents"]}, free_mask(6, 6, OBSTACLES))


def test_an_agent_declared_gone_is_told_and_exits_5(tmp_path):
    """The server forgot an agent it declared gone before relaying LEFT, so the agent never
    heard it: after a pause longer than --dead-after it flew its plan on, its frames
    dropped, until its server timeout (exit 3) or the end (exit 1). Status 5, "declared
    gone", could not happen."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = procs.start(
            "server", "serve", *GRID, "--agents", 2, "--seed", 5, "--port", 0,
            "--time-scale", 0.03, "--heartbeat", 0.2, "--dead-after", 1.0,
            "--timeout", MISSION, "--json", rec_path,
        )
        address = endpoint(server)
        viewer = Viewer(address)
        steady = procs.start("steady", "agent", "--connect", address, "--id", 1)
        victim = procs.start("victim", "agent", "--connect", address, "--id", 2,
                             "--server-timeout", 30)
        server.wait_line("mission started", JOINED)
        end = time.monotonic() + 30.0
        while viewer.jobs_of(2) < 1:
            assert time.monotonic() < end, "agent 2 never did a job"
            time.sleep(0.05)
        victim.popen.send_signal(signal.SIGSTOP)
        try:
            server.wait_line(r"agent 2 fell silent", 10)
        finally:
            victim.popen.send_signal(signal.SIGCONT)
        assert victim.wait(10) == 5, victim.output
        assert "the server declared me gone" in victim.output
        assert server.wait(60) == 0, server.output  # agent 1 finishes alone
        assert steady.wait(15) == 0, steady.output
        viewer.stop = True
    net = json.loads(rec_path.read_text())
    assert net["complete"] and [d["id"] for d in net["network"]["left"]] == [2]
