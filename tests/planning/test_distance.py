"""Distance kernels against independent routes (scipy.sparse.csgraph, networkx)."""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from swarmex.planning import hop_shift
from swarmex.planning.distance import (
    distance_field,
    distance_fields,
    hop_field,
    hops_to_distances,
    lattice_structure,
    on_path_neighbors,
    repair_hops,
    shift_hop_field,
    step_length,
    steps_towards,
)
from swarmex.planning.kernel_arrays import BLOCKED
from swarmex.worlds import GraphWorld, GridWorld
from swarmex.worlds.generators import random_obstacles


def reference(graph, sources, blocked) -> np.ndarray:
    """Multi-source shortest paths by scipy on the graph minus blocked vertices; a blocked
    source still radiates (edges out of a source are kept)."""
    src = np.atleast_1d(np.asarray(sources))
    n = graph.n_nodes
    rows = np.repeat(np.arange(n), np.diff(graph.indptr))
    cols = graph.indices.astype(np.int64)
    is_src = np.zeros(n, dtype=bool)
    is_src[src] = True
    keep = ~blocked[cols] & (~blocked[rows] | is_src[rows])
    # a super-source joined to every source by zero-length edges (scipy drops explicit
    # zeros, so use a tiny length and round it away below)
    eps = 1e-12
    r = np.concatenate([rows[keep], np.full(src.size, n)])
    c = np.concatenate([cols[keep], src])
    w = np.concatenate([graph.weights[keep], np.full(src.size, eps)])
    m = csr_matrix((w, (r, c)), shape=(n + 1, n + 1))
    d = dijkstra(m, directed=True, indices=n)[:n]
    return np.where(np.isfinite(d), d - eps, d)


def random_blocked(n: int, density: float, rng: np.random.Generator) -> np.ndarray:
    return rng.random(n) < density


def weighted_world(seed: int) -> GraphWorld:
    g = nx.connected_watts_strogatz_graph(80, 4, 0.3, seed=seed)
    rng = np.random.default_rng(seed)
    for a, b in g.edges:
        g.edges[a, b]["weight"] = float(rng.uniform(0.2, 3.0))
    return GraphWorld(g)


GRIDS = [
    ("grid4", lambda s: random_obstacles(23, 17, 0.25, seed=s)),
    ("grid8", lambda s: GridWorld(random_obstacles(19, 21, 0.2, seed=s).free, connectivity=8)),
    ("weighted", weighted_world),
]


@pytest.mark.parametrize("name,make", GRIDS)
@pytest.mark.parametrize("seed", range(4))
def test_distance_field_matches_scipy(name, make, seed):
    world = make(seed)
    g = world.graph
    rng = np.random.default_rng(seed)
    blocked = random_blocked(g.n_nodes, 0.15, rng)
    for k in (1, 3):
        src = rng.choice(g.n_nodes, size=k, replace=False)
        got = distance_field(g, src, blocked)
        np.testing.assert_allclose(got, reference(g, src, blocked), rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("seed", range(3))
def test_bfs_matches_networkx_hop_counts(seed):
    world = random_obstacles(30, 20, 0.3, seed=seed)
    g = world.graph
    rng = np.random.default_rng(seed)
    s = int(rng.choice(np.flatnonzero(~world.blocked)))
    nxg = nx.Graph()
    nxg.add_nodes_from(range(g.n_nodes))
    for u in np.flatnonzero(~world.blocked):
        for v in g.neighbors(u):
            if not world.blocked[v]:
                nxg.add_edge(int(u), int(v))
    want = nx.single_source_shortest_path_length(nxg, s)
    got = distance_field(g, s, world.blocked)
    assert {v: int(d) for v, d in enumerate(got) if np.isfinite(d)} == want
    hops = hop_field(g, s, world.blocked)
    assert {v: int(h) for v, h in enumerate(hops) if h >= 0} == want
    np.testing.assert_array_equal(hops_to_distances(hops, step_length(g)), got)


def test_blocked_source_still_radiates_and_no_blocked_vertex_is_entered():
    world = random_obstacles(10, 10, 0.0, seed=0)
    g = world.graph
    blocked = np.zeros(g.n_nodes, dtype=bool)
    blocked[[11, 12, 55]] = True
    d = distance_field(g, 11, blocked)
    assert d[11] == 0 and d[1] == 1 and np.isinf(d[12]) and np.isinf(d[55])


@pytest.mark.parametrize("name,make", GRIDS)
def test_distance_fields_are_separate_single_source_fields(name, make):
    world = make(5)
    g = world.graph
    rng = np.random.default_rng(5)
    blocked = random_blocked(g.n_nodes, 0.1, rng)
    src = rng.choice(g.n_nodes, size=5, replace=False)
    many = distance_fields(g, src, blocked)
    assert many.shape == (5, g.n_nodes)
    for row, s in zip(many, src, strict=True):
        np.testing.assert_array_equal(row, distance_field(g, int(s), blocked))
    assert distance_fields(g, [], blocked).shape == (0, g.n_nodes)


def test_lattice_structure_recognises_exactly_the_4_connected_grids():
    for h, w in [(1, 7), (7, 1), (5, 6), (9, 4)]:
        world = GridWorld(np.ones((h, w), dtype=bool))
        width, mask = lattice_structure(world.graph)
        assert width >= 1 and mask is not None
        # the mask reproduces the CSR degrees
        assert np.array_equal(
            np.unpackbits(mask[:, None], axis=1).sum(axis=1), np.diff(world.graph.indptr)
        )
    assert lattice_structure(GridWorld(np.ones((4, 4), dtype=bool), connectivity=8).graph)[0] == 0
    assert lattice_structure(weighted_world(0).graph)[0] == 0
    # a uniform graph that is not a lattice: a ring
    assert lattice_structure(GraphWorld(nx.cycle_graph(12)).graph)[0] == 0


@pytest.mark.parametrize("seed", range(5))
def test_shift_hop_field_equals_a_fresh_search(seed):
    world = random_obstacles(25, 18, 0.3, seed=seed)
    g = world.graph
    rng = np.random.default_rng(seed)
    blocked = world.blocked | random_blocked(g.n_nodes, 0.05, rng)
    free = np.flatnonzero(~blocked)
    s = int(rng.choice(free))
    hops = hop_field(g, s, blocked)
    for step in range(60):  # a random walk, each step shifting the field
        nbrs = [int(v) for v in g.neighbors(s) if not blocked[v]]
        if not nbrs:
            break
        s = nbrs[int(rng.integers(len(nbrs)))]
        method = ("auto", "cone", "complement", "complement-bits")[step % 4]
        hops = shift_hop_field(g, hops, s, method)
        fresh = hop_field(g, s, blocked)
        np.testing.assert_array_equal(np.maximum(hops, -1), fresh)
    with pytest.raises(ValueError):
        shift_hop_field(g, hops, s)  # not a neighbour of the field's source


@pytest.mark.parametrize("name,make", [GRIDS[0], ("ring", lambda s: GraphWorld(
    nx.connected_watts_strogatz_graph(60, 4, 0.2, seed=s)))])
@pytest.mark.parametrize("seed", range(5))
def test_repair_hops_equals_a_fresh_search(name, make, seed):
    world = make(seed)
    g = world.graph
    assert g.uniform
    rng = np.random.default_rng(seed)
    blocked = np.zeros(g.n_nodes, dtype=bool)
    s = int(rng.integers(g.n_nodes))
    hops = hop_field(g, s, blocked)
    for _ in range(6):
        new = rng.choice(g.n_nodes, size=int(rng.integers(1, 6)), replace=False)
        new = new[~blocked[new]]
        blocked[new] = True
        changed = repair_hops(g, hops, s, new, blocked)
        fresh = hop_field(g, s, blocked)
        np.testing.assert_array_equal(np.maximum(hops, -1), fresh)
        assert changed >= 0


@pytest.mark.parametrize("name,make", GRIDS)
def test_steps_towards_are_the_first_steps_of_shortest_paths(name, make):
    world = make(2)
    g = world.graph
    rng = np.random.default_rng(2)
    blocked = world.blocked
    free = np.flatnonzero(~blocked)
    for _ in range(20):
        a, t = (int(x) for x in rng.choice(free, 2, replace=False))
        to_t = distance_field(g, t, blocked)
        steps = steps_towards(g, to_t, a)
        if not np.isfinite(to_t[a]):
            assert steps.size == 0
            continue
        w = g.neighbor_weights(a)
        nb = g.neighbors(a)
        want = nb[np.isclose(to_t[nb] + w, to_t[a], rtol=1e-9, atol=1e-9)]
        assert set(steps.tolist()) == set(want.tolist())
        for v in steps:
            assert not blocked[v]
        got = on_path_neighbors(g, a, to_t[a], to_t[nb])
        np.testing.assert_array_equal(got, steps)


@pytest.mark.parametrize("seed", range(3))
def test_in_place_shift_equals_a_shift_into_another_row(seed):
    """The field cache shifts a row in place (old and new row the same array); the shift
    kernels take a separate, vectorised path then and must give the same row."""
    world = random_obstacles(31, 17, 0.25, seed=seed)
    g = world.graph
    width, mask = lattice_structure(g)
    rng = np.random.default_rng(seed)
    blocked = world.blocked.copy()
    free = np.flatnonzero(~blocked)
    s = int(rng.choice(free))
    row = hop_field(g, s, blocked).astype(np.int16)
    row[blocked] = BLOCKED
    n = g.n_nodes
    queue = np.empty(n, dtype=np.int32)
    for step in range(40):
        nbrs = [int(v) for v in g.neighbors(s) if not blocked[v]]
        if not nbrs:
            break
        t = nbrs[int(rng.integers(len(nbrs)))]
        apart = np.empty_like(row)
        if step % 2:
            hop_shift._shift_source_lattice(width, mask, row, apart, t, queue)
            hop_shift._shift_source_lattice(width, mask, row, row, t, queue)
        else:
            hop_shift._shift_by_complement_bits(width, mask, row, apart, t, s, queue)
            hop_shift._shift_by_complement_bits(width, mask, row, row, t, s, queue)
        np.testing.assert_array_equal(row, apart)
        np.testing.assert_array_equal(np.maximum(row, -1), hop_field(g, t, blocked))
        s = t
