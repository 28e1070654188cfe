"""WMA-RRT construction: Main Root rules, Secondary Roots and tree invariants."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from swarmex.errors import InputError
from swarmex.planning.prm import build_prm
from swarmex.planning.rrt import grow_rrt
from swarmex.planning.rrt_wma import build_wma_rrt, crossing_candidates, main_root

from .conftest import CLUTTER, cluster, make


@pytest.mark.parametrize(("n", "k", "step", "seed"), [(1, 60, 10, 0), (3, 200, 10, 1),
                                                      (4, 300, 15, 2), (6, 150, 8, 3)])
def test_tree_invariants(clutter, n, k, step, seed):
    starts = cluster(n)
    rm = build_wma_rrt(clutter, starts, k, step, np.random.default_rng(seed))
    assert rm.n_nodes == k + 1 and rm.n_edges == k  # K nodes plus the Main Root
    assert rm.components == 1 and rm.cycles == 0
    # exactly n branches; the Main Root's only edges are the n first edges
    root_edges = [e for e, (u, v) in enumerate(rm.edges.tolist()) if 0 in (u, v)]
    assert sorted(root_edges) == list(range(n))
    assert sorted(rm.branch[rm.edges[root_edges, 1]].tolist()) == list(range(n))
    # the Main Root is never expanded: no grown node hangs from it
    assert np.all(rm.parent[n + 1 :] > 0)
    # every node reaches its Secondary Root through parents of its own branch
    for v in range(1, rm.n_nodes):
        u = v
        while rm.parent[u] != 0:
            assert rm.branch[rm.parent[u]] == rm.branch[v]
            u = rm.parent[u]
        assert u == rm.branch[v] + 1
    # every edge collision-free (independent route), grown edges exactly ε long
    a, b = rm.pos[rm.edges[:, 0]], rm.pos[rm.edges[:, 1]]
    assert clutter.segments_free_by_tree(a, b).all()
    assert np.allclose(rm.edge_length[n:], step)
    assert np.all(rm.edge_length[:n] <= step + 1e-9) and np.all(rm.edge_length[:n] > 0)
    # start → Main Root legs are free too
    assert clutter.segments_free_by_tree(starts, np.repeat(rm.pos[:1], n, 0)).all()


def test_nearest_neighbour_is_exact(clutter):
    """The batched growth picks the true nearest node for every accepted sample."""
    trace: list = []
    init = cluster(3)
    pos, parent, _, _ = grow_rrt(clutter, init, np.arange(3), 400, 10.0,
                                 np.random.default_rng(7), trace=trace)
    assert len(trace) == len(pos) - 3
    for j, (q, par) in enumerate(trace):
        existing = pos[: 3 + j]
        d = np.hypot(*(existing - np.asarray(q)).T)
        assert d[par] == pytest.approx(d.min(), abs=1e-12)
        assert par == parent[3 + j]


def test_main_root_square_is_the_crossing_of_diagonals(clutter):
    sq = np.array([[10, 10], [20, 10], [20, 20], [10, 20]], dtype=float)
    m, rule = main_root(clutter, sq, 10)
    assert rule == "diagonals" and np.allclose(m, [15, 15])


def test_main_root_falls_back_to_next_pair():
    # pentagon whose two longest diagonals cross inside a small obstacle
    pent = np.array([[0, 0], [40, -2], [50, 30], [20, 50], [-10, 30]], dtype=float) + 60
    cands = crossing_candidates(pent)
    first = cands[0][0]
    env = {"bounds": [0, 0, 200, 200],
           "obstacles": [[[first[0] - 1, first[1] - 1], [first[0] + 1, first[1] - 1],
                          [first[0] + 1, first[1] + 1], [first[0] - 1, first[1] + 1]]]}
    w = make(env)
    m, rule = main_root(w, pent, 10)
    assert rule == "diagonals"
    assert not np.allclose(m, first)
    assert any(np.allclose(m, c) for c, _ in cands[1:])


@pytest.mark.parametrize("n", [1, 2, 3])
def test_small_teams_use_the_centroid(clutter, n):
    starts = cluster(n)
    m, rule = main_root(clutter, starts, 10)
    assert rule == "centroid" and np.allclose(m, starts.mean(axis=0))


def test_collinear_and_coincident_roots(clutter):
    starts = np.array([[10, 10], [30, 10], [50, 10], [10.0, 10.0 + 1e-12]])
    rm = build_wma_rrt(clutter, starts[:3], 50, 10, np.random.default_rng(0))
    sec = rm.pos[1:4]
    assert np.min(cdist(sec, sec) + np.eye(3) * 1e9) > 0  # three distinct roots
    # a start exactly on the Main Root gets a free direction
    rm2 = build_wma_rrt(clutter, np.array([[30.0, 10.0]]), 20, 10, np.random.default_rng(0))
    assert rm2.edge_length[0] == pytest.approx(10)


def test_blocked_starts_raise(clutter, enclosed):
    # one start inside the walled corner, one outside: no point sees both
    with pytest.raises(InputError, match="Main Root"):
        build_wma_rrt(enclosed, np.array([[20, 20], [120, 20]]), 20, 10,
                      np.random.default_rng(0))
    with pytest.raises(InputError, match="fewer"):
        build_wma_rrt(clutter, cluster(3), 2, 10, np.random.default_rng(0))


def test_prm_structure(clutter):
    rm = build_prm(clutter, cluster(3), 300, 10, np.random.default_rng(4))
    assert rm.n_nodes == 300 and rm.parent is None
    a, b = rm.pos[rm.edges[:, 0]], rm.pos[rm.edges[:, 1]]
    assert clutter.segments_free_by_tree(a, b).all()
    assert np.all(rm.edge_length <= 20 + 1e-9)  # merge radius 2ε
    assert rm.cycles > 0  # merging makes loops
    import networkx as nx

    g = nx.Graph()
    g.add_nodes_from(range(rm.n_nodes))
    g.add_edges_from(rm.edges.tolist())
    assert rm.components == nx.number_connected_components(g)
    assert rm.cycles == g.number_of_edges() - g.number_of_nodes() + rm.components
    for p, e in zip(rm.starts, rm.entry_node, strict=True):
        assert e >= 0 and clutter.segment_free(*p, *rm.pos[e])


def test_same_seed_same_tree():
    w = make(CLUTTER)
    a = build_wma_rrt(w, cluster(3), 200, 10, np.random.default_rng(11))
    b = build_wma_rrt(w, cluster(3), 200, 10, np.random.default_rng(11))
    assert np.array_equal(a.pos, b.pos) and np.array_equal(a.edges, b.edges)
