"""Bit-exact fingerprints of traversal runs, so a speed-up can never change a result.

The hashes below were computed from the simulation *before* the performance work on distance
fields, the field cache and the policy loop; the cases changed by the arrival rule (commit
ccf3914) were regenerated then and cross-checked against the pre-optimisation code with that
rule applied, which gives the same hashes. Each case's result record (``wall_seconds`` and
``swarmex_version`` dropped: they are not behaviour) plus the thesis-style paths, decision
branch counts and first doer per vertex are serialised as canonical JSON and hashed. Any
change in a decision, a tie-break draw, a timing or a metric changes the hash.

If a change of *semantics* is intended (or the record gains a field), regenerate with
``python tests/missions/traversal/test_regression_fingerprint.py`` and say why in the commit.
"""

from __future__ import annotations

from collections.abc import Callable

import networkx as nx
import numpy as np
import pytest

from swarmex.comm import Channel
from swarmex.missions.traversal import (
    AgentSpec,
    run_traversal,
    uniform_agents,
)
from swarmex.missions.traversal.metrics import run_fingerprint as fingerprint
from swarmex.missions.traversal.sim import TraversalRun
from swarmex.worlds import GraphWorld, GridWorld
from swarmex.worlds.generators import random_obstacles, rooms

try:  # a plain script run (regeneration) has no package parent
    from .thesis_grid import thesis_grid, tid_to_node
except ImportError:  # pragma: no cover
    from thesis_grid import thesis_grid, tid_to_node  # type: ignore[no-redef]


def _nests(world, k: int, seed: int) -> list[int]:
    free = np.nonzero(~world.blocked)[0]
    rng = np.random.default_rng(1000 + seed)
    return [int(v) for v in rng.choice(free, size=k, replace=True)]


def _worked(seed: int) -> TraversalRun:
    world = thesis_grid(5, 5, obstacles=(3, 13, 14, 19))
    nests = [tid_to_node(k, 5, 5) for k in (1, 11, 23)]
    return run_traversal(world, uniform_agents(nests, 2.0, 9.0), seed=seed)


def _random(size: int, density: float, agents: int, seed: int, **kw) -> TraversalRun:
    world = random_obstacles(size, size, density, seed=seed)
    return run_traversal(
        world, uniform_agents(_nests(world, agents, seed), 1.0, 1.0), seed=seed, **kw
    )


def _shared_nest(size: int, agents: int, seed: int) -> TraversalRun:
    world = random_obstacles(size, size, 0.25, seed=seed)
    free = np.nonzero(~world.blocked)[0]
    nest = int(free[free.size // 2])
    return run_traversal(world, uniform_agents([nest] * agents, 1.0, 1.0), seed=seed)


def _lossy() -> TraversalRun:
    world = random_obstacles(20, 20, 0.2, seed=3)
    return run_traversal(
        world, uniform_agents(_nests(world, 4, 3), 1.0, 2.0), seed=3, channel=Channel(loss=0.2)
    )


def _delayed_ranged() -> TraversalRun:
    world = random_obstacles(16, 16, 0.2, seed=4)
    return run_traversal(
        world,
        uniform_agents(_nests(world, 4, 4), 1.0, 1.0),
        seed=4,
        channel=Channel(loss=0.1, delay=0.3, range=6.0),
    )


def _eight_connected() -> TraversalRun:
    base = random_obstacles(20, 20, 0.2, seed=5)
    world = GridWorld(base.free, connectivity=8, source="random 20x20 8-conn")
    return run_traversal(world, uniform_agents(_nests(world, 5, 5), 1.0, 1.0), seed=5)


def _heterogeneous() -> TraversalRun:
    world = rooms(27, 27, room=8, door=2, seed=6)
    nests = _nests(world, 4, 6)
    specs = [
        AgentSpec(nests[0], 1.0, 1.0),
        AgentSpec(nests[1], 1.7, 0.5, altitude=3.0, up_speed=1.5, down_speed=0.3),
        AgentSpec(nests[2], 0.6, 2.5),
        AgentSpec(nests[3], 1.3, 0.0),
    ]
    return run_traversal(world, specs, seed=6, start_interval=0.5, job_failure=0.1)


def _weighted_graph() -> TraversalRun:
    g = nx.connected_watts_strogatz_graph(60, 4, 0.2, seed=7)
    rng = np.random.default_rng(7)
    for a, b in g.edges:
        g.edges[a, b]["weight"] = float(rng.integers(1, 5)) * 0.5
    # obstacles include a cut-off pocket: vertex 59 is reachable only through obstacles
    g.add_edges_from([(59, 60), (60, 61)], weight=1.0)
    world = GraphWorld(g, obstacles=[3, 17, 29, 44, 59])
    return run_traversal(world, uniform_agents([0, 0, 30, 45], 1.0, 1.5), seed=7)


def _nearest() -> TraversalRun:
    world = random_obstacles(20, 20, 0.25, seed=8)
    return run_traversal(
        world, uniform_agents(_nests(world, 4, 8), 1.0, 1.0), algorithm="nearest", seed=8
    )


CASES: dict[str, Callable[[], TraversalRun]] = {
    **{f"worked-seed{s}": (lambda s=s: _worked(s)) for s in range(10)},
    "random20-3a-s0": lambda: _random(20, 0.2, 3, 0),
    "random20-5a-s1": lambda: _random(20, 0.3, 5, 1),
    "random20-8a-s2": lambda: _random(20, 0.2, 8, 2),
    "random40-4a-s0": lambda: _random(40, 0.25, 4, 0),
    "random40-8a-s1": lambda: _random(40, 0.2, 8, 1),
    "random40-6a-s2-sync": lambda: _random(40, 0.3, 6, 2, start_interval=0.0),
    "shared-nest30-6a": lambda: _shared_nest(30, 6, 9),
    "lossy-0.2": _lossy,
    "lossy-delay-range": _delayed_ranged,
    "eight-connected": _eight_connected,
    "hetero-rooms-failures": _heterogeneous,
    "weighted-graph": _weighted_graph,
    "nearest": _nearest,
}

EXPECTED: dict[str, str] = {
    "worked-seed0": "6630e04a8e530905db7fac0ca481047bc2af257ac3dfad8ab80fe9cce6e189b7",
    "worked-seed1": "b501f8905609da18518725061f3098ec6eefa6390a719d01354f60cdce82b570",
    "worked-seed2": "29979af0cc422051182f97c9fb8e16ba7d1f00421a1059fb98db4014383462f6",
    "worked-seed3": "99da6cb6bf143eb7f1c76b59e784f0da6859f046e50c19e8f35d7cac3f0bb5d6",
    "worked-seed4": "7233c94bd7319318524a30fbd5a4dd9035d9a85b9b2df50b566094f7b338288e",
    "worked-seed5": "62968f690dc1719f9964b3ceb9a182e4c82a056e78058d33a22e12e13359f4ca",
    "worked-seed6": "36ffde7e1d225623c84c0482b722668d6b85b1a93d37d531b1dec32da69179c4",
    "worked-seed7": "b8d452961f4d924e1bedf883df272d352647af97f4e1e6981e7fcc421a405cf0",
    "worked-seed8": "f31e000c38453ff8b2d6ceb117e60f0eca0ede63767c2344a841b2cca5ba05d5",
    "worked-seed9": "2b80f012d4d60266a194a5bbded1f5867ccce02201cc137eb5ed9ad0496c0b9e",
    "random20-3a-s0": "ae25ba7f58ab04cc1a98138ae5d839eb77f7b6c01f8a2a928158f3f56e9bc812",
    "random20-5a-s1": "b370acd1cb34d42545afbc0bea8017217f07f97d57001a16b12e42097430cacb",
    "random20-8a-s2": "dcf89927a733cbdb95425b8630a5a8812a694510f13cc7d0dbb61cc24846d952",
    "random40-4a-s0": "2cc7cab220b7eefe973beaff86039d10de68d3c9516c56c062f4f6ad7b92e44c",
    "random40-8a-s1": "acef7eae9fba527e0e5e977668de7a9a5f698f367c5c1f9cd75218788af479e0",
    "random40-6a-s2-sync": "df31ab1ae74dbbfa19c4143b1951314ff9c32fe942154cdc406253e699014d6a",
    "shared-nest30-6a": "0b83e906e843428a2415e6b1e0c0ce9ed7ea553e627f1956857e2f4abeca3318",
    "lossy-0.2": "eea9899eb8618978f8ca57280e8099801a73b0379c64af28498c7f8e3f839499",
    "lossy-delay-range": "9c4a37b93928744eff35f63ee4d645a55d43fd0bd8caadcbbc0bb3d0e6170879",
    "eight-connected": "e08232255f03d760a5de20dcadc82536457e491d1a27ffd06e94a55c08f8c129",
    "hetero-rooms-failures": "4138a9ce7ca305e7378f3c06487f4fd38e81c35e2e60a2f8762ceb7ad4afac27",
    "weighted-graph": "b5ec3ac7877d9f89e64f864fda00fc5272375274eeca7cd7b295c5e78cfec644",
    "nearest": "8bb6fc02d8f87bb133674817b1b3e6e8c7d47602c50aa2247aeead7a9eda45d8",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_fingerprint_unchanged(name: str) -> None:
    assert fingerprint(CASES[name]()) == EXPECTED[name]


@pytest.mark.parametrize("name", ["random40-8a-s1", "shared-nest30-6a", "hetero-rooms-failures"])
def test_fingerprint_unchanged_with_background_fields(name: str, monkeypatch) -> None:
    """Fields derived on the worker thread (sim.PREFETCH_FIELDS) give the same runs."""
    from swarmex.missions.traversal import sim
    from swarmex.planning import fieldcache

    monkeypatch.setattr(sim, "PREFETCH_FIELDS", True)
    monkeypatch.setattr(fieldcache, "PREFETCH_MIN_NODES", 0)  # even on small maps
    assert fingerprint(CASES[name]()) == EXPECTED[name]


if __name__ == "__main__":  # regenerate EXPECTED
    for key in CASES:
        print(f'    "{key}": "{fingerprint(CASES[key]())}",')
