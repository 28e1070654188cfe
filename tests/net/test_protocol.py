"""The traversal protocol without sockets: the stream order reproduces the simulator, and
departures and spares keep every participant consistent."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.traversal import run_traversal, uniform_agents
from swarmex.net.traversal import (
    AgentCore,
    Mission,
    Recorder,
    Replica,
    catch_up,
    forget_agent,
    run_inprocess,
)
from swarmex.net.wire import decode_broadcast, decode_message, pack
from swarmex.worlds import GridWorld
from swarmex.worlds.generators import random_obstacles


def _world_and_nests(size: int, density: float, k: int, seed: int):
    world = random_obstacles(size, size, density, seed=seed)
    free = np.nonzero(~world.blocked)[0]
    rng = np.random.default_rng(100 + seed)
    return world, [int(v) for v in rng.choice(free, size=k)]


@pytest.mark.parametrize(
    "size,density,k,seed,kw",
    [
        (6, 0.0, 3, 0, {}),
        (9, 0.2, 4, 1, {}),
        (10, 0.25, 5, 2, {"job_failure": 0.2}),
        (8, 0.15, 3, 3, {"algorithm": "nearest"}),
        (9, 0.2, 4, 6, {"algorithm": "madgta-r"}),
        (9, 0.2, 4, 5, {"algorithm": "madgta-p"}),
        (9, 0.2, 4, 7, {"algorithm": "madgta-k"}),
        (9, 0.2, 4, 8, {"algorithm": "madgta-f"}),
        (9, 0.2, 4, 9, {"algorithm": "madgta-p@ils=5,follow=walls,keep=true"}),
        (9, 0.2, 4, 10, {"algorithm": "madgta-s"}),
        (6, 0.0, 3, 11, {"algorithm": "madgta-s"}),
        (7, 0.1, 2, 4, {"start_interval": 0.0}),
    ],
)
def test_stream_order_reproduces_the_simulator(size, density, k, seed, kw):
    world, nests = _world_and_nests(size, density, k, seed)
    specs = uniform_agents(nests, 2.22, 10.0)
    run = run_traversal(world, specs, kw.get("algorithm", "madgta"), seed,
                        start_interval=kw.get("start_interval", 0.5),
                        job_failure=kw.get("job_failure", 0.0))
    mission = Mission(world, specs, kw.get("algorithm", "madgta"), seed,
                      kw.get("start_interval", 0.5), job_failure=kw.get("job_failure", 0.0))
    cores, recorder = run_inprocess(mission)
    for sim_log, (_, core) in zip(run.agents, sorted(cores.items()), strict=True):
        for log in (core.log, recorder.current[core.me].log):  # the agent's and the server's
            assert log.trajectory == sim_log.trajectory
            assert log.jobs == sim_log.jobs
            assert log.travel_time == sim_log.travel_time
            assert log.job_time == sim_log.job_time
            assert log.failed_jobs == sim_log.failed_jobs
            assert log.nest_job == sim_log.nest_job
            assert log.finished_at == sim_log.finished_at
    assert recorder.messages == run.messages
    assert np.array_equal(recorder.job_count, run.job_count)


def test_own_generators_still_cover_everything():
    world, nests = _world_and_nests(8, 0.2, 3, 5)
    mission = Mission(world, uniform_agents(nests, 1.0, 1.0), seed=5, rng_mode="own")
    _, recorder = run_inprocess(mission)
    assert np.all(recorder.job_count[recorder.reachable()] >= 1)


def _drive(mission, cores, replicas, recorder, stop_when=None, log=None):
    """Relay every step to everybody until nobody has an event (or ``stop_when()``);
    ``log`` collects the stream as the server keeps it for late joiners."""
    server = replicas[0]
    while (a := server.next_agent()) is not None:
        if stop_when is not None and stop_when():
            return
        assert all(r.next_agent() == a for r in replicas[1:])
        key = server.pending[a]
        for b in cores[a].step(key[0], server.rng):
            frame = b.frame()
            if log is not None:
                log.append(frame)
            b = decode_broadcast(frame)
            recorder.on_broadcast(b, 0)
            for r in replicas:
                r.on_broadcast(b)
            for c in cores.values():
                c.receive(b)


def test_departure_reverts_the_open_job_and_the_others_finish():
    world = GridWorld(np.ones((5, 5), dtype=bool))
    mission = Mission(world, uniform_agents([0, 0, 24], 1.0, 5.0), seed=2)
    cores = {i: AgentCore(mission, i) for i in (1, 2, 3)}
    replicas = [Replica(mission) for _ in range(4)]  # the server's, then one per agent
    recorder = Recorder(mission)
    # run until agent 3 is in the middle of a job, then it vanishes
    _drive(mission, cores, replicas, recorder,
           stop_when=lambda: 3 in replicas[0].open_job and len(cores[3].log.jobs) >= 2)
    node = replicas[0].open_job[3]
    for r in replicas:
        r.on_left(3)
    recorder.on_left(3, 99.0, node)
    dead = cores.pop(3)
    for c in cores.values():
        forget_agent(c.belief, 3, node)
        assert c.belief.status[node] == 0 and c.belief.loc[3] == -1
    _drive(mission, cores, replicas, recorder)
    assert np.all(recorder.job_count[recorder.reachable()] == 1)
    assert recorder.current[3].abandoned_jobs[-1][1] == node
    assert dead.log.jobs[-1][1] == node  # it had started the job it never finished


@pytest.mark.parametrize("algorithm", ["madgta", "madgta-s"])
def test_a_spare_replays_the_stream_into_the_same_view_and_finishes_the_work(algorithm):
    """A spare's catch-up gives it the view of the agents that were there all along, the
    newest team plan included (madgta-s)."""
    world = GridWorld(np.ones((5, 5), dtype=bool))
    mission = Mission(world, uniform_agents([0, 12, 24], 1.0, 5.0), algorithm, seed=4)
    cores = {i: AgentCore(mission, i) for i in (1, 2, 3)}
    replicas = [Replica(mission) for _ in range(4)]
    recorder = Recorder(mission)
    log: list[bytes] = []
    _drive(mission, cores, replicas, recorder, log=log,
           stop_when=lambda: len(cores[2].log.jobs) >= 3)
    node = replicas[0].open_job.get(2, -1)
    log.append(pack(["LEFT", 2, 50.0]))
    for r in replicas:
        r.on_left(2)
    recorder.on_left(2, 50.0, node)
    cores.pop(2)
    for c in cores.values():
        forget_agent(c.belief, 2, node)
    t, seq = replicas[0].min_time(), replicas[0].counter
    log.append(pack(["JOIN", 2, t, seq]))
    for r in replicas:
        r.on_join(2, t, seq)
    recorder.on_join(2)
    spare, rep = AgentCore(mission, 2), Replica(mission)
    for frame in log:
        catch_up(spare.belief, rep, decode_message(frame))
    ref = cores[1].belief
    assert rep.pending == replicas[0].pending and rep.counter == replicas[0].counter
    assert rep.rng == replicas[0].rng
    assert np.array_equal(spare.belief.status, ref.status)
    assert np.array_equal(spare.belief.reserved, ref.reserved)
    assert np.array_equal(spare.belief.loc, ref.loc)
    if algorithm == "madgta-s":
        mine, theirs = spare.belief.plan, ref.plan
        assert mine is not None and theirs is not None and mine.t == theirs.t
        assert mine.lens.tolist() == theirs.lens.tolist()
        for a, k in enumerate(theirs.lens.tolist()):
            assert mine.routes[a, :k].tolist() == theirs.routes[a, :k].tolist()
    cores[2] = spare
    replicas.append(rep)
    _drive(mission, cores, replicas, recorder)
    assert np.all(recorder.job_count[recorder.reachable()] == 1)
    assert recorder.departed and recorder.departed[0].log.id == 2
