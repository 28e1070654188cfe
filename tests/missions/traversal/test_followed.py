"""``madgta-f`` (swarmex.missions.traversal.followed): madgta-k with the size gate whose
agents follow their own searched, kept end-game plan once a wall is known.

What is pinned: the name selects it everywhere a traversal algorithm is chosen; it is
madgta-k with its documented settings, run for run; on an open lattice it is madgta-k's
rollout (the plan is not followed); behind walls it follows the plan and completes every
job once, over a perfect and a lossy, range-limited channel.
"""

from __future__ import annotations

import numpy as np
import pytest

import swarmex
from swarmex.comm.channel import Channel
from swarmex.missions.traversal import make_policy, run_metrics, run_traversal, uniform_agents
from swarmex.missions.traversal.followed import MadgtaF, MadgtaS
from swarmex.missions.traversal.partition import MadgtaK
from swarmex.missions.traversal.policies import POLICIES
from swarmex.worlds import empty_grid, random_obstacles


def _team(world, m: int) -> list:
    free = np.nonzero(~world.blocked)[0]
    return uniform_agents([int(v) for v in free[:m]], 2.0, 9.0)


def test_registered_and_selectable():
    assert POLICIES["madgta-f"] is MadgtaF
    policy = make_policy("madgta-f")
    assert isinstance(policy, MadgtaK) and policy.name == "madgta-f"
    assert (policy.follow, policy.ils, policy.keep) == ("walls", 30, True)
    assert policy.sweep.tip_per_agent == 60
    with pytest.raises(ValueError, match="follow"):
        MadgtaF(follow="sometimes")


def test_is_madgta_k_with_its_settings_run_for_run():
    world = random_obstacles(14, 14, 0.2, seed=2)
    agents = _team(world, 5)
    ours = run_traversal(world, agents, MadgtaF(), seed=2)
    spelled = run_traversal(world, agents, MadgtaK(tip_per_agent=60, follow="walls", ils=30,
                                                   keep=True), seed=2)
    assert ours.path_strings() == spelled.path_strings()


def test_on_an_open_lattice_it_is_madgta_k():
    world = empty_grid(9, 9)
    agents = uniform_agents([0] * 4, 2.0, 9.0)
    ours = run_traversal(world, agents, MadgtaF(), seed=5)
    assert ours.path_strings() == run_traversal(world, agents, MadgtaK(), seed=5).path_strings()


@pytest.mark.parametrize(
    "channel", [Channel(), Channel(loss=0.3, range=4.0), Channel(delay=3.0)],
    ids=["perfect", "lossy", "delayed"],
)
@pytest.mark.parametrize("kind", [MadgtaF, MadgtaS], ids=["madgta-f", "madgta-s"])
def test_behind_walls_it_follows_its_plan_and_completes(kind, channel):
    """madgta-f, and madgta-s whose plan travels over the same channel (late or not at all)."""
    world = random_obstacles(12, 12, 0.2, seed=1)
    policy = kind()
    run = run_traversal(world, _team(world, 5), policy, seed=1, channel=channel)
    assert run.complete and policy.plans > 0
    assert np.all(run.job_count[run.reachable] >= 1)
    if channel.perfect:
        assert run_metrics(run, 1.0)[0]["duplicate_jobs"] == 0
        rollout = run_traversal(world, _team(world, 5), MadgtaK(tip_per_agent=60), seed=1)
        assert run.path_strings() != rollout.path_strings()


def test_swarmex_run_selects_it_by_name():
    rec = swarmex.run("traversal", grid="8x7", obstacles="2,1;2,2;2,3;5,4", agents=3,
                      algorithm="madgta-f", seed=1).to_dict()
    assert rec["algorithm"] == "madgta-f" and rec["complete"]


def test_unknown_walled_plans_no_job_on_a_likely_wall(monkeypatch):
    """``madgta-f@unknown=walled``: the followed plan leaves out the unsensed vertices next
    to a known wall (docs/traversal-variants.md §7, "Tried and not kept"); every job is still
    done once, and on an open lattice nothing changes."""
    from swarmex.missions.traversal import teamplan

    seen: list[tuple[set[int], set[int]]] = []
    likely_now: list[set[int]] = []
    real_plan = teamplan._team_plan

    def plan(*args):
        seen.append(({int(v) for v in args[7]}, likely_now[-1]))
        return real_plan(*args)

    def likely_walls(belief) -> set[int]:
        """Written out cell by cell, apart from the policy's own helper: not known done, not
        a known wall, not sensed (no agent has stood on it or next to it) and next to a
        known wall."""
        g, blocked = belief.graph, belief.known.blocked
        stood = {v for v in range(g.n_nodes) if belief.status[v] > 0}
        stood |= {int(v) for v in belief.loc if v >= 0}
        sensed = stood | {int(u) for v in stood for u in g.neighbors(v)}
        return {v for v in range(g.n_nodes)
                if belief.status[v] == 0 and not blocked[v] and v not in sensed
                and any(blocked[u] for u in g.neighbors(v))}

    class Watching(MadgtaF):
        def decide(self, belief, rng):
            likely_now.append(likely_walls(belief))
            return super().decide(belief, rng)

    monkeypatch.setattr(teamplan, "_team_plan", plan)
    world = random_obstacles(16, 16, 0.25, seed=2)
    agents = _team(world, 5)
    run = run_traversal(world, agents, Watching(unknown="walled"), seed=2)
    assert run.complete and np.all(run.job_count[run.reachable] == 1)
    # (when every vacant vertex is a likely wall, the plan keeps them all)
    assert seen and all(not (planned & likely) or planned <= likely for planned, likely in seen)
    assert any(likely for _, likely in seen)  # the guess had something to leave out
    assert run.path_strings() != run_traversal(world, agents, MadgtaF(), seed=2).path_strings()
    open_grid = empty_grid(9, 9)
    team = uniform_agents([0] * 4, 2.0, 9.0)
    assert run_traversal(open_grid, team, MadgtaF(unknown="walled"), seed=5).path_strings() == \
        run_traversal(open_grid, team, MadgtaF(), seed=5).path_strings()
