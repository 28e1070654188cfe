"""The thesis's future work (seed 000 §1.3, §4.1, §6.2): MADGTA over a lossy, delayed or
limited-range broadcast, kept convergent by the §4.1 done-nodes list.

Everything here is checked against the run's own record, independently of the simulator's
bookkeeping: which vertices must be done comes from labelling the free cells around the nests
(scipy), what was done from the agents' job lists, and whether the agents moved legally from a
replay of their trajectories. The agents' final beliefs are read through a policy that keeps a
reference to the belief it is handed (the public ``run_traversal(..., algorithm=<policy>)``
entry), so nothing private of the simulator is touched for that.

Findings these tests pin down (docs/traversal-variants.md, second section):

* loss (0.3, 0.6), limited range and delays: the mission completes. A delay shorter than one
  edge time used to deadlock a vertex: two agents that announced the same vertex before
  hearing each other both saw it "reserved by the rival" on arrival, both skipped the job and
  could both finish. The arrival rule now keeps an agent's own announcement apart
  (belief.job_on_arrival), and the seeds that failed are kept as a regression test;
* with loss or limited range an agent that finished can miss the very last C07/C08 messages,
  because nothing is broadcast after the last job; one final exchange of done-nodes lists
  (what the §4.2 termination stage, C09 + statistics upload, could carry) makes every belief
  complete.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from swarmex.comm.channel import Channel
from swarmex.missions.traversal import Madgta, run_metrics, run_traversal, uniform_agents
from swarmex.missions.traversal.belief import DONE_BY_UNKNOWN, TraversalBelief
from swarmex.missions.traversal.sim import _encode_done_list, _encode_km, _merge_done_list
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import GridWorld, random_obstacles

TRAVEL, JOB = 2.0, 9.0  # seconds per edge and per job, as in the §3.2.4 example

CHANNELS = {
    "loss0.3": Channel(loss=0.3),
    "loss0.6": Channel(loss=0.6),
    "range3": Channel(range=3.0),
    "delay2": Channel(delay=2.0),
    "delay1": Channel(delay=1.0),
    "loss0.3+range5": Channel(loss=0.3, range=5.0),
    "loss0.3+delay2": Channel(loss=0.3, delay=2.0),
}
LOSSLESS = {
    "perfect": Channel(),
    "delay1": Channel(delay=1.0),
    "delay2": Channel(delay=2.0),
    "delay5": Channel(delay=5.0),
}
SEEDS = range(8)


class RecordingMadgta(Madgta):
    """MADGTA that remembers each agent's belief object, so a test can read it at the end.

    The simulator hands the same belief object to every decision of an agent and keeps
    updating it afterwards (messages still arrive after an agent finished), so the stored
    reference is the agent's final knowledge when the run returns.
    """

    def __init__(self) -> None:
        self.beliefs: dict[int, TraversalBelief] = {}

    def decide(self, belief, rng):
        self.beliefs[belief.me] = belief
        return super().decide(belief, rng)


def scenario(seed: int, size: int = 10, agents: int = 4) -> tuple[GridWorld, list[int]]:
    world = random_obstacles(size, size, 0.2, seed=seed)
    free = np.nonzero(~world.blocked)[0]
    nests = np.random.default_rng(seed).choice(free, agents, replace=False)
    return world, [int(n) for n in nests]


def must_do(world: GridWorld, nests: list[int]) -> np.ndarray:
    """Free cells 4-connected to a nest, by image labelling (independent of the simulator)."""
    labels, _ = ndimage.label(world.free)
    flat = labels.ravel()
    wanted = np.unique(flat[nests])
    return np.isin(flat, wanted[wanted > 0])


def run(seed: int, channel: Channel, policy=None):
    world, nests = scenario(seed)
    policy = policy or RecordingMadgta()
    result = run_traversal(
        world, uniform_agents(nests, TRAVEL, JOB), policy, seed=seed, channel=channel
    )
    return world, nests, result, policy


def jobs_per_vertex(result, n: int) -> np.ndarray:
    counts = np.zeros(n, dtype=np.int64)
    for agent in result.agents:
        for _, v in agent.jobs:
            counts[v] += 1
    return counts


def assert_legal_moves(world: GridWorld, result) -> None:
    for agent in result.agents:
        nodes = [v for _, v in agent.trajectory]
        times = [t for t, _ in agent.trajectory]
        assert times == sorted(times)
        for u, v in zip(nodes, nodes[1:], strict=False):
            assert v in set(world.graph.neighbors(u).tolist()), (agent.id, u, v)
            assert world.free.ravel()[v]


# ----------------------------------------------------------------------------- (1) completion
@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", list(CHANNELS))
def test_mission_completes_over_an_imperfect_channel(name, seed):
    world, nests, result, _ = run(seed, CHANNELS[name])
    todo = must_do(world, nests)
    counts = jobs_per_vertex(result, world.n_nodes)
    assert not result.stopped_early
    assert (counts[todo] >= 1).all(), f"missed {np.nonzero(todo & (counts == 0))[0]}"
    assert (counts[~todo] == 0).all()  # no job on an obstacle or an unreachable cell
    assert result.complete
    assert_legal_moves(world, result)


# the seeds on which a 1 s delay (half an edge) left a vertex undone before the arrival rule
# was fixed (commit ccf3914): two agents announced the same vertex before hearing each other,
# each found it reserved by the other on arrival, both skipped it and both finished
SHORT_DELAY_SEEDS = [6, 16, 18, 25, 28, 29, 35]


@pytest.mark.parametrize("seed", SHORT_DELAY_SEEDS)
@pytest.mark.parametrize("algorithm", ["madgta", "madgta+"])
def test_a_delay_shorter_than_an_edge_no_longer_leaves_a_vertex_undone(algorithm, seed):
    world, nests = scenario(seed)
    result = run_traversal(
        world, uniform_agents(nests, TRAVEL, JOB), algorithm, seed=seed, channel=Channel(delay=1.0)
    )
    counts = jobs_per_vertex(result, world.n_nodes)
    assert (counts[must_do(world, nests)] >= 1).all()
    assert result.complete
    assert_legal_moves(world, result)


# ----------------------------------------------------------------------- (1) knowledge
def final_exchange(beliefs: dict[int, TraversalBelief]) -> None:
    """Every agent broadcasts its §4.1 done-nodes list (KM) once more, and every agent hears
    all."""
    lists = {k: _encode_km(b.status.copy()) for k, b in beliefs.items()}
    for k, b in beliefs.items():
        for j, done_list in lists.items():
            if j != k:
                _merge_done_list(b, done_list)


def assert_sound(world: GridWorld, result, beliefs) -> None:
    """Nothing is believed done that was not: a doer id names an agent that did start it."""
    doers: dict[int, set[int]] = {}
    for agent in result.agents:
        for _, v in agent.jobs:
            doers.setdefault(v, set()).add(agent.id)
    for b in beliefs.values():
        for v in np.nonzero(b.status > 0)[0]:
            k = int(b.status[v])
            if k == DONE_BY_UNKNOWN:
                # the not-done form names no doer; KM's obstacles keep walls out of it
                assert v in doers, v
            else:
                assert k in doers.get(int(v), set()), (v, k)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", list(LOSSLESS))
def test_lossless_channels_converge_without_help(name, seed):
    world, nests, result, policy = run(seed, LOSSLESS[name])
    todo = must_do(world, nests)
    assert len(policy.beliefs) == len(nests)
    for k, b in policy.beliefs.items():
        assert (b.status[todo] > 0).all(), f"agent {k} lacks {np.nonzero(todo & (b.status <= 0))}"
    assert_sound(world, result, policy.beliefs)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", list(CHANNELS))
def test_lossy_channels_converge_after_one_final_done_list_exchange(name, seed):
    world, nests, result, policy = run(seed, CHANNELS[name])
    todo = must_do(world, nests)
    assert_sound(world, result, policy.beliefs)
    final_exchange(policy.beliefs)
    for k, b in policy.beliefs.items():
        assert (b.status[todo] > 0).all(), f"agent {k} lacks {np.nonzero(todo & (b.status <= 0))}"
        # a belief's obstacles are true obstacles; the lists never invent one
        assert world.blocked[b.status == -1].all()
    assert_sound(world, result, policy.beliefs)


def test_without_the_final_exchange_a_finished_agent_lacks_at_most_the_last_few_jobs():
    # Nothing is sent after the last job, so at loss 0.6 a finished agent can miss the last
    # C07/C08 (about 1 agent in 20 over these seeds; docs/traversal-variants.md). The gap is
    # bounded: each missing vertex is one the agent had heard announced (C05) or released.
    # (If the simulator ever broadcasts the list once more at the end, the gaps become 0.)
    gaps = []
    for seed in range(20):
        world, nests, _, policy = run(seed, Channel(loss=0.6))
        todo = must_do(world, nests)
        gaps += [int((todo & (b.status <= 0)).sum()) for b in policy.beliefs.values()]
    assert max(gaps) <= 3


# ------------------------------------------------------------------ (2) the done-nodes list
def belief_for(n: int) -> TraversalBelief:
    world = GridWorld(np.ones((1, n), dtype=bool))
    return TraversalBelief(1, 3, KnownGraph(world.graph), np.ones(4), np.zeros(4))


def test_done_list_holds_done_nodes_below_half():
    status = np.zeros(10, dtype=np.int32)
    status[[1, 4, 7]] = [2, 3, 2]
    status[9] = -1  # an obstacle is neither done nor listed
    bit, idx, doers = _encode_done_list(status)
    assert bit == 1
    assert idx.tolist() == [1, 4, 7]
    assert doers.tolist() == [2, 3, 2]


def test_done_list_flips_to_not_done_nodes_at_half():
    status = np.zeros(10, dtype=np.int32)
    status[:4] = 1
    assert _encode_done_list(status)[0] == 1  # 4 of 10 done: still the done list
    status[4] = 2
    bit, idx, doers = _encode_done_list(status)  # 5 of 10: exactly half flips it
    assert bit == 0
    assert idx.tolist() == [5, 6, 7, 8, 9]
    assert doers.size == 0


@pytest.mark.parametrize("seed", range(40))
def test_done_list_round_trips_and_is_at_most_half_the_graph(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    status = np.zeros(n, dtype=np.int32)
    kind = rng.random(n)
    frac = rng.random()
    status[kind < frac] = rng.integers(1, 4, size=int((kind < frac).sum()))
    status[kind > 0.9] = -1
    sender = status.copy()
    done_list = _encode_done_list(sender)
    bit, idx, _ = done_list
    assert idx.size <= n // 2 + (n % 2)  # §4.1: "at least twice" smaller than the graph
    assert bit == (1 if (sender > 0).sum() * 2 < n else 0)

    receiver = belief_for(n)
    receiver.see_obstacles(np.nonzero(sender == -1)[0])  # it knows the same obstacles
    _merge_done_list(receiver, done_list)
    assert ((receiver.status > 0) == (sender > 0)).all()
    assert ((receiver.status == -1) == (sender == -1)).all()
    if bit == 1:  # the done form names the doers; the not-done form cannot
        assert (receiver.status[sender > 0] == sender[sender > 0]).all()
    else:
        assert (receiver.status[sender > 0] == DONE_BY_UNKNOWN).all()


def test_merging_keeps_what_the_receiver_knows_and_clears_stale_reservations():
    n = 8
    receiver = belief_for(n)
    receiver.see_obstacles([7])
    receiver.mark_done(0, 1)
    receiver.reserve(3, 2)  # agent 2 announced vertex 3 ...
    sender = np.zeros(n, dtype=np.int32)
    sender[[3, 4, 5, 6]] = 3  # ... and the sender knows agent 3 did it (4 of 8: not-done form)
    _merge_done_list(receiver, _encode_done_list(sender))
    assert receiver.status[0] == 1  # the receiver's own knowledge, doer id kept
    assert receiver.status[7] == -1  # a known obstacle is not overwritten
    assert receiver.status[3] > 0 and receiver.reserved[3] == 0
    assert receiver.reservation[2] == -1
    assert (receiver.status[[1, 2]] == 0).all()


# ------------------------------------------------------------------ (3) duplicate jobs
@pytest.mark.parametrize("seed", range(6))
def test_perfect_broadcast_never_duplicates_a_job(seed):
    world, nests, result, _ = run(seed, Channel())
    totals, _ = run_metrics(result, 1.0)
    assert totals["duplicate_jobs"] == 0
    assert (jobs_per_vertex(result, world.n_nodes) <= 1).all()


def test_loss_causes_duplicates_that_are_counted():
    counted, independent = [], []
    for seed in SEEDS:
        world, _, result, _ = run(seed, Channel(loss=0.6))
        totals, _ = run_metrics(result, 1.0)
        counts = jobs_per_vertex(result, world.n_nodes)
        counted.append(totals["duplicate_jobs"])
        independent.append(int(np.maximum(counts - 1, 0).sum()))
    assert counted == independent
    assert sum(counted) > 0  # the channel really was lossy enough to matter


def test_km_list_teaches_walls_a_receiver_never_heard_of():
    """A receiver that missed every obstacle announcement learns the walls from one KM list,
    in both forms (done list, and not-done list once half is done), and never marks a wall
    as a done vertex."""
    world, nests = scenario(3)
    run = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), "madgta", seed=3)
    walls = np.nonzero(~world.free.ravel())[0]
    done = np.zeros(world.n_nodes, dtype=np.int32)
    for agent in run.agents:
        for _, v in agent.jobs:
            done[v] = agent.id
    for fraction in (0.2, 0.9):  # the done form, then the not-done form
        sender = np.where(world.free.ravel(), 0, -1).astype(np.int32)
        jobs = np.nonzero(done)[0]
        keep = jobs[: int(fraction * world.free.sum())]
        sender[keep] = done[keep]
        bit, *_ = km = _encode_km(sender)
        assert bit == (0 if fraction > 0.5 else 1)
        receiver = TraversalBelief(
            1, len(run.agents), KnownGraph(world.graph), np.ones(5), np.zeros(5)
        )
        _merge_done_list(receiver, km)
        assert (receiver.status[walls] == -1).all()
        assert (receiver.status[keep] > 0).all()
        assert ((receiver.status > 0) == (sender > 0)).all()
        assert _encode_done_list(sender)[0] == bit  # the list itself is the thesis's

