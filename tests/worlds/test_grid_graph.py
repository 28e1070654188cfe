"""Grid and graph worlds: adjacency matches an independent networkx construction."""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.worlds import GraphWorld, GridWorld, maze, random_obstacles, rooms


def _edges(world) -> set[tuple[int, int]]:
    g = world.graph
    return {
        (min(u, int(v)), max(u, int(v))) for u in range(g.n_nodes) for v in g.neighbors(u)
    }


def test_four_connected_matches_networkx():
    w = random_obstacles(7, 5, 0.3, seed=3)
    ref = nx.grid_2d_graph(5, 7)  # nodes (row, col)
    expected = {
        tuple(sorted((r1 * 7 + c1, r2 * 7 + c2))) for (r1, c1), (r2, c2) in ref.edges
    }
    assert _edges(w) == expected
    assert w.graph.uniform


def test_eight_connected_has_no_corner_cutting():
    free = np.array([[True, False], [False, True]])
    w = GridWorld(free, connectivity=8)
    # the diagonal between (0,0) and (1,1) squeezes between two walls: no edge
    assert 3 not in w.graph.neighbors(0).tolist()
    open_ = GridWorld(np.ones((2, 2), bool), connectivity=8)
    assert sorted(open_.graph.neighbors(0).tolist()) == [1, 2, 3]
    assert open_.graph.edge_length(0, 3) == pytest.approx(np.sqrt(2))
    assert not open_.graph.uniform


def test_coordinates_are_column_row():
    w = GridWorld(np.ones((3, 4), bool))
    assert w.node(3, 2) == 11
    assert w.xy(11) == (3, 2)
    assert w.graph.pos[11].tolist() == [3.0, 2.0]


def test_graph_world_high_degree_and_weights():
    g = nx.star_graph(40)  # centre 0 has degree 40
    for u, v in g.edges:
        g.edges[u, v]["weight"] = 1.0 + v / 10
    w = GraphWorld(g, obstacles=[5, 6])
    assert len(w.graph.neighbors(w.node(0))) == 40
    assert w.free_cells == 39
    assert w.graph.edge_length(w.node(0), w.node(7)) == pytest.approx(1.7)


def test_graph_world_rejects_bad_input():
    with pytest.raises(InputError, match="undirected"):
        GraphWorld(nx.DiGraph([(0, 1)]))
    with pytest.raises(InputError, match="not a vertex"):
        GraphWorld(nx.path_graph(3), obstacles=[9])


@pytest.mark.parametrize("make", [lambda s: random_obstacles(20, 15, 0.3, s), lambda s: rooms(
    30, 20, seed=s), lambda s: maze(21, 15, seed=s)])
def test_generators_are_seeded_and_connected(make):
    from scipy import ndimage

    a, b, c = make(1), make(1), make(2)
    assert np.array_equal(a.free, b.free)
    assert a.free_cells > 0
    assert ndimage.label(a.free)[1] == 1
    assert not np.array_equal(a.free, c.free)


def test_an_edge_of_length_zero_is_refused_as_a_negative_one_is():
    # a zero-length edge makes travel free and distance ties degenerate ("must be positive")
    with pytest.raises(InputError, match="edge lengths must be positive"):
        _ = GraphWorld(nx.Graph([(0, 1, {"weight": 0.0})])).graph


def test_a_self_loop_is_no_neighbour_and_distances_are_networkxs():
    """A loop (v, v) would list v among its own neighbours: an agent could 'move' onto the
    vertex it stands on. Neighbours and distances are networkx's, loops left out."""
    from swarmex.planning.distance import distance_field

    g = nx.path_graph(4)
    g.add_edge(1, 1)
    nx.set_edge_attributes(g, 1.0, "weight")
    w = GraphWorld(g)
    for v in range(4):
        assert sorted(w.graph.neighbors(v)) == sorted(set(g[v]) - {v})
    want = nx.single_source_dijkstra_path_length(g, 0)
    assert list(distance_field(w.graph, 0)) == [want[v] for v in range(4)]


def test_the_weight_attribute_named_is_the_one_read():
    # GraphWorld(weight="len") read "weight" (absent: every edge 1.0) and nobody noticed
    from swarmex.planning.distance import distance_field

    g = nx.path_graph(3)
    nx.set_edge_attributes(g, 3.0, "len")
    w = GraphWorld(g, weight="len")
    assert w.graph.edge_length(0, 1) == 3.0
    assert distance_field(w.graph, 0)[2] == nx.dijkstra_path_length(g, 0, 2, weight="len")
