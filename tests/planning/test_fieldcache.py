"""KnownGraph stays exact while obstacles are discovered (property tests).

Every answer of the cache is compared with an independent computation (scipy's Dijkstra
on the graph minus the obstacles known at that moment), whatever the interleaving of
discoveries, requests, evictions and source moves; so are the per-tile hop bounds that
branch 3 prunes with (``tile_bounds``).
"""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from swarmex.planning import fieldcache, tiles
from swarmex.planning.distance import steps_towards
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import GraphWorld, GridWorld
from swarmex.worlds.generators import random_obstacles

from .test_distance import reference

SETTINGS = settings(max_examples=40, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])


def grid_world(seed: int, w: int, h: int, connectivity: int) -> GridWorld:
    rng = np.random.default_rng(seed)
    return GridWorld(rng.random((h, w)) >= 0.1, connectivity=connectivity)


def weighted_world(seed: int, n: int) -> GraphWorld:
    g = nx.connected_watts_strogatz_graph(n, 4, 0.3, seed=seed)
    rng = np.random.default_rng(seed)
    for a, b in g.edges:
        g.edges[a, b]["weight"] = float(rng.integers(1, 7)) * 0.25
    return GraphWorld(g)


# one step of a scenario: (op, vertex choice, number of vertices)
OPS = st.lists(
    st.tuples(st.sampled_from(["obstacles", "field", "slots", "distances", "walk", "prefetch"]),
              st.integers(0, 10**6), st.integers(1, 4)),
    min_size=1, max_size=25,
)


def run_scenario(world, ops, capacity: int, max_hop: int | None = None,
                 prefetch: bool = False) -> None:
    g = world.graph
    n = g.n_nodes
    known = KnownGraph(g, capacity=capacity, prefetch=prefetch)
    if max_hop is not None:  # pretend the narrow hop type holds only this much
        known._max_hop = max_hop
    walker = 0
    for op, pick, k in ops:
        v = pick % n
        if op == "prefetch":  # announce a move: the field may be derived in the background
            if known.uniform:
                nbrs = [int(x) for x in g.neighbors(walker)]
                known.prefetch(nbrs[pick % len(nbrs)], walker)
            continue
        if op == "obstacles":
            # obstacles are discovered next to where someone is, as in the missions
            near = [int(x) for x in g.neighbors(walker)] + [v]
            known.add_obstacles([near[(pick + j) % len(near)] for j in range(k)])
            continue
        if op == "walk":  # a source moving to a neighbour: the shift path on lattices
            nbrs = [int(x) for x in g.neighbors(walker) if not known.blocked[x]]
            if nbrs:
                walker = nbrs[pick % len(nbrs)]
            v = walker
        want = reference(g, v, known.blocked)
        if op in ("field", "walk") or not known.uniform:  # hop rows are for uniform graphs
            got = known.field(v)
        elif op == "distances":
            idx = np.arange(0, n, max(1, k))
            got_part = known.distances(v, idx)
            check(got_part, want[idx], known.uniform)
            continue
        else:  # several rows valid together
            srcs = np.array([(pick + 7 * j) % n for j in range(k)] + [walker], dtype=np.int64)
            rows = known.slots(srcs)
            for s, r in zip(srcs.tolist(), rows.tolist(), strict=True):
                hops = known.hops[r]
                got = np.where(hops >= 0, hops * known.step, np.inf)
                check(got, reference(g, s, known.blocked), True)
            check_tile_bounds(known, srcs, rows)
            continue
        check(got, want, known.uniform)


def check_tile_bounds(known: KnownGraph, srcs: np.ndarray, rows: np.ndarray) -> None:
    """The rows' tile bounds (kept through shifts, repairs and evictions since the last
    call) hold for the true hop counts, and a tile marked unreached has no reached vertex."""
    lo, hi, slack = known.tile_bounds(rows)
    tile_of = known.tiling.tile_of
    for s, r in zip(srcs.tolist(), rows.tolist(), strict=True):
        want = reference(known.graph, s, known.blocked)
        fin = np.isfinite(want)
        hops = np.round(want[fin] / known.step).astype(np.int64)
        t = tile_of[fin]
        assert np.all(lo[r, t] - slack[r] <= hops), (s, r)
        assert np.all(hops <= hi[r, t] + slack[r]), (s, r)
        assert not np.isin(t, np.flatnonzero(lo[r] == tiles.NONE_LO)).any()


def check(got: np.ndarray, want: np.ndarray, exact: bool) -> None:
    assert np.array_equal(np.isinf(got), np.isinf(want))
    fin = np.isfinite(want)
    if exact:  # hop counts times one edge length: the very same floats
        np.testing.assert_allclose(got[fin], want[fin], rtol=0, atol=1e-9)
    else:  # float Dijkstra fields kept across discoveries may differ in the last bits
        np.testing.assert_allclose(got[fin], want[fin], rtol=1e-9, atol=1e-9)


@SETTINGS
@given(seed=st.integers(0, 50), ops=OPS, capacity=st.integers(1, 6))
def test_lattice_cache_is_exact(seed, ops, capacity):
    run_scenario(grid_world(seed, 9, 7, 4), ops, capacity)


@SETTINGS
@given(seed=st.integers(0, 50), ops=OPS, capacity=st.integers(1, 6))
def test_uniform_graph_cache_is_exact(seed, ops, capacity):
    g = nx.connected_watts_strogatz_graph(40, 4, 0.3, seed=seed)
    run_scenario(GraphWorld(g), ops, capacity)


@SETTINGS
@given(seed=st.integers(0, 50), ops=OPS, capacity=st.integers(1, 6))
def test_weighted_cache_is_exact(seed, ops, capacity):
    run_scenario(weighted_world(seed, 40), ops, capacity)


@SETTINGS
@given(seed=st.integers(0, 50), ops=OPS, max_hop=st.integers(2, 12))
def test_narrow_hop_table_widens_when_a_distance_does_not_fit(seed, ops, max_hop):
    run_scenario(grid_world(seed, 9, 7, 4), ops, 3, max_hop=max_hop)


@SETTINGS
@given(seed=st.integers(0, 50), ops=OPS, capacity=st.integers(1, 6))
def test_background_shifts_keep_the_cache_exact(seed, ops, capacity):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(fieldcache, "PREFETCH_MIN_NODES", 0)
        run_scenario(grid_world(seed, 9, 7, 4), ops, capacity, prefetch=True)


def test_widening_keeps_the_fields():
    world = GridWorld(np.ones((3, 40), dtype=bool))
    known = KnownGraph(world.graph, capacity=4)
    known._max_hop = 10
    assert known.hops.dtype == np.int16
    for v in (0, 1, 2, 3):  # a walk along the long side: the far end is 39 hops away
        check(known.field(v), reference(world.graph, v, known.blocked), True)
    assert known.hops.dtype == np.int32


def test_widening_keeps_the_fields_of_a_graph_that_is_no_lattice():
    """The same on a cycle, which runs the CSR kernel, not the lattice one (a path graph
    would be taken for a lattice one cell wide): only grids had exercised the widening."""
    world = GraphWorld(nx.cycle_graph(80))
    known = KnownGraph(world.graph, capacity=4)
    known._max_hop = 10
    assert known.hops.dtype == np.int16
    for v in (0, 1, 2, 3):  # the far side of the cycle is 40 hops away
        check(known.field(v), reference(world.graph, v, known.blocked), True)
    assert known.hops.dtype == np.int32


@SETTINGS
@given(seed=st.integers(0, 50), ops=OPS)
def test_eight_connected_cache_is_exact(seed, ops):
    run_scenario(grid_world(seed, 8, 8, 8), ops, 3)


def test_counters_and_in_place_shift_on_a_walk():
    world = GridWorld(np.ones((30, 30), dtype=bool))
    known = KnownGraph(world.graph, capacity=4)
    path = [world.node(x, 10) for x in range(5, 25)]
    for v in path:
        known.slot(v)
    assert known.recomputed == len(path)
    assert known.shifted == len(path) - 1  # each step derived from the previous field
    assert (known._source >= 0).sum() == 1  # and in place: one row all along
    before = known.reused + known.repaired
    known.add_obstacles([world.node(3, 3)])
    known.slot(path[-1])
    assert known.reused + known.repaired == before + 1
    check(known.field(path[-1]), reference(world.graph, path[-1], known.blocked), True)


@pytest.mark.parametrize("seed", range(4))
def test_first_steps_equal_the_steps_of_the_targets_field(seed):
    """KnownGraph.first_steps walks back through the source's own row; the answer must be
    steps_towards on the target's own field (an independent search from the target)."""
    world = random_obstacles(23, 19, 0.3, seed=seed)
    g = world.graph
    kg = KnownGraph(g)
    rng = np.random.default_rng(seed)
    kg.add_obstacles(np.flatnonzero(world.blocked)[: int(world.blocked.sum()) // 2])
    free = np.flatnonzero(~kg.blocked)
    for _ in range(40):
        source, target = (int(v) for v in rng.choice(free, 2))
        slot = kg.slot(source)
        got = np.sort(kg.first_steps(slot, target))
        want = np.sort(steps_towards(g, kg.field(target), source))
        np.testing.assert_array_equal(got, want)
    slot = kg.slot(source)
    assert kg.first_steps(slot, source).size == 0
