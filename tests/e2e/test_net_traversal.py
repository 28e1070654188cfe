"""``swarmex serve`` / ``swarmex agent`` end to end: real processes on 127.0.0.1.

The server and agents run as subprocesses (port 0: the server binds a free port and prints
it), every wait is bounded, and leftovers are killed in ``finally``. The records are checked
like simulated ones (independent replay against the map), and a fault-free networked run
must *be* the simulated run of the same seed: same paths, same times, same makespan.
"""

from __future__ import annotations

import json
import signal
import threading
import time
from pathlib import Path

import pytest
import zmq

from swarmex.missions.traversal import run_traversal, traversal_record, uniform_agents
from swarmex.net import wire
from swarmex.net.events import viewer_batches
from swarmex.worlds import GridWorld
from tests.e2e.test_cli_traversal import free_mask, replay
from tests.net.netproc import Proc, Procs, endpoint

pytestmark = pytest.mark.timeout(90)

OBSTACLES = [(2, 2), (3, 3), (4, 1)]
GRID = ["--grid", "6x6", "--obstacles", ";".join(f"{x},{y}" for x, y in OBSTACLES)]
#: seconds for every agent to join: each agent process compiles the traversal kernels before
#: it connects (about 20 s of CPU on a cold cache), and two of them share the two cores with
#: the other test worker (30 s was once too short in CI)
JOINED = 120
#: the server's own limit on the whole mission, which must outlast the join
MISSION = JOINED + 60


def _world() -> GridWorld:
    return GridWorld(free_mask(6, 6, OBSTACLES))


def assert_is_the_simulated_run(
    net: dict, agents: int, seed: int, algorithm: str = "madgta"
) -> dict:
    """The networked record ``net`` is the simulated run of ``agents`` agents at cell 0 (same
    seed and algorithm): complete, the same makespan, trajectories and jobs. Returns the
    simulated record."""
    sim_run = run_traversal(_world(), uniform_agents([0] * agents, 2.22, 10.0), algorithm,
                            seed=seed)
    sim = traversal_record(sim_run, {}).to_dict()
    assert net["complete"] and net["makespan"] == sim["makespan"]
    for x, y in zip(net["agents"], sim["agents"], strict=True):
        assert x["trajectory"] == y["trajectory"]
        assert x["jobs"] == y["jobs"]
    return sim


def serve(procs: Procs, agents: int, *flags: object, record: Path | None = None) -> Proc:
    """``swarmex serve`` of the GRID mission to ``agents`` agents, as process "server": a free
    port (see :func:`endpoint`), the MISSION limit, ``flags``, its record to ``record``."""
    json_flag = () if record is None else ("--json", record)
    return procs.start("server", "serve", *GRID, "--agents", agents, "--port", 0,
                       "--timeout", MISSION, *json_flag, *flags)


class Viewer:
    """Collects the server's monitor events on a thread (what ``swarmex watch`` reads)."""

    def __init__(self, address: str) -> None:
        self.events: list[dict] = []
        self.stop = False
        self.thread = threading.Thread(target=self._run, args=(address,), daemon=True)
        self.thread.start()

    def _run(self, address: str) -> None:
        for batch in viewer_batches(address, timeout=30, stop=lambda: self.stop):
            self.events.extend(batch)

    def jobs_of(self, agent: int) -> int:
        return sum(1 for e in list(self.events) if e["type"] == "job" and e["agent"] == agent)

    def wait_for_jobs(self, agents: tuple[int, ...], n: int, what: str) -> None:
        """Wait until ``agents`` have done ``n`` jobs between them; after 30 s fail, ``what``."""
        end = time.monotonic() + 30.0
        while sum(self.jobs_of(a) for a in agents) < n:
            assert time.monotonic() < end, what
            time.sleep(0.05)


def _rogue(address: str) -> None:
    """An intruder: an id outside the mission, a C22 for an id never given, damaged frames
    and garbage — each must be refused or dropped and counted."""
    sock = zmq.Context.instance().socket(zmq.DEALER)
    sock.setsockopt(zmq.LINGER, 0)
    sock.connect(address)
    try:
        sock.send(wire.pack(["C00", 99]))
        assert sock.poll(10_000), "no answer to C00 99"
        assert wire.decode_message(sock.recv())[:1] == ["REF"]
        sock.send(wire.pack(["C22", 2]))
        assert sock.poll(10_000), "no answer to C22 2"
        reply = wire.decode_message(sock.recv())
        assert reply[0] == "REF" and "unknown id" in reply[1]
        good = wire.Broadcast("C05", 1, 3, t=1.0, eta=2.0).frame()
        for bad in (good[:-1] + bytes([good[-1] ^ 1]), good[:7], b"\x00", b"garbage!!!"):
            sock.send(bad)
        sock.send(good)  # well formed, but this connection is not agent 1
    finally:
        sock.close(0)


def test_networked_run_is_the_simulated_run(tmp_path, capsys):
    from swarmex.cli import main

    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 3, "--seed", 7, "--time-scale", 0.004, record=rec_path)
        address = endpoint(server)
        viewer = Viewer(address)
        _rogue(address)
        # `swarmex agent --id 5` on a 3-agent mission: refused, exit 4 (run in this process)
        assert main(["agent", "--connect", address, "--id", "5", "--server-timeout", "5"]) == 4
        assert "refused: unknown id 5" in capsys.readouterr().err  # a failure: stderr
        a = procs.start("agents", "agent", "--connect", address, "--count", 3,
                        "--inject-corrupt", 0.3, "--fault-seed", 1, "--server-timeout", 20)
        assert server.wait(75) == 0, server.output
        assert a.wait(15) == 0, a.output
        viewer.thread.join(10)
    net = json.loads(rec_path.read_text())
    sim = assert_is_the_simulated_run(net, 3, seed=7)
    assert net["time_unit"] == "s" and net["mission"] == "traversal"
    for x, y in zip(net["agents"], sim["agents"], strict=True):
        assert x["metrics"] == y["metrics"]
    same = {k: v for k, v in net["metrics"].items() if k != "message_bytes"}
    assert same == {k: v for k, v in sim["metrics"].items() if k != "message_bytes"}
    replay(net, free_mask(6, 6, OBSTACLES))
    n = net["network"]
    assert n["refused"] == 3  # C00 99, the C22 of an id never given, and --id 5
    assert n["dropped_checksum"] + n["dropped_encoding"] >= 4  # rogue + injected copies
    assert n["dropped_sender"] >= 1
    assert n["stats_received"] == 3 and n["stats_mismatch"] == 0
    assert n["left"] == [] and net["departed_agents"] == []
    # the monitor stream: schema, one job event per job, and the end
    events = viewer.events
    assert events[0]["type"] == "hello" and events[0]["source"] == "network"
    assert events[1]["type"] == "world" and events[1]["cells"][2][2] == "@"
    jobs = sum(len(x["jobs"]) for x in net["agents"])
    assert sum(e["type"] == "job" for e in events) == jobs
    assert events[-1]["type"] == "end" and events[-1]["makespan"] == net["makespan"]
    times = [e["t"] for e in events if "t" in e and e["type"] != "end"]
    assert times == sorted(times)
    # the page's and watch's message count is the record's (status events aside: the page
    # said 131 where the record says 128, its finish events counted)
    from swarmex.net.watch import STATUS_KINDS

    said = [e for e in events if e["type"] == "message" and e["kind"] not in STATUS_KINDS]
    assert len(said) == net["metrics"]["messages"] == events[-1]["messages"]
    assert {e["kind"] for e in events if e["type"] == "message"} & set(STATUS_KINDS)


def _served_like_simulated(tmp_path, algorithm: str) -> dict:
    """``algorithm`` served to three agent processes (seed 4): its record, after checking
    that the run is the simulated one, trajectories, jobs and message count."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 3, "--seed", 4, "--algorithm", algorithm, "--time-scale", 0.002,
                       record=rec_path)
        a = procs.start("agents", "agent", "--connect", endpoint(server), "--count", 3,
                        "--server-timeout", 20)
        assert server.wait(75) == 0, server.output
        assert a.wait(15) == 0, a.output
    net = json.loads(rec_path.read_text())
    sim = assert_is_the_simulated_run(net, 3, seed=4, algorithm=algorithm)
    assert net["metrics"]["messages"] == sim["metrics"]["messages"]
    assert net["network"]["stats_mismatch"] == 0
    return net


def test_a_shared_team_plan_travels_on_the_wire(tmp_path):
    """madgta-s over sockets: its team plans ride on the decisions' frames, and the run is
    the simulated one, message count included (a plan counts as its own message)."""
    net = _served_like_simulated(tmp_path, "madgta-s")
    plain = run_traversal(_world(), uniform_agents([0, 0, 0], 2.22, 10.0), "madgta-f", seed=4)
    assert net["metrics"]["messages"] > plain.messages
    replay(net, free_mask(6, 6, OBSTACLES))


def test_a_leave_travels_on_the_finish(tmp_path):
    """madgta-h over sockets: every finish of its agents says ``leave`` (C09's job bit), and
    the run is the simulated one, the leaves counted as messages as simulated."""
    net = _served_like_simulated(tmp_path, "madgta-h")
    plain = run_traversal(_world(), uniform_agents([0, 0, 0], 2.22, 10.0), "madgta+", seed=4)
    # identical agents: madgta-h is madgta+ with one leave per agent
    assert net["metrics"]["messages"] == plain.messages + 3


def test_killed_agent_is_replaced_by_a_spare(tmp_path):
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 3, "--seed", 2, "--time-scale", 0.04, "--heartbeat", 0.2,
                       "--dead-after", 1.0, record=rec_path)
        address = endpoint(server)
        viewer = Viewer(address)
        # two agents and a spare in one process, the victim alone in another
        # a short --connect-timeout: a spare the server answers waits past it (it used to
        # give up after it, exit 4, and leave the vacated id to nobody)
        pair = procs.start("pair", "agent", "--connect", address, "--count", 2, "--spares", 1,
                           "--connect-timeout", 1)
        victim = procs.start("victim", "agent", "--connect", address, "--id", 3)
        server.wait_line("mission started", JOINED)
        pair.wait_line(r"waiting for a vacant id \(as long as the mission runs\)", 30)
        waiting_since = time.monotonic()
        end = time.monotonic() + 30.0
        while viewer.jobs_of(3) < 2 or time.monotonic() < waiting_since + 2.0:
            assert time.monotonic() < end, "agent 3 never did two jobs"
            time.sleep(0.05)
        victim.popen.send_signal(signal.SIGKILL)
        server.wait_line(r"agent 3 fell silent", 10)
        server.wait_line(r"a spare took id 3", 10)
        assert server.wait(60) == 0, server.output
        assert pair.wait(15) == 0, pair.output
        viewer.stop = True
    net = json.loads(rec_path.read_text())
    assert net["complete"]
    n = net["network"]
    assert [d["id"] for d in n["left"]] == [3] and [d["id"] for d in n["joined"]] == [3]
    assert [d["id"] for d in net["departed_agents"]] == [3]
    assert n["stats_received"] == 3  # the pair and the spare; the victim never landed
    assert [a["metrics"].get("left_at") for a in net["agents"]] == [None, None, None]
    assert net["departed_agents"][0]["metrics"]["left_at"] > 0
    # every free cell done exactly once, counting the departed agent's finished jobs (its
    # unfinished one went back to not-done and was redone by someone else)
    replay({**net, "agents": net["agents"] + net["departed_agents"]}, free_mask(6, 6, OBSTACLES))


@pytest.mark.parametrize(("seed", "says"), [
    ("-1", "--seed must be at least 0, got -1"),
    (str(2**64), f"--seed must be at most {2**64 - 1}"),
])
def test_serve_refuses_a_seed_the_run_or_the_wire_cannot_take(
    seed: str, says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from swarmex.cli import main

    assert main(["serve", "--grid", "4x4", "--agents", "1", "--port", "0", "--seed", seed]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err and "listen" not in err
    assert "optimal," not in err and "nearest, optimal" not in err


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_ctrl_c_on_the_server_writes_the_record_so_far_and_ends_the_agents(tmp_path, sig):
    """Ctrl-C used to end ``serve`` without its record (minutes of flight lost) and without
    ``END``: the agents waited out ``--server-timeout`` and exited 3, "server gone". SIGTERM
    (``kill``, ``timeout``, a service manager) did so until 29 Nov 2026."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 3, "--time-scale", 0.05, "--dead-after", 60, record=rec_path)
        address = endpoint(server)
        viewer = Viewer(address)
        agents = procs.start("agents", "agent", "--connect", address, "--count", 3,
                             "--server-timeout", 30)
        server.wait_line("mission started", JOINED)
        # interrupt once the monitor has shown 4 jobs, or after 20 s of mission in any case
        # (a loaded machine can starve the viewer thread; the record below is what counts:
        # it must hold at least 4 jobs either way)
        end = time.monotonic() + 20.0
        while sum(viewer.jobs_of(a) for a in (1, 2, 3)) < 4 and time.monotonic() < end:
            time.sleep(0.05)
        server.popen.send_signal(sig)
        assert server.wait(10) == 130, server.output
        assert "Traceback" not in server.output
        how = "Ctrl-C" if sig == signal.SIGINT else "SIGTERM"
        server.wait_line(rf"interrupted \({how}\), ending the mission", 1)
        assert agents.wait(10) == 1, agents.output  # "the mission ended before I finished"
        viewer.stop = True
    net = json.loads(rec_path.read_text())
    assert not net["complete"]
    jobs = [(x, y) for a in net["agents"] for _t, x, y in a["jobs"]]
    assert len(jobs) >= 4 and len(jobs) == len(set(jobs)) < 33


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_ctrl_c_on_an_agent_process_hands_its_ids_back(tmp_path, sig):
    """Ctrl-C used to make agents vanish: the server noticed only after --dead-after, and a
    real copter was left hovering in GUIDED mode. Now each agent hands its id back (RET,
    as for a vehicle fault) and lands; the process exits 130."""
    rec_path = tmp_path / "net.json"
    with Procs() as procs:
        server = serve(procs, 3, "--time-scale", 0.02, "--dead-after", 30, "--heartbeat", 0.25,
                       record=rec_path)
        address = endpoint(server)
        viewer = Viewer(address)
        pair = procs.start("pair", "agent", "--connect", address, "--count", 2)
        third = procs.start("third", "agent", "--connect", address, "--id", 3)
        server.wait_line("mission started", JOINED)
        viewer.wait_for_jobs((1, 2), 3, "no jobs done")
        pair.popen.send_signal(sig)
        how = "Ctrl-C" if sig == signal.SIGINT else "SIGTERM"
        assert pair.wait(10) == 130, pair.output
        assert "Traceback" not in pair.output
        pair.wait_line(rf"handing id \d back: interrupted \({how}\)", 1)
        # --dead-after is 30 s: only the hand-back can free the ids this fast
        server.wait_line(r"agent [12] handed its id back", 10)
        assert server.wait(60) == 0, server.output  # agent 3 finishes the mission alone
        assert third.wait(15) == 0, third.output
        viewer.stop = True
    net = json.loads(rec_path.read_text())
    assert net["complete"]
    back = net["network"]["handed_back"]
    assert sorted(h["id"] for h in back) == [1, 2]
    assert {h["reason"] for h in back} == {f"interrupted ({how})"}


def test_an_agent_that_never_got_an_id_says_so(tmp_path):
    """Three agents for a two-agent mission: the third waits for a vacant id, none falls
    vacant, and at END it used to exit 1 with "the mission ended before I finished", as if it
    had failed its work. It never joined: exit 4, refused, saying why."""
    with Procs() as procs:
        server = serve(procs, 2, "--time-scale", 0.004)
        address = endpoint(server)
        trio = procs.start("trio", "agent", "--connect", address, "--count", 3,
                           "--server-timeout", 20)
        assert server.wait(75) == 0, server.output
        assert trio.wait(15) == 4, trio.output
        assert "refused: the mission ended with no vacant id for me" in trio.output
        assert "ended before I finished" not in trio.output


@pytest.mark.parametrize(("algorithm", "says"), [
    ("madgta-f@bogus=1", "madgta-f has no option 'bogus'"),
    ("optimal", "--algorithm must be madgta, madgta+"),
    ("nope", "madgta-s or nearest, got 'nope'"),  # the served list, without optimal
    ("madgta-k@tip_per_agent=-1", "tip_per_agent must be >= 0"),
])
def test_serve_refuses_an_algorithm_it_cannot_serve(
    algorithm: str, says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """A spec's options are checked before the server listens: one line, status 2."""
    from swarmex.cli import main

    assert main(["serve", "--grid", "4x4", "--agents", "1", "--port", "0",
                 "--algorithm", algorithm]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err and "listen" not in err


def test_agent_and_watch_refuse_a_port_out_of_range(capsys: pytest.CaptureFixture[str]) -> None:
    from swarmex.cli import main

    for command in ("agent", "watch"):
        assert main([command, "--connect", "tcp://127.0.0.1:99999"]) == 2
        assert "--connect: expected tcp://HOST:PORT" in capsys.readouterr().err
