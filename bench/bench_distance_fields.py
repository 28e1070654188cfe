"""Distance-field kernels against networkx on the same graph.

Graph: the free cells of MovingAI ``den520d.map`` (4-connected; from ``$SWARMEX_MAPS``,
default ``../shared/maps``), or a generated 256 x 256 random-obstacle grid when the map is
absent. Prints, from one run:

* single-source fields: :func:`swarmex.planning.distance_field` (the multi-source BFS
  kernel, called with one source) against ``nx.single_source_shortest_path_length`` on the
  graph of free cells, for the same sources, with the ratio (goal: at least 10x);
* the 8-connected grid (Dijkstra kernel) against ``nx.single_source_dijkstra_path_length``;
* one multi-source call (nearest of 16 sources), 16 separate fields in one
  ``distance_fields`` call (parallel over cores) against 16 single calls, and the
  hop-field shift of the field cache against a fresh search.

    .venv/bin/python bench/bench_distance_fields.py
"""

from __future__ import annotations

import time

import networkx as nx
import numpy as np

import _cli
from swarmex.planning.distance import (
    distance_field,
    distance_fields,
    hop_field,
    shift_hop_field,
)
from swarmex.worlds import GridWorld, load_movingai, random_obstacles

GOAL_RATIO = 10.0


maps_dir = _cli.maps_dir  # $SWARMEX_MAPS, default ../shared/maps


def free_cell_graph(world: GridWorld) -> nx.Graph:
    """The networkx view: free cells only, an edge between free neighbours."""
    g = world.graph
    blocked = world.blocked
    src = np.repeat(np.arange(g.n_nodes), np.diff(g.indptr))
    keep = ~blocked[src] & ~blocked[g.indices] & (src < g.indices)
    out = nx.Graph()
    out.add_nodes_from(np.flatnonzero(~blocked).tolist())
    out.add_weighted_edges_from(
        zip(src[keep].tolist(), g.indices[keep].tolist(), g.weights[keep].tolist(),
            strict=True)
    )
    return out


def per_call(fn, items, repeat: int = 1) -> float:
    """Best-of-``repeat`` mean seconds per call of ``fn`` over ``items``."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for it in items:
            fn(it)
        best = min(best, (time.perf_counter() - t0) / len(items))
    return best


def main() -> int:
    # no options; parsed so that --help works and a stray argument is refused, not ignored
    _cli.Parser(description=__doc__.split("\n\n")[0]).parse_args()
    path = maps_dir() / "den520d.map"
    if path.exists():
        world, name = load_movingai(path), "den520d.map"
    else:
        world, name = random_obstacles(256, 256, 0.35, seed=1), "random 256x256 (map absent)"
        print(f"note: {path} not found; using a generated grid instead")
    g = world.graph
    blocked = world.blocked
    free = np.flatnonzero(~blocked)
    rng = np.random.default_rng(0)
    sources = rng.choice(free, size=64, replace=False)
    print(f"graph: {name}, {g.n_nodes} vertices, {free.size} free, 4-connected")

    # ---- single source: ours vs networkx BFS
    distance_field(g, int(sources[0]), blocked)  # compile / load the kernel
    ours = per_call(lambda s: distance_field(g, int(s), blocked), sources, repeat=3)
    nxg = free_cell_graph(world)
    few = sources[:8]
    theirs = per_call(lambda s: nx.single_source_shortest_path_length(nxg, int(s)), few)
    for s in few[:2]:  # same answers
        want = nx.single_source_shortest_path_length(nxg, int(s))
        got = distance_field(g, int(s), blocked)
        assert {v: int(d) for v, d in enumerate(got) if np.isfinite(d)} == want
    ratio = theirs / ours
    print(f"single-source BFS field   swarmex {ours * 1e3:8.3f} ms   networkx "
          f"{theirs * 1e3:8.2f} ms   ratio {ratio:6.1f}x  (goal >= {GOAL_RATIO:.0f}x: "
          f"{'met' if ratio >= GOAL_RATIO else 'not met'})")

    # ---- 8-connected: Dijkstra kernel vs networkx Dijkstra
    w8 = GridWorld(world.free, connectivity=8)
    g8 = w8.graph
    distance_field(g8, int(sources[0]), blocked)
    ours8 = per_call(lambda s: distance_field(g8, int(s), blocked), sources[:16], repeat=2)
    nx8 = free_cell_graph(w8)
    theirs8 = per_call(lambda s: nx.single_source_dijkstra_path_length(nx8, int(s)), few[:4])
    want8 = nx.single_source_dijkstra_path_length(nx8, int(few[0]))
    got8 = distance_field(g8, int(few[0]), blocked)
    assert all(abs(got8[v] - d) < 1e-9 for v, d in want8.items())
    print(f"single-source Dijkstra 8c swarmex {ours8 * 1e3:8.3f} ms   networkx "
          f"{theirs8 * 1e3:8.2f} ms   ratio {theirs8 / ours8:6.1f}x")

    # ---- many sources
    sixteen = sources[:16]
    distance_field(g, sixteen, blocked)
    multi = per_call(lambda _: distance_field(g, sixteen, blocked), range(10), repeat=3)
    print(f"multi-source field (nearest of 16 sources, one call)     {multi * 1e3:8.3f} ms")
    distance_fields(g, sixteen, blocked)
    sep = per_call(lambda _: distance_fields(g, sixteen, blocked), range(3), repeat=3)
    seq = per_call(lambda _: [distance_field(g, int(s), blocked) for s in sixteen],
                   range(3), repeat=3)
    print(f"16 separate fields: distance_fields {sep * 1e3:8.2f} ms   16 single calls "
          f"{seq * 1e3:8.2f} ms   ratio {seq / sep:5.2f}x (parallel over cores)")

    # ---- the field cache's hop kernels: BFS vs shifting a neighbour's field
    steps = []
    for s in sources[:32]:
        nb = [int(v) for v in g.neighbors(int(s)) if not blocked[v]]
        if nb:
            steps.append((hop_field(g, int(s), blocked), nb[0]))
    fresh = per_call(lambda st: hop_field(g, st[1], blocked), steps, repeat=3)
    shift = per_call(lambda st: shift_hop_field(g, st[0], st[1]), steps, repeat=3)
    h, v = steps[0]
    assert np.array_equal(np.maximum(shift_hop_field(g, h, v), -1), hop_field(g, v, blocked))
    print(f"hop field of a moved agent: fresh BFS {fresh * 1e3:8.3f} ms   shift of the "
          f"previous field {shift * 1e3:8.3f} ms   ratio {fresh / shift:5.2f}x")
    return 0


if __name__ == "__main__":
    _cli.run(main)
