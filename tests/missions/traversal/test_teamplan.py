"""``madgta-p`` (swarmex.missions.traversal.teamplan): madgta-r's rollout with the first
vertex of an end-game team plan as one more candidate.

What is pinned: it is registered and selectable; the plan's local search lowers a
hand-checked plan to its optimum and stays near the brute-force min-max optimum on tiny
instances (and at it on most); the policy completes missions (identical and mixed teams,
perfect and lossy channels, every option), is MADGTA before the end game, never writes the
belief and gives the same decision for the same belief; compiled and interpreted kernels
give the same run.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from swarmex.comm.channel import Channel
from swarmex.missions.traversal import (
    make_policy,
    run_metrics,
    run_traversal,
    uniform_agents,
)
from swarmex.missions.traversal import teamplan as tp
from swarmex.missions.traversal.policies import POLICIES
from swarmex.missions.traversal.rollout import MadgtaR
from swarmex.missions.traversal.rollout_sim import _fill_rows
from swarmex.worlds import empty_grid, random_obstacles
from swarmex.worlds.nodegraph import NodeGraph

from ._helpers import corridor, mixed_agents
from .checking import checking, jit_and_python_agree


def test_registered_and_selectable():
    assert POLICIES["madgta-p"] is tp.MadgtaP
    policy = make_policy("madgta-p")
    assert isinstance(policy, tp.MadgtaP) and isinstance(policy, MadgtaR)
    assert policy.name == "madgta-p" and not policy.madgta_branch2
    assert tp.MadgtaP(k=2, max_vacant=50).k == 2  # madgta-r's keywords pass through
    for bad in (dict(passes=-1), dict(commit=True), dict(k=0)):
        with pytest.raises(ValueError):
            tp.MadgtaP(**bad)


def _rows(g: NodeGraph, vacant: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = g.n_nodes
    table = np.empty((vacant.size, n), dtype=np.int32)
    row_of = np.full(n, -1, dtype=np.int64)
    row_of[vacant] = np.arange(vacant.size)
    _fill_rows(g.indptr, g.indices, np.zeros(n, dtype=bool), vacant, row_of[vacant], table,
               np.empty(n, dtype=np.int32))
    return table, row_of


def _ends(base, pos, routes, lens, edge, jt, table, row_of) -> list[float]:
    return [tp._route_end(a, base, pos, routes, lens, edge, jt, table, row_of)
            for a in range(1, base.size)]


def test_local_search_splits_a_corridor_between_its_two_ends():
    """Corridor 0-...-6, agents at 0 and 6 (free at t = 0), vertices 1..5 vacant, 2 s per
    edge, 9 s per job. Start: agent 1 does all five (5 x 11 = 55 s). By hand the min-max
    optimum gives three to one agent and two to the other: 33 s, with 22 s for the other."""
    g = corridor(7)
    vacant = np.arange(1, 6, dtype=np.int64)
    table, row_of = _rows(g, vacant)
    base = np.zeros(3)
    pos = np.array([-1, 0, 6])
    routes = np.full((3, 6), -1, dtype=np.int64)
    routes[1, :5] = vacant
    lens = np.array([0, 5, 0])
    edge = np.array([0.0, 2.0, 2.0])
    jt = np.array([0.0, 9.0, 9.0])
    active = np.array([False, True, True])
    assert _ends(base, pos, routes, lens, edge, jt, table, row_of) == [55.0, 0.0]
    tp._improve(base, pos, active, routes, lens, edge, jt, table, row_of, 50)
    assert sorted(_ends(base, pos, routes, lens, edge, jt, table, row_of)) == [22.0, 33.0]
    done = sorted(routes[1, :lens[1]].tolist() + routes[2, :lens[2]].tolist())
    assert done == [1, 2, 3, 4, 5]


def _brute_force(base, pos, vac, edge, jt, table, row_of) -> float:
    """The least makespan over every assignment and order (tiny instances only)."""
    m = base.size - 1
    best = np.inf
    for perm in itertools.permutations(vac.tolist()):
        for cuts in itertools.combinations_with_replacement(range(len(perm) + 1), m - 1):
            bounds = (0, *cuts, len(perm))
            worst = 0.0
            for a in range(1, m + 1):
                seq = perm[bounds[a - 1]:bounds[a]]
                c, prev = base[a], pos[a]
                for v in seq:
                    c += edge[a] * table[row_of[v], prev] + jt[a]
                    prev = v
                worst = max(worst, c)
            best = min(best, worst)
    return float(best)


def _tiny(seed: int) -> tuple | None:
    """Two agents (free at random times) and five vacant vertices on a 5x5 random map."""
    rng = np.random.default_rng(seed)
    world = random_obstacles(5, 5, 0.15, seed=seed)
    g = world.graph
    free = np.nonzero(~world.blocked)[0]
    n = g.n_nodes
    pick = rng.choice(free, 7, replace=False)
    pos = np.array([-1, pick[0], pick[1]])
    vac = np.sort(pick[2:]).astype(np.int64)
    table = np.empty((vac.size, n), dtype=np.int32)
    row_of = np.full(n, -1, dtype=np.int64)
    row_of[vac] = np.arange(vac.size)
    _fill_rows(g.indptr, g.indices, world.blocked, vac, row_of[vac], table,
               np.empty(n, dtype=np.int32))
    if (table[:, pos[1:]] < 0).any() or (table[:, vac] < 0).any():
        return None  # a walled-off cell drawn
    base = np.array([0.0, rng.uniform(0, 10), rng.uniform(0, 10)])
    return base, pos, vac, table, row_of


_EDGE = np.array([0.0, 2.0, 2.0])  # the tiny instances' seconds per edge and per job
_JOB = np.array([0.0, 9.0, 9.0])


def _tiny_plans():
    """Per tiny instance: (instance, routes, lens, makespan, optimum), the routes being the
    local search's plan from the worst start (every vertex on agent 1)."""
    for seed in range(16):
        inst = _tiny(seed)
        if inst is None:
            continue
        base, pos, vac, table, row_of = inst
        routes = np.full((3, vac.size + 1), -1, dtype=np.int64)
        routes[1, :vac.size] = vac
        lens = np.array([0, vac.size, 0])
        tp._improve(base, pos, np.array([False, True, True]), routes, lens, _EDGE, _JOB,
                    table, row_of, 100)
        got = max(_ends(base, pos, routes, lens, _EDGE, _JOB, table, row_of))
        yield inst, routes, lens, got, _brute_force(base, pos, vac, _EDGE, _JOB, table, row_of)


def test_local_search_against_the_brute_force_optimum_on_tiny_instances():
    """A local search, not an exact solver: from the worst start (everything on agent 1) it
    reaches the min-max optimum on most tiny instances and stays about one edge above it on
    the others (16 instances: 13 optimal, 3 at 2.0-2.9 s above; the tail exchange was added
    for instance 3, which relocations and swaps left one edge above the optimum)."""
    optimal = tried = 0
    for inst, routes, lens, got, best in _tiny_plans():
        base, pos, vac, table, row_of = inst
        assert best - 1e-9 <= got <= best + 3.0
        assert sorted(routes[1, :lens[1]].tolist() + routes[2, :lens[2]].tolist()) == \
            vac.tolist()
        tried += 1
        optimal += got <= best + 1e-9
    assert tried >= 12 and optimal >= tried - 3


def _neighbours(seqs: list[list[int]]):
    """Every plan one move away: a vertex moved to any place of any route, two vertices
    swapped, a stretch of a route reversed."""
    flat = [(a, i) for a, seq in enumerate(seqs) for i in range(len(seq))]
    for a, i in flat:
        for b in range(len(seqs)):
            for q in range(len(seqs[b]) + (a != b)):
                new = [list(x) for x in seqs]
                v = new[a].pop(i)
                new[b].insert(q, v)
                yield new
    for (a, i), (b, j) in itertools.combinations(flat, 2):
        new = [list(x) for x in seqs]
        new[a][i], new[b][j] = new[b][j], new[a][i]
        yield new
        if a == b:
            new = [list(x) for x in seqs]
            new[a][i:j + 1] = new[a][i:j + 1][::-1]
            yield new


def test_the_sum_pass_lowers_the_sum_within_the_makespan_limit_to_a_local_optimum():
    """``slack``: after the min-max search, a search that keeps a move only when it lowers
    the plan's sum and no route then ends after the limit (the makespan plus ``slack``
    edges). On the tiny instances, from the min-max plan: no route ends after the limit,
    every vertex is planned once, the sum falls on at least two instances, and no plan one
    move away (relocation, swap or reversal, enumerated here) is within the limit with a
    lower sum."""
    lowered = tried = 0
    for inst, routes, lens, got, _ in _tiny_plans():
        base, pos, vac, table, row_of = inst
        active = np.array([False, True, True])
        before = sum(_ends(base, pos, routes, lens, _EDGE, _JOB, table, row_of))
        limit = got + 1.5 * _EDGE[1]
        tp._improve_from(base, pos, active, routes, lens, _EDGE, _JOB, table, row_of, 100,
                         np.ones(3, dtype=bool), limit)
        ends = _ends(base, pos, routes, lens, _EDGE, _JOB, table, row_of)
        assert max(ends) <= limit + 1e-9 and sum(ends) <= before + 1e-9
        seqs = [routes[a, :lens[a]].tolist() for a in (1, 2)]
        assert sorted(seqs[0] + seqs[1]) == vac.tolist()
        for new in _neighbours(seqs):
            moved = np.full_like(routes, -1)
            moved_lens = np.zeros_like(lens)
            for a, seq in enumerate(new, start=1):
                moved[a, :len(seq)] = seq
                moved_lens[a] = len(seq)
            e = _ends(base, pos, moved, moved_lens, _EDGE, _JOB, table, row_of)
            assert max(e) > limit + 1e-9 or sum(e) >= sum(ends) - 1e-9
        tried += 1
        lowered += sum(ends) < before - 1e-9
    assert tried >= 12 and lowered >= 2


@pytest.mark.parametrize("options", [dict(), dict(follow=True), dict(follow=True, commit=True),
                                     dict(passes=0), dict(ils=5, ruin=4),
                                     dict(ils=5, follow=True),
                                     dict(ils=5, follow=True, keep=True)])
@pytest.mark.parametrize("fleet", ["same", "mixed"])
def test_completes_every_job_once(options, fleet):
    world = random_obstacles(12, 12, 0.2, seed=1)
    free = np.nonzero(~world.blocked)[0]
    agents = (uniform_agents([int(v) for v in free[:5]], 2.0, 9.0) if fleet == "same"
              else mixed_agents(world, 5, 1))
    policy = tp.MadgtaP(**options)
    run = run_traversal(world, agents, policy, seed=1)
    assert run.complete and policy.plans > 0
    assert np.all(run.job_count[run.reachable] >= 1)
    assert run_metrics(run, 1.0)[0]["duplicate_jobs"] == 0


@pytest.mark.parametrize("options", [dict(), dict(follow=True, commit=True)])
def test_completes_over_a_lossy_range_limited_channel(options):
    world = random_obstacles(10, 10, 0.2, seed=3)
    run = run_traversal(world, mixed_agents(world, 4, 3), tp.MadgtaP(**options), seed=3,
                        channel=Channel(loss=0.3, range=4.0))
    assert run.complete


def test_before_the_end_game_it_is_madgta_record_for_record():
    world = random_obstacles(14, 14, 0.2, seed=7)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 6, 2.0, 9.0)
    ours = run_traversal(world, agents, tp.MadgtaP(max_vacant=0), seed=7)
    theirs = run_traversal(world, agents, "madgta", seed=7)
    assert ours.path_strings() == theirs.path_strings()
    assert run_metrics(ours, 1.0)[0] == run_metrics(theirs, 1.0)[0]


def test_the_start_plan_is_madgtas_simulated_routes():
    """Corridor 0-1-2-3-4, agent 1 free at 0 (t = 0), agent 2 working at 4 until t = 5
    (test_rollout's mission seen whole). MADGTA: agent 1 takes 1 then 2, agent 2 takes 3;
    nothing to improve (agent 2 ends at 16 and agent 1 at 22; giving 2 to agent 2 ends it
    at 27), so the plan is those routes and agent 1's first vertex is 1."""
    g = corridor(5)
    n = 5
    status = np.zeros(n, dtype=np.int32)
    status[0] = 1
    status[4] = 2
    vacant = np.array([1, 2, 3], dtype=np.int64)
    table, row_of = _rows(g, vacant)
    loc = np.array([-1, 0, 4])
    mode = np.array([-1, 0, 2])
    tfree = np.array([0.0, 0.0, 5.0])
    routes = np.full((3, 4), -1, dtype=np.int64)
    lens = np.zeros(3, dtype=np.int64)
    first = tp._team_plan(
        1, 0.0, g.indptr, g.indices, np.zeros(n, dtype=bool), status,
        np.zeros(n, dtype=np.int32), vacant, table, row_of, loc, loc.copy(), tfree, mode,
        np.full(3, -1), np.full(3, -1), np.array([0.0, 2.0, 2.0]), np.array([0.0, 9.0, 9.0]),
        1.0, np.arange(n, dtype=np.int64), 50, routes, lens, 0, 12,
        np.full((3, 1), -1, dtype=np.int64), np.zeros(3, dtype=np.int64), 0.0, 0.5,
        np.empty_like(routes), np.empty_like(lens),
    )
    assert first == 1
    assert routes[1, :lens[1]].tolist() == [1, 2]
    assert routes[2, :lens[2]].tolist() == [3]


@pytest.mark.parametrize("bad", [dict(ils=-1), dict(ruin=0)])
def test_bad_ruin_and_recreate_settings_are_refused(bad):
    with pytest.raises(ValueError, match=next(iter(bad))):
        tp.MadgtaP(**bad)


def test_ruin_and_recreate_is_deterministic_per_run():
    world = random_obstacles(12, 12, 0.2, seed=4)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(v) for v in free[:5]], 2.0, 9.0)
    runs = [run_traversal(world, agents, tp.MadgtaP(ils=5, follow=True), seed=4)
            for _ in range(2)]
    assert runs[0].path_strings() == runs[1].path_strings()


def test_never_writes_the_belief_and_is_deterministic():
    world = random_obstacles(10, 10, 0.2, seed=5)
    free = np.nonzero(~world.blocked)[0]
    spy = checking(tp.MadgtaP, 40)
    run = run_traversal(world, uniform_agents([int(v) for v in free[:4]], 2.0, 9.0), spy,
                        seed=5)
    assert run.complete and spy.checked > 20 and spy.plans > 0


def test_compiled_and_interpreted_give_the_same_run(tmp_path):
    code = """
    import json
    import numpy as np
    from swarmex.missions.traversal import run_traversal, run_metrics, uniform_agents
    from swarmex.missions.traversal.teamplan import MadgtaP
    from swarmex.worlds import empty_grid, random_obstacles
    world = random_obstacles(9, 9, 0.2, seed=2)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 4, 2.0, 9.0)
    for policy in (MadgtaP(), MadgtaP(follow=True, slack=1.5)):  # the second: the sum pass
        run = run_traversal(world, agents, policy, seed=2)
        print(json.dumps([run.path_strings(), run_metrics(run, 1.0)[0]["max_total_time"]]))
    """
    jit_and_python_agree(code, tmp_path)


def test_iterated_search_reaches_the_brute_force_optimum_where_the_local_search_stops():
    """Ruin and recreate (``ils``) starts from the local search's plan, so it is never worse,
    and on the tiny instances it closes the local search's gap to the min-max optimum; the
    same seed gives the same plan, and every vertex stays planned exactly once. 16
    instances: the local search alone is optimal on 13, with ruin and recreate on 15 (the
    16th stays 0.24 s above: a cluster of 3 of the 5 vertices put back greedily does not
    reach the optimum's split, a cluster of all 5 does)."""
    edge, jt = _EDGE, _JOB
    active = np.array([False, True, True])
    tried = optimal = local_optimal = 0
    for seed, (inst, routes, lens, local, best) in enumerate(_tiny_plans()):
        base, pos, vac, table, row_of = inst
        local_optimal += local <= best + 1e-9
        plans = []
        for _ in range(2):
            r, n = routes.copy(), lens.copy()
            tp._iterated_search(base, pos, active, r, n, edge, jt, table, row_of, 40, 3, 50,
                                seed)
            plans.append((r, n))
        (r, n), (r2, n2) = plans
        assert np.array_equal(r, r2) and np.array_equal(n, n2)
        assert sorted(r[1, :n[1]].tolist() + r[2, :n[2]].tolist()) == vac.tolist()
        got = max(_ends(base, pos, r, n, edge, jt, table, row_of))
        assert best - 1e-9 <= got <= local + 1e-9
        tried += 1
        optimal += got <= best + 1e-9
    assert tried >= 12 and optimal >= tried - 1 and optimal > local_optimal


def test_warm_start_keeps_the_better_plan_and_every_vertex_once():
    """The previous plan (``keep``) replaces the current one only when it is better after the
    local search, and whatever it holds, the plan covers exactly the vertices to plan:
    stale vertices (done since) are dropped and new ones inserted."""
    active = np.array([False, True, True])
    for inst, routes, lens, local, _ in _tiny_plans():
        base, pos, vac, table, row_of = inst
        ends = np.zeros(3)
        # the optimum-seeking ruin and recreate gives a plan at least as good: as the warm
        # plan, it must be taken (or tie) and change nothing worse
        good, glens = routes.copy(), lens.copy()
        tp._iterated_search(base, pos, active, good, glens, _EDGE, _JOB, table, row_of, 40, 3,
                            50, 1)
        r, n = routes.copy(), lens.copy()
        tp._warm_start(base, pos, active, r, n, _EDGE, _JOB, table, row_of, good, glens, 50)
        assert sorted(r[1, :n[1]].tolist() + r[2, :n[2]].tolist()) == vac.tolist()
        got = tp._plan_ends(base, pos, active, r, n, _EDGE, _JOB, table, row_of, ends)
        best = tp._plan_ends(base, pos, active, good, glens, _EDGE, _JOB, table, row_of, ends)
        assert got[0] <= best[0] + 1e-9
        # a stale warm plan: a vertex done since (not to plan any more), and none of
        # vac[2:], which are new to it
        done = int(np.setdiff1d(np.arange(row_of.size), vac)[0])
        stale = np.full((3, vac.size + 2), -1, dtype=np.int64)
        stale[1, :2] = [vac[0], done]
        stale[2, :1] = [vac[1]]
        r, n = routes.copy(), lens.copy()
        tp._warm_start(base, pos, active, r, n, _EDGE, _JOB, table, row_of, stale,
                       np.array([0, 2, 1]), 50)
        assert sorted(r[1, :n[1]].tolist() + r[2, :n[2]].tolist()) == vac.tolist()
        assert max(_ends(base, pos, r, n, _EDGE, _JOB, table, row_of)) <= local + 1e-9


def _planned(seed: int, agents: int = 4, cells: int = 28):
    """A local optimum of a larger random instance (``agents`` agents, ``cells`` vacant
    vertices on a 12 x 12 random map), for the search's shortcuts to be checked on."""
    rng = np.random.default_rng(seed)
    world = random_obstacles(12, 12, 0.15, seed=seed)
    g = world.graph
    n = g.n_nodes
    free = np.nonzero(~world.blocked)[0]
    pick = rng.choice(free, agents + cells, replace=False)
    pos = np.r_[-1, pick[:agents]].astype(np.int64)
    vac = np.sort(pick[agents:]).astype(np.int64)
    table = np.empty((vac.size, n), dtype=np.int32)
    row_of = np.full(n, -1, dtype=np.int64)
    row_of[vac] = np.arange(vac.size)
    _fill_rows(g.indptr, g.indices, world.blocked, vac, row_of[vac], table,
               np.empty(n, dtype=np.int32))
    base = np.r_[0.0, rng.uniform(0, 10, agents)]
    edge = np.r_[0.0, rng.choice([1.0, 2.0], agents)]
    jt = np.r_[0.0, rng.choice([5.0, 9.0], agents)]
    active = np.r_[False, np.ones(agents, dtype=bool)]
    routes = np.full((agents + 1, vac.size + 1), -1, dtype=np.int64)
    lens = np.zeros(agents + 1, dtype=np.int64)
    for t, v in enumerate(vac.tolist()):  # round robin, then the local search
        a = 1 + t % agents
        routes[a, lens[a]] = v
        lens[a] += 1
    state = (base, pos, active, routes, lens, edge, jt, table, row_of)
    assert tp._improve(*state, 200) < 200  # a local optimum
    return state


@pytest.mark.parametrize("seed", range(6))
def test_spliced_route_end_from_hop_prefixes_is_the_walked_end(seed):
    """The tail exchange prices a[:i] + b[j:] from the routes' hop prefixes; checked against
    walking the spliced route, for every i and j (a route may be unreachable: _FAR hops)."""
    base, pos, _, routes, lens, edge, jt, table, row_of = _planned(seed)
    hp = np.empty((routes.shape[0], routes.shape[1] + 1))
    for a in range(1, routes.shape[0]):
        tp._hop_prefix(a, pos, routes, lens, table, row_of, hp[a])
    for a, b in ((1, 2), (2, 1), (3, 4)):
        for i in range(lens[a] + 1):
            for j in range(lens[b] + 1):
                walked = np.full((routes.shape[0], lens[a] + lens[b] + 1), -1, dtype=np.int64)
                seq = routes[a, :i].tolist() + routes[b, j:lens[b]].tolist()
                walked[a, :len(seq)] = seq
                wl = np.zeros_like(lens)
                wl[a] = len(seq)
                want = tp._route_end(a, base, pos, walked, wl, edge, jt, table, row_of)
                got = tp._spliced_end(a, base, pos, routes, i, b, j, lens, edge, jt, table,
                                      row_of, hp[a], hp[b])
                assert got == pytest.approx(want, abs=1e-9)


@pytest.mark.parametrize("seed", range(6))
def test_the_tail_exchange_stops_only_where_no_candidate_can_gain(seed):
    """The tail exchange stops scanning i (or j) once a[:i] alone (b[:j] alone) ends later
    than both routes do now. That is exact only if every a[:i] + b[j:] ends no sooner than
    that prefix's bound, computed the same way, and the bound grows with i; checked in
    floating point for every i and j with edge and job times that are not whole numbers."""
    base, pos, _, routes, lens, edge, jt, table, row_of = _planned(seed)
    edge = edge * 1.11  # 1.11 and 2.22 s per edge: sums that round
    jt = jt * 1.37
    hp = np.empty((routes.shape[0], routes.shape[1] + 1))
    for a in range(1, routes.shape[0]):
        tp._hop_prefix(a, pos, routes, lens, table, row_of, hp[a])
    for a, b in ((1, 2), (2, 1), (3, 4), (4, 3)):
        bounds = [base[a] + edge[a] * hp[a][i] + jt[a] * i for i in range(lens[a] + 1)]
        assert bounds == sorted(bounds)
        for i in range(lens[a] + 1):
            for j in range(lens[b] + 1):
                got = tp._spliced_end(a, base, pos, routes, i, b, j, lens, edge, jt, table,
                                      row_of, hp[a], hp[b])
                assert got >= bounds[i]


@pytest.mark.parametrize("seed", range(6))
def test_search_from_the_changed_routes_takes_the_moves_of_a_full_search(seed):
    """After a ruin and recreate of a locally optimal plan, the search that prices only
    moves touching a changed route (what the iterated search runs) ends at exactly the plan
    of the full search, on instances with mixed edge and job times."""
    base, pos, active, routes, lens, edge, jt, table, row_of = _planned(seed)
    rs = np.array([np.uint64(seed + 1) ^ np.uint64(0x9E3779B97F4A7C15)], dtype=np.uint64)
    ends = np.zeros(base.size)
    checked = 0
    for _ in range(8):
        before, before_lens = routes.copy(), lens.copy()
        tp._plan_ends(base, pos, active, routes, lens, edge, jt, table, row_of, ends)
        tp._ruin_recreate(base, pos, active, routes, lens, edge, jt, table, row_of, ends, 6, rs)
        dirty = np.array([lens[a] != before_lens[a]
                          or not np.array_equal(routes[a, :lens[a]], before[a, :lens[a]])
                          for a in range(base.size)])
        full, full_lens = routes.copy(), lens.copy()
        tp._improve(base, pos, active, full, full_lens, edge, jt, table, row_of, 200)
        tp._improve_from(base, pos, active, routes, lens, edge, jt, table, row_of, 200, dirty,
                         -1.0)
        assert np.array_equal(routes, full) and np.array_equal(lens, full_lens)
        checked += int(dirty.sum() < active.sum())  # some routes really were skipped
    assert checked > 0


def test_follow_walls_is_the_rollout_on_an_open_lattice_and_follows_behind_walls():
    """``follow="walls"``: on a lattice with no wall known the decisions are exactly
    madgta-p's rollout (the search options unused), behind walls the plan is followed (the
    run differs from the rollout's and completes every job once)."""
    open_world = empty_grid(8, 8)
    agents = uniform_agents([0] * 5, 2.0, 9.0)
    plain = run_traversal(open_world, agents, tp.MadgtaP(), seed=3)
    walls = tp.MadgtaP(follow="walls", ils=5, keep=True)
    run = run_traversal(open_world, agents, walls, seed=3)
    assert walls.plans > 0 and run.path_strings() == plain.path_strings()
    world = random_obstacles(12, 12, 0.2, seed=1)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(v) for v in free[:5]], 2.0, 9.0)
    walls = tp.MadgtaP(follow="walls", ils=5, keep=True)
    run = run_traversal(world, agents, walls, seed=1)
    followed = run_traversal(world, agents, tp.MadgtaP(follow=True, ils=5, keep=True), seed=1)
    rollout = run_traversal(world, agents, tp.MadgtaP(), seed=1)
    assert run.complete and run_metrics(run, 1.0)[0]["duplicate_jobs"] == 0
    assert run.path_strings() == followed.path_strings() != rollout.path_strings()
    with pytest.raises(ValueError, match="follow"):
        tp.MadgtaP(follow="always")
