"""``madgta+`` (swarmex.missions.traversal.variants): correct, decentralised, not worse.

* Correctness is checked from the run's record alone: what had to be done comes from
  labelling the free cells around the nests, what was done from the job lists, and the moves
  are replayed against the map.
* Decentralisation: the policy is handed a read-only proxy of the agent's belief that logs
  every attribute it touches, inside a full simulation. It must use only belief attributes,
  must write nothing, and must give the same answer on a deep copy of the belief. The module
  must not import the simulator or the world.
* Quality: over seeds, on a fixed generated map where the effect is robust, the mean
  makespan is no worse than MADGTA's (docs/traversal-variants.md has the full comparison on
  the real maps).
"""

from __future__ import annotations

import ast
import inspect

import numpy as np
import pytest
from scipy import ndimage

from swarmex.missions.traversal import (
    Madgta,
    make_policy,
    run_metrics,
    run_traversal,
    uniform_agents,
    variants,
)
from swarmex.missions.traversal.policies import POLICIES
from swarmex.missions.traversal.variants import MadgtaPlus
from swarmex.worlds import GridWorld, random_obstacles, rooms

from .checking import BELIEF_API, spying

TRAVEL, JOB = 2.0, 9.0


def nests_in(world: GridWorld, agents: int, seed: int, shared: bool) -> list[int]:
    free = np.nonzero(~world.blocked)[0]
    rng = np.random.default_rng(seed)
    if shared:
        return [int(rng.choice(free))] * agents
    return [int(v) for v in rng.choice(free, agents, replace=False)]


def must_do(world: GridWorld, nests: list[int]) -> np.ndarray:
    labels, _ = ndimage.label(world.free)
    flat = labels.ravel()
    wanted = np.unique(flat[nests])
    return np.isin(flat, wanted[wanted > 0])


def test_registered_under_its_name():
    assert POLICIES["madgta+"] is MadgtaPlus
    policy = make_policy("madgta+")
    assert isinstance(policy, MadgtaPlus) and isinstance(policy, Madgta)
    assert policy.name == "madgta+"


def test_bad_claim_radius_is_rejected():
    with pytest.raises(ValueError, match="claim_radius"):
        MadgtaPlus(claim_radius=-1)


# --------------------------------------------------------------------------- correctness
@pytest.mark.parametrize("seed", range(24))
def test_completes_with_each_job_once_and_legal_moves(seed):
    rng = np.random.default_rng(seed)
    size = int(rng.integers(6, 14))
    world = random_obstacles(size, size, float(rng.uniform(0.0, 0.3)), seed=seed)
    agents = int(rng.integers(2, 7))
    nests = nests_in(world, min(agents, world.free_cells), seed, shared=seed % 3 == 0)
    run = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), "madgta+", seed=seed)
    assert run.algorithm == "madgta+"

    todo = must_do(world, nests)
    counts = np.zeros(world.n_nodes, dtype=np.int64)
    for agent in run.agents:
        for _, v in agent.jobs:
            counts[v] += 1
    assert (counts[todo] == 1).all()  # every reachable free cell exactly once
    assert (counts[~todo] == 0).all()
    assert run.complete
    assert run_metrics(run, 1.0)[0]["duplicate_jobs"] == 0

    neighbours = world.graph.neighbors
    for agent in run.agents:
        nodes = [v for _, v in agent.trajectory]
        times = [t for t, _ in agent.trajectory]
        assert times == sorted(times)
        assert nodes[0] == nests[agent.id - 1]
        for u, v in zip(nodes, nodes[1:], strict=False):
            assert v in set(neighbours(u).tolist())
            assert world.free.ravel()[v]
        # a job is done where the agent stands, at a time it is there
        held = {(round(t, 9), v) for t, v in agent.trajectory}
        assert all((round(t, 9), v) in held for t, v in agent.jobs)


def test_is_deterministic_for_a_seed():
    world = rooms(20, 20, seed=3)
    nests = nests_in(world, 5, 3, shared=False)
    a = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), "madgta+", seed=11)
    b = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), "madgta+", seed=11)
    assert a.path_strings() == b.path_strings()


def test_single_agent_falls_back_to_nearest_first():
    world = random_obstacles(9, 9, 0.2, seed=1)
    nests = nests_in(world, 1, 1, shared=True)
    run = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), "madgta+", seed=0)
    assert run.complete


# ------------------------------------------------------------------------ decentralisation
def test_reads_only_the_belief_and_never_writes_it():
    world = random_obstacles(14, 14, 0.2, seed=5)
    nests = nests_in(world, 5, 5, shared=False)
    spy = spying(MadgtaPlus, limit=200)
    run = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), spy, seed=5)
    assert run.complete
    assert spy.checked > 50
    assert spy.seen <= BELIEF_API, spy.seen - BELIEF_API
    # it really uses the rival state that C05/C07 carry
    assert {"next_loc", "free_at", "now"} <= spy.seen


def test_module_does_not_import_the_simulator_or_the_world():
    tree = ast.parse(inspect.getsource(variants))
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            imported.add(node.module)
        elif isinstance(node, ast.Import):
            imported.update(alias.name for alias in node.names)
    forbidden = {"swarmex.missions.traversal.sim", "swarmex.worlds", "swarmex.comm"}
    assert not any(m == f or m.startswith(f + ".") for m in imported for f in forbidden)


# ------------------------------------------------------------------------------- quality
def makespans(algorithm: str, world: GridWorld, agents: int, seeds, shared: bool) -> np.ndarray:
    out = []
    for s in seeds:
        nests = nests_in(world, agents, 100 + s, shared=shared)
        run = run_traversal(world, uniform_agents(nests, TRAVEL, JOB), algorithm, seed=s)
        assert run.complete
        out.append(run_metrics(run, 1.0)[0]["max_total_time"])
    return np.array(out)


@pytest.mark.parametrize("shared", [True, False], ids=["shared-nest", "own-nests"])
def test_no_worse_than_madgta_on_average(shared):
    # A crowded map (16 agents on ~800 free cells) is where the end-game waste that madgta+
    # removes is largest: there it is 1-2 % faster on average (6 of 8 seeds better). Paired
    # runs (same nests, same seed); the 0.5 % tolerance keeps the check about the direction,
    # not the exact figure, which moves with any change of tie-breaking upstream.
    world = random_obstacles(32, 32, 0.2, seed=8)
    seeds = range(8)
    base = makespans("madgta", world, 16, seeds, shared=shared)
    plus = makespans("madgta+", world, 16, seeds, shared=shared)
    assert plus.mean() <= 1.005 * base.mean(), (plus.mean(), base.mean())
    assert (plus < base).sum() >= len(seeds) // 2
