"""Coverage behaviour (§3.1): completes, traverses every edge, marks every branch COMPLETE."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmex.missions.roadmap import COMPLETE, build_record, replay_problems, run_roadmap

from .conftest import cluster


@pytest.mark.parametrize("planner", ["wma-rrt", "wma-rrt-takeover", "wma-rrt-fairshare"])
@pytest.mark.parametrize(("n", "seed"), [(1, 0), (2, 1), (3, 2), (5, 3)])
def test_coverage_completes(clutter, planner, n, seed):
    run = run_roadmap(clutter, cluster(n), planner=planner, nodes=150, step=10,
                      sensor_range=15, seed=seed)
    b = run.board
    assert run.complete and not run.budget_exhausted
    assert np.all(b.weight == COMPLETE) and np.all(b.sync == 0)
    assert np.all(b.traversals >= 2)  # every edge down and back at least once
    assert np.all(b.rem_sub == 0) and np.all(b.busy == 0)
    assert np.all(b.completed_at >= 1) and b.completed_at.max() <= run.steps
    for a in run.agents:  # everyone is home at the Main Root
        assert a.state == "done" and a.node == 0
        assert np.allclose(a.xy, run.roadmap.pos[0])
    rec = build_record(run, {"task": "coverage", "starts": cluster(n).tolist()}, seed, 0.0)
    assert replay_problems(rec.to_dict(), clutter) == []


def test_single_agent_is_a_dfs(clutter):
    run = run_roadmap(clutter, cluster(1), nodes=120, step=10, sensor_range=15, seed=4)
    assert np.all(run.board.traversals == 2)
    assert run.steps == 1 + 2 * run.roadmap.n_edges  # entry leg, then each edge twice
    entry = np.hypot(*(run.roadmap.pos[0] - cluster(1)[0]))
    assert run.path_length[0] == pytest.approx(entry + 2 * run.roadmap.edge_length.sum())


def test_helpers_join_and_finish_faster_with_takeover_and_fairshare(clutter):
    steps: dict[str, list[int]] = {"wma-rrt": [], "wma-rrt-takeover": [], "wma-rrt-fairshare": []}
    for seed in range(4):
        for planner, out in steps.items():
            run = run_roadmap(clutter, cluster(3), planner=planner, nodes=300, step=10,
                              sensor_range=15, seed=seed)
            out.append(run.steps)
            if planner == "wma-rrt":
                assert max(a.branches_entered for a in run.agents) >= 2  # someone helped
    assert np.mean(steps["wma-rrt-takeover"]) < np.mean(steps["wma-rrt"])
    assert np.mean(steps["wma-rrt-fairshare"]) < np.mean(steps["wma-rrt"])


def test_fairshare_takes_an_unexplored_child_first(clutter):
    """Fair-share differs from takeover exactly where an unexplored child edge is at hand: it
    takes it (the paper's first preference) even when a larger sub-branch is open."""
    from swarmex.missions.roadmap.blackboard import WMABoard
    from swarmex.missions.roadmap.sim import build_roadmap
    from swarmex.missions.roadmap.wma_policy import WMAAgent

    rng = np.random.default_rng(0)
    rm = build_roadmap(clutter, "wma-rrt", cluster(1), 150, 10, rng)
    board = WMABoard(rm, 1)
    fair = WMAAgent(0, cluster(1)[0], board, "fairshare")
    take = WMAAgent(0, cluster(1)[0], board, "takeover")
    # a node with two or more children whose sub-branches differ in size
    node = next(v for v in range(1, rm.n_nodes) if len(board.children[v]) >= 2
                and len({int(board.rem_sub[e]) for e in board.children[v]}) > 1)
    kids = list(board.children[node])
    big = max(kids, key=lambda e: board.rem_sub[e])
    small = min(kids, key=lambda e: board.rem_sub[e])
    board.w_g[big] = 1  # the large sub-branch has been entered by someone, the small one not
    for a in (fair, take):
        a.node = node
    fair_pick = fair._choose_edge(np.random.default_rng(1))
    take_pick = take._choose_edge(np.random.default_rng(1))
    assert board.w_g[fair_pick] == 0
    assert take_pick == big and fair_pick != big
    assert small in kids


def test_coverage_grows_with_range(clutter):
    cov = [run_roadmap(clutter, cluster(3), nodes=100, step=10, sensor_range=r,
                       seed=0).raster.coverage() for r in (5, 20, math.inf)]
    assert cov[0] < cov[1] < cov[2]
    assert cov[2] > 0.95


def test_same_seed_same_record(clutter):
    recs = []
    for _ in range(2):
        run = run_roadmap(clutter, cluster(3), nodes=120, step=10, sensor_range=15, seed=9)
        d = build_record(run, {"task": "coverage"}, 9, 0.0).to_dict()
        d.pop("wall_seconds")
        recs.append(d)
    assert recs[0] == recs[1]


@pytest.mark.parametrize("planner", ["wma-rrt", "wma-rrt-fairshare"])
def test_any_policy_over_the_agents_choices_completes_every_edge(clutter, planner):
    """The choices an agent offers another policy (``choice``/``carry_out``, what the
    PettingZoo env exposes) keep the paper's guarantee: whatever is picked among them, the run
    completes with every edge travelled down and back and every branch COMPLETE."""
    from swarmex.missions.roadmap.wma_policy import WAIT

    picker = np.random.default_rng(99)
    offered = {"edge": 0, "branch": 0}

    def random_policy(agent, t, rng):
        choice = agent.choice()
        if choice is None:
            return agent.decide(t, rng)
        offered[choice.kind] += 1
        assert len(set(choice.options)) == len(choice.options) > 1
        option = choice.options[int(picker.integers(len(choice.options)))]
        if choice.kind == "branch":
            assert choice.options[-1] == WAIT
        return agent.carry_out(choice, option)

    run = run_roadmap(clutter, cluster(3), planner=planner, nodes=150, step=10,
                      sensor_range=15, seed=5, decide=random_policy)
    b = run.board
    assert offered["edge"] > 10 and offered["branch"] > 0
    assert run.complete and np.all(b.weight == COMPLETE)
    assert np.all(b.traversals >= 2)
    assert all(a.state == "done" and a.node == 0 for a in run.agents)


def test_carry_out_refuses_an_option_not_offered(clutter):
    from swarmex.missions.roadmap.blackboard import WMABoard
    from swarmex.missions.roadmap.sim import build_roadmap
    from swarmex.missions.roadmap.wma_policy import Choice, WMAAgent

    rm = build_roadmap(clutter, "wma-rrt", cluster(1), 40, 10, np.random.default_rng(0))
    agent = WMAAgent(0, cluster(1)[0], WMABoard(rm, 1))
    with pytest.raises(ValueError, match="not one of"):
        agent.carry_out(Choice("edge", (1, 2)), 3)


def test_a_roadmap_of_a_billion_nodes_is_refused_before_it_is_built():
    from pathlib import Path

    import swarmex

    fig8 = Path(__file__).resolve().parents[3] / "examples" / "roadmap_fig8.json"
    with pytest.raises(swarmex.InputError, match="^nodes must be at most 1000000"):
        swarmex.run("roadmap", env=str(fig8), agents=2, nodes=10**9, step=20,
                    sensor_range="1eps")


def test_a_watching_callback_gets_only_the_frames_it_wants_and_the_run_is_the_same():
    """A progress bar on a large roadmap built a frame (every edge's count copied) at every
    step; a callback with ``wants(t)`` now gets only those, and the run does not change."""
    from pathlib import Path

    import swarmex
    from swarmex.missions.registry import get

    fig8 = Path(__file__).resolve().parents[3] / "examples" / "roadmap_fig8.json"
    opts = dict(env=str(fig8), agents=2, nodes=80, step=40, sensor_range="1eps", seed=1)

    class Watcher:
        def __init__(self) -> None:
            self.steps: list[int] = []

        def wants(self, t: int) -> bool:
            return t % 10 == 0

        def __call__(self, frame) -> None:
            self.steps.append(frame.step)

    w = Watcher()
    watched = swarmex.run("roadmap", **opts, on_frame=w).to_dict()
    plain = swarmex.run("roadmap", **opts).to_dict()
    watched.pop("wall_seconds"), plain.pop("wall_seconds")
    assert watched == plain
    last = int(plain["makespan"])
    assert w.steps == sorted({0, *range(10, last, 10), last})  # wanted steps and the end
    mission = get("roadmap")
    params = mission.params(opts)
    spec = mission.progress(params, mission.prepare(params))
    frames = []
    swarmex.run("roadmap", **opts, on_frame=frames.append)
    assert spec.unit == "edges travelled" and spec.total == 80
    assert spec.count(frames[-1]) == 80  # coverage ends with every edge travelled


def _free_agent(clutter, n, weight, left):
    """A free paper-rule agent on a board of ``n`` branches with the given ``Weight``s."""
    from swarmex.missions.roadmap.blackboard import WMABoard
    from swarmex.missions.roadmap.sim import build_roadmap
    from swarmex.missions.roadmap.wma_policy import WMAAgent

    rm = build_roadmap(clutter, "wma-rrt", cluster(n), 60, 10, np.random.default_rng(0))
    board = WMABoard(rm, n)
    agent = WMAAgent(0, cluster(n)[0], board)
    board.weight[:] = weight
    agent.left = left
    return agent


def test_a_free_agent_does_not_go_back_into_the_branch_it_left(clutter):
    """Paper rule: a free agent helps another open branch, never the one it just left (even
    when that one has the least Weight), and waits (-1) when the one it left is all that is open."""
    agent = _free_agent(clutter, 3, [1.0, 3.0, COMPLETE], left=0)
    picks = {agent._pick_branch(np.random.default_rng(s)) for s in range(100)}
    assert picks == {1}
    agent = _free_agent(clutter, 3, [1.0, 1.0, 3.0], left=0)  # tied with the left branch
    picks = {agent._pick_branch(np.random.default_rng(s)) for s in range(100)}
    assert picks == {1}
    agent = _free_agent(clutter, 3, [1.0, COMPLETE, COMPLETE], left=0)
    assert {agent._pick_branch(np.random.default_rng(s)) for s in range(20)} == {-1}


def test_a_free_agent_helps_the_open_branch_of_least_weight(clutter):
    """Paper rule: a free agent helps the open branch of least Weight, drawing uniformly
    among the tied minima only (the expected set is the argmin over the board's open branches)."""
    agent = _free_agent(clutter, 3, [3.0, 1.0, 5.0], left=-1)
    assert {agent._pick_branch(np.random.default_rng(s)) for s in range(50)} == {1}

    weight = np.array([3.0, 1.0, COMPLETE, 1.0, 5.0])
    agent = _free_agent(clutter, 5, weight, left=-1)
    open_ = np.flatnonzero(weight != COMPLETE)
    want = set(open_[weight[open_] == weight[open_].min()].tolist())
    assert want == {1, 3}
    picks = [agent._pick_branch(np.random.default_rng(s)) for s in range(200)]
    assert set(picks) == want
    assert 60 < picks.count(1) < 140  # both tied minima drawn, about evenly


def test_takeover_free_agent_waits_when_no_branch_has_unexplored_edges(clutter):
    """Takeover rule (module docstring): a free agent picks the branch of largest share
    ``rem_sub / (busy + 1)``, and waits (-1) when no open branch has unexplored edges left."""
    agent = _free_agent(clutter, 3, [1.0, 1.0, 1.0], left=-1)
    agent.rule = "takeover"
    b = agent.board
    b.rem_sub[b.first_edge] = 0
    assert {agent._pick_branch(np.random.default_rng(s)) for s in range(20)} == {-1}
    b.rem_sub[b.first_edge[2]] = 4
    assert {agent._pick_branch(np.random.default_rng(s)) for s in range(20)} == {2}


def test_paper_rule_joins_the_least_odd_frontier_and_skips_even_finished_edges(clutter):
    """The paper's rule with no unexplored child: an odd global weight marks a frontier
    another agent is still beneath, so the agent joins it (the least odd weight); an even
    weight is a finished sub-branch and is never re-entered; with no odd child it goes
    back along its dedicated weight-1 edge (the module docstring's resolution)."""
    from swarmex.missions.roadmap.blackboard import WMABoard
    from swarmex.missions.roadmap.sim import build_roadmap
    from swarmex.missions.roadmap.wma_policy import WMAAgent

    rng = np.random.default_rng(0)
    rm = build_roadmap(clutter, "wma-rrt", cluster(1), 150, 10, rng)
    board = WMABoard(rm, 1)
    agent = WMAAgent(0, cluster(1)[0], board)  # the paper's rule
    node = next(v for v in range(1, rm.n_nodes) if len(board.children[v]) >= 3)
    kids = list(board.children[node])
    agent.node = node
    a, b, c = kids[:3]
    for e in kids:
        board.w_g[e] = 2  # every child finished
    board.w_g[a], board.w_g[b], board.w_g[c] = 5, 3, 4
    picks = {agent._choose_edge(np.random.default_rng(s)) for s in range(20)}
    assert picks == {b}  # the least odd weight; 4 is even however small
    board.w_g[a] = 3  # two frontiers of the same weight: uniform between them
    picks = {agent._choose_edge(np.random.default_rng(s)) for s in range(40)}
    assert picks == {a, b}
    agent.w_d[a] = 1  # an edge it used since entering is no candidate
    assert {agent._choose_edge(np.random.default_rng(s)) for s in range(20)} == {b}
    board.w_g[b] = 2  # no odd child left: the way back
    assert agent._choose_edge(np.random.default_rng(0)) == node - 1
