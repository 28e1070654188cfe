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
from tests.e2e.test_net_traversal import (
    JOINED,
    OBSTACLES,
    Viewer,
    assert_is_the_simulated_run,
    serve,
)
from tests.net.netproc import Procs, endpoint

pytestmark = pytest.mark.timeout(150)


def test_a_waiting_spare_takes_over_from_the_last_agent(tmp_path):
    """With the default --spare-wait 0 the server ended the mission, incomplete, in the very
    pass that declared its last agent gone, and the spare already waiting for an id printed
    "the mission ended without needing a spare" (exit 0). It takes the id now."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 1, "--seed", 3, "--time-scale", 0.03, "--heartbeat", 0.2,
                       "--dead-after", 1.0, record=rec_path)
        address = endpoint(server)
        viewer = Viewer(address)
        victim = procs.start("victim", "agent", "--connect", address, "--id", 1)
        spare = procs.start("spare", "agent", "--connect", address, "--spare",
                            "--connect-timeout", 5, "--server-timeout", 20)
        server.wait_line("mission started", JOINED)
        spare.wait_line(r"waiting for a vacant id \(as long as the mission runs\)", 30)
        viewer.wait_for_jobs((1,), 2, "agent 1 never did two jobs")
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
        server = serve(procs, 2, "--seed", 5, "--time-scale", 0.03, "--heartbeat", 0.2,
                       "--dead-after", 1.0, record=rec_path)
        address = endpoint(server)
        viewer = Viewer(address)
        steady = procs.start("steady", "agent", "--connect", address, "--id", 1)
        victim = procs.start("victim", "agent", "--connect", address, "--id", 2,
                             "--server-timeout", 30)
        server.wait_line("mission started", JOINED)
        viewer.wait_for_jobs((2,), 1, "agent 2 never did a job")
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


def test_an_agent_restarted_before_the_start_gets_its_id_back(tmp_path):
    """An armed agent killed before GO kept its id for a hard-coded 60 s: its restart with
    the same --id was refused at once ("id 1 is taken", exit 4), the dead id counted as
    ready, and GO went out with everybody waiting at its start event. Now the restart asks
    again until the server, after --dead-after of silence, frees the id, and the mission is
    the simulated run."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 2, "--seed", 6, "--time-scale", 0.004, "--heartbeat", 0.2,
                       "--dead-after", 1.0, record=rec_path)
        address = endpoint(server)
        first = procs.start("first", "agent", "--connect", address, "--id", 1)
        server.wait_line("id 1 given to a new agent", JOINED)
        time.sleep(2.0)  # it arms within milliseconds of its id (and waits for id 2)
        first.kill()
        again = procs.start("again", "agent", "--connect", address, "--id", 1,
                            "--connect-timeout", 60)
        other = procs.start("other", "agent", "--connect", address, "--id", 2)
        assert server.wait(90) == 0, server.output
        assert again.wait(15) == 0, again.output
        assert other.wait(15) == 0, other.output
        assert server.output.count("id 1 given to a new agent") == 2, server.output
        assert "a spare took" not in server.output
    net = json.loads(rec_path.read_text())
    assert_is_the_simulated_run(net, 2, seed=6)
