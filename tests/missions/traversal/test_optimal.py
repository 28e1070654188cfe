"""The exact offline optimum (optimal.py) against independent checks.

* tiny instances: the MILP optimum equals a brute force over every assignment of vertices to
  agents and every job order, on distances from networkx (not the package's kernels);
* the thesis's worked example (seed 000 §3.2.4): the optimum is bracketed by an honest lower
  bound and by MADGTA, and its exact value is confirmed by an independent path-cover search;
* refusal above the size limit; and a replay of the result record against the map.
"""

from __future__ import annotations

import itertools
from functools import cache

import networkx as nx
import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.traversal import run_metrics, run_traversal, uniform_agents
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.metrics import traversal_record
from swarmex.missions.traversal.optimal import (
    MAX_FREE_VERTICES,
    optimal_record,
    solve_optimal,
)
from swarmex.worlds import GraphWorld, GridWorld, random_obstacles

from .thesis_grid import thesis_grid, tid_to_node

# ----------------------------------------------------------------------------- brute force


def _closure(world, verts: list[int]) -> dict[tuple[int, int], float]:
    """Shortest-path lengths between free vertices, computed by networkx from the CSR."""
    g = nx.Graph()
    graph = world.graph
    free = [v for v in range(graph.n_nodes) if not world.blocked[v]]
    g.add_nodes_from(free)
    for u in free:
        for v, w in zip(graph.neighbors(u), graph.neighbor_weights(u), strict=True):
            if not world.blocked[v]:
                g.add_edge(int(u), int(v), weight=float(w))
    lengths = dict(nx.all_pairs_dijkstra_path_length(g, weight="weight"))
    return {(u, v): lengths[u].get(v, np.inf) for u in verts for v in verts}


def brute_force(world, agents: list[AgentSpec], objective: str) -> float:
    """Enumerate every assignment of vertices to agents and every order of each agent's jobs."""
    g = nx.Graph()
    graph = world.graph
    for u in range(graph.n_nodes):
        for v in graph.neighbors(u):
            if not (world.blocked[u] or world.blocked[v]):
                g.add_edge(int(u), int(v))
    nests = {a.nest for a in agents}
    g.add_nodes_from(nests)
    verts = sorted(set().union(*(nx.node_connected_component(g, s) for s in nests)))
    d = _closure(world, verts)

    @cache
    def agent_cost(a: int, jobs: frozenset) -> float:
        spec = agents[a]
        best = np.inf
        for order in itertools.permutations(sorted(jobs)):
            seq = (spec.nest, *order)
            length = sum(d[u, v] for u, v in zip(seq, seq[1:], strict=False))
            best = min(best, length / spec.travel_speed + spec.job_time * len(order))
        return best

    best = np.inf
    for owner in itertools.product(range(len(agents)), repeat=len(verts)):
        costs = [
            agent_cost(a, frozenset(v for v, o in zip(verts, owner, strict=True) if o == a))
            for a in range(len(agents))
        ]
        best = min(best, sum(costs) if objective == "sum" else max(costs))
    return best


def tiny_instance(seed: int):
    """≤ 7 free vertices: a random 3×3 grid or a weighted random graph; 1–3 mixed agents."""
    rng = np.random.default_rng(seed)
    if seed % 3 == 2:
        g = nx.connected_watts_strogatz_graph(7, 3, 0.5, seed=seed)
        for u, v in g.edges:
            g.edges[u, v]["weight"] = float(rng.uniform(0.5, 3.0))
        for v in g.nodes:
            g.nodes[v]["pos"] = (float(v), float(v % 2))
        obstacles = [int(rng.integers(7))] if seed % 2 else []
        world = GraphWorld(g, obstacles=obstacles)
    else:
        free = rng.random((3, 3)) >= 0.3
        free[0, 0] = True
        while free.sum() > 7:
            free.flat[rng.choice(np.nonzero(free.ravel()[1:])[0] + 1)] = False
        world = GridWorld(free)
    free_v = np.nonzero(~world.blocked)[0]
    m = 1 + seed % 3
    return world, [
        AgentSpec(
            int(rng.choice(free_v)),
            travel_speed=float(rng.choice([0.5, 1.0, 1.5])),
            job_time=float(rng.choice([0.0, 2.0, 5.0])),
        )
        for _ in range(m)
    ]


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("objective", ["sum", "makespan"])
def test_milp_equals_brute_force(seed, objective):
    world, agents = tiny_instance(seed)
    expected = brute_force(world, agents, objective)
    # the flow model's makespan (min T, C_a <= T) is slow even here: checked separately below
    for formulation in ("flow", "partition") if objective == "sum" else ("partition",):
        plan = solve_optimal(world, agents, objective, formulation=formulation)
        assert plan.proven_optimal, (formulation, plan.status)
        assert plan.value == pytest.approx(expected, rel=1e-9, abs=1e-6), formulation
        # the reported value is that of the reported plan, recomputed from its walks
        times = [a.total_time for a in plan.agents]
        assert plan.value == pytest.approx(sum(times) if objective == "sum" else max(times))
        assert sorted(v for a in plan.agents for v in a.jobs) == plan.vertices


@pytest.mark.parametrize("seed", [4, 5, 10])
def test_flow_makespan_matches_brute_force(seed):
    world, agents = tiny_instance(seed)
    plan = solve_optimal(world, agents, "makespan", formulation="flow")
    assert plan.proven_optimal
    assert plan.value == pytest.approx(brute_force(world, agents, "makespan"), abs=1e-6)


@pytest.mark.parametrize("objective", ["sum", "makespan"])
def test_identical_agents_on_one_nest_match_brute_force(objective):
    # the symmetric case of Tables 5.1-5.2: one shared nest, identical agents (one class)
    free = np.ones((3, 3), dtype=bool)
    free[1, 1] = free[0, 2] = False
    world = GridWorld(free)
    agents = [AgentSpec(4 - 1, 0.5, 9.0)] * 3
    expected = brute_force(world, agents, objective)
    for formulation in ("flow", "partition") if objective == "sum" else ("partition",):
        plan = solve_optimal(world, agents, objective, formulation=formulation)
        assert plan.proven_optimal
        assert plan.value == pytest.approx(expected, abs=1e-6), formulation


def test_obstacle_cut_vertices_are_not_required_and_agents_may_idle():
    # a 3x3 grid whose right column is walled off: only the left 2 columns need jobs
    free = np.array([[1, 0, 1], [1, 1, 0], [1, 1, 0]], dtype=bool)
    world = GridWorld(free)
    agents = [AgentSpec(0, 1.0, 1.0), AgentSpec(0, 1.0, 1.0), AgentSpec(0, 1.0, 1.0)]
    plan = solve_optimal(world, agents, "sum")
    assert 2 not in plan.vertices  # (x=2, y=0) is free but unreachable
    assert plan.value == pytest.approx(brute_force(world, agents, "sum"))
    assert any(not a.jobs for a in plan.agents)  # one path covers the 5 cells best


# ----------------------------------------------------------------------- worked example

EXAMPLE_OBSTACLES = (3, 13, 14, 19)
EXAMPLE_NESTS = (1, 11, 23)


@pytest.fixture(scope="module")
def example():
    world = thesis_grid(5, 5, obstacles=EXAMPLE_OBSTACLES)
    nests = [tid_to_node(k, 5, 5) for k in EXAMPLE_NESTS]
    agents = uniform_agents(nests, travel_time=2.0, job_time=9.0)
    record = optimal_record(world, agents, "sum", seed=0, params={"grid": "5x5"})
    return world, agents, record


def _perfect_cover_exists(world, nests: list[int]) -> bool:
    """Do vertex-disjoint grid paths from the nests cover every free vertex?

    That is the only way to pay exactly one edge per job beyond the nests: 18 moves here.
    Depth-first over self-avoiding walks, one agent after the other.
    """
    free = {int(v) for v in np.nonzero(~world.blocked)[0]}
    adj = {v: [int(u) for u in world.graph.neighbors(v) if int(u) in free] for v in free}

    def extend(k: int, here: int, used: frozenset) -> bool:
        if len(used) == len(free):
            return True
        for u in adj[here]:
            if u not in used and extend(k, u, used | {u}):
                return True
        return k + 1 < len(nests) and nests[k + 1] not in used and extend(
            k + 1, nests[k + 1], used | {nests[k + 1]}
        )

    return extend(0, nests[0], frozenset({nests[0]}))


def test_worked_example_is_bracketed_by_the_bound_and_by_madgta(example):
    world, agents, record = example
    value = record.metrics["total_time_all"]
    assert record.metrics["proven_optimal"]
    # Lower bound: 21 jobs of 9 s, plus one 2 s edge to reach each of the 18 vertices that
    # are not a nest (a nest's job can be done without moving).
    free = int((~world.blocked).sum())
    assert free == 21
    lower = free * 9.0 + (free - 3) * 2.0
    assert lower == 225.0
    assert value >= lower
    # The bound is not attained: every plan costs 189 + 2·moves (odd, so 226 is impossible),
    # and 225 would need 3 disjoint grid paths from the nests through all 21 cells.
    nests = [a.nest for a in agents]
    assert not _perfect_cover_exists(world, nests)
    assert value == 227.0
    # MADGTA, online and without the map, can only do as well or worse.
    for seed in range(5):
        run = run_traversal(world, agents, seed=seed)
        totals, _ = run_metrics(run, 1.0)
        assert run.complete
        assert value <= totals["total_time_all"] + 1e-9
    totals, _ = run_metrics(run_traversal(world, agents, seed=2), 1.0)
    assert totals["total_time_all"] == 229.0  # the printed run: 20 moves, 2 of them extra


def test_the_cover_search_finds_a_cover_when_one_exists():
    world = thesis_grid(3, 3)
    assert _perfect_cover_exists(world, [tid_to_node(1, 3, 3)])  # a snake through 3×3


# ------------------------------------------------------------------------------- limits


def test_refuses_above_the_size_limit():
    world = GridWorld(np.ones((5, 5), dtype=bool))
    agents = [AgentSpec(0, 1.0, 1.0), AgentSpec(24, 1.0, 1.0)]
    assert MAX_FREE_VERTICES["makespan"] < 25
    with pytest.raises(InputError, match=r"25 free vertices.*limited to"):
        solve_optimal(world, agents, "makespan")
    big = GridWorld(np.ones((8, 8), dtype=bool))
    assert MAX_FREE_VERTICES["sum"] < 64
    with pytest.raises(InputError, match=r"64 free vertices.*limited to"):
        optimal_record(big, agents, "sum", seed=0, params={})


def test_bad_arguments_are_input_errors():
    world = GridWorld(np.ones((2, 2), dtype=bool))
    agents = [AgentSpec(0, 1.0, 1.0)]
    with pytest.raises(InputError, match="objective"):
        solve_optimal(world, agents, "fastest")
    with pytest.raises(InputError, match="formulation"):
        solve_optimal(world, agents, "sum", formulation="dfj")
    blocked = GridWorld(np.array([[False, True], [True, True]]))
    with pytest.raises(InputError, match="obstacle"):
        solve_optimal(blocked, agents, "sum")


# ------------------------------------------------------------------------------- record


def _replay(world, record) -> None:
    """Independent checker: moves are edges between free cells, each free cell one job."""
    at = {tuple(world.graph.pos[v]): v for v in range(world.graph.n_nodes)}
    done: list[int] = []
    for agent in record.agents:
        cells = [at[(x, y)] for _, x, y in agent.trajectory]
        times = [t for t, _, _ in agent.trajectory]
        assert times[0] == 0.0 and times == sorted(times)
        for u, v in zip(cells, cells[1:], strict=False):
            assert v in world.graph.neighbors(u).tolist()
            assert not world.blocked[u] and not world.blocked[v]
        held = set(zip(times, cells, strict=True))
        for t, x, y in agent.jobs:
            assert (t, at[(x, y)]) in held  # a job is done where and when the agent is
            done.append(at[(x, y)])
        m = agent.metrics
        assert m["nodes_done"] == len(agent.jobs)
        if agent.jobs:  # the walk ends with the last job
            spec_job = m["job_time"] / m["nodes_done"]
            assert agent.jobs[-1][0] + spec_job == pytest.approx(m["total_time"])
    free = sorted(int(v) for v in np.nonzero(~world.blocked)[0])
    assert sorted(done) == free


def test_record_replays_on_the_worked_example(example):
    world, agents, record = example
    _replay(world, record)
    assert record.complete and record.algorithm == "optimal"
    assert record.params["objective"] == "sum"
    assert record.makespan == max(a.metrics["total_time"] for a in record.agents)
    # the same metric names as MADGTA's record, so the two compare column by column
    madgta = traversal_record(run_traversal(world, agents, seed=2), {})
    assert set(madgta.metrics) <= set(record.metrics)
    for a, b in zip(madgta.agents, record.agents, strict=True):
        assert set(a.metrics) == set(b.metrics)
    d = record.to_dict()
    assert d["solver"]["status"] == "Optimal" and d["metrics"]["mip_gap"] == 0.0


@pytest.mark.parametrize("seed", [0, 1, 4])
def test_record_replays_for_makespan_on_mixed_agents(seed):
    world = random_obstacles(4, 4, 0.2, seed=seed)
    nest = int(np.nonzero(~world.blocked)[0][0])
    agents = [AgentSpec(nest, 1.0, 3.0), AgentSpec(nest, 0.5, 1.0)]
    record = optimal_record(world, agents, "makespan", seed=seed, params={})
    _replay(world, record)
    assert record.metrics["proven_optimal"]
    assert record.makespan == pytest.approx(record.metrics["objective_value"])


def test_deterministic():
    world, agents = tiny_instance(7)
    a = solve_optimal(world, agents, "makespan")
    b = solve_optimal(world, agents, "makespan")
    assert [p.walk for p in a.agents] == [p.walk for p in b.agents]
