"""``madgta-k`` (swarmex.missions.traversal.partition): a sweep kept to each agent's part of
a balanced partition of the vacant vertices, then madgta-p's end game.

What is pinned: it is registered and selectable; the partition is hand-checked on
corridors (Voronoi halves, the head start of a busy rival, the weights giving the smaller
part the vertex between two agents but not the region behind one); the policy completes
missions (identical and mixed teams, perfect and lossy channels), is madgta-p once every
decision is in the end game, never writes the belief and gives the same decision for the
same belief; compiled and interpreted kernels give the same run.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.comm.channel import Channel
from swarmex.missions.traversal import (
    make_policy,
    run_metrics,
    run_traversal,
    uniform_agents,
)
from swarmex.missions.traversal import partition as pt
from swarmex.missions.traversal.policies import POLICIES
from swarmex.missions.traversal.teamplan import MadgtaP
from swarmex.worlds import random_obstacles

from ._helpers import mixed_agents
from .checking import checking, jit_and_python_agree


def test_registered_and_selectable():
    assert POLICIES["madgta-k"] is pt.MadgtaK
    policy = make_policy("madgta-k")
    assert isinstance(policy, pt.MadgtaK) and isinstance(policy, MadgtaP)
    assert policy.name == "madgta-k" and not policy.madgta_branch2
    assert pt.MadgtaK(rounds=5, max_vacant=50).sweep.rounds == 5
    for bad in (dict(rounds=0), dict(passes=-1), dict(k=0)):
        with pytest.raises(ValueError):
            pt.MadgtaK(**bad)


def _parts(n: int, places: list[int], vacant: list[int], off: list[float] | None = None,
           rounds: int = 40) -> tuple[list[int], float]:
    """The partition kernel on corridor 0-1-...-(n-1) with agents at ``places``."""
    hops = np.abs(np.arange(n)[None, :] - np.asarray(places)[:, None]).astype(np.int16)
    assign = np.full(len(vacant), -1, dtype=np.int64)
    _, err = pt._balanced_parts(
        hops, np.arange(len(places), dtype=np.int64), np.asarray(vacant, dtype=np.int64),
        np.zeros(len(places)) if off is None else np.asarray(off, dtype=float), rounds,
        assign,
    )
    return assign.tolist(), err


def test_two_ends_of_a_corridor_split_it_in_halves():
    """Agents at 0 and 9, vertices 1..8 vacant: 1..4 are nearer 0, 5..8 nearer 9."""
    assert _parts(10, [0, 9], list(range(1, 9))) == ([0, 0, 0, 0, 1, 1, 1, 1], 0.0)


def test_a_busy_rival_has_a_head_start_against_it():
    """The same corridor, agent 2 busy for 2 more edges: vertex v costs v to agent 1 and
    9 - v + 2 to agent 2, so 1..5 go to agent 1 (5 against 3: imbalance 1, kept)."""
    assert _parts(10, [0, 9], list(range(1, 9)), off=[0.0, 2.0]) == (
        [0, 0, 0, 0, 0, 1, 1, 1], 1.0)


def test_weights_give_the_smaller_part_what_lies_between_not_what_lies_behind():
    """Corridor 0..12, agents at 0 and 4, vacant 1-3 and 5-12. Voronoi: 1 and 2 (a tie,
    lowest id) to agent 1, the other nine to agent 2 (imbalance 3.5). Round 1 moves the
    weights 2.39 hops apart, so 3 goes to agent 1 (3 against 8: 2.5). Every vertex past
    4 is 4 hops farther from agent 1 than from agent 2, so a weight can only move all of
    them at once (round 2: 11 against 0); the first partition of least imbalance is kept."""
    assign, err = _parts(13, [0, 4], [1, 2, 3, *range(5, 13)])
    assert assign == [0, 0, 0] + [1] * 8 and err == 2.5
    assert _parts(13, [0, 4], [1, 2, 3, *range(5, 13)], rounds=1) == ([0, 0] + [1] * 9, 3.5)


class _EarlyEndGame(pt.MadgtaK):
    """madgta-k whose end game starts at 20 vacant vertices, so that a small map has both
    phases (checking() builds it without arguments)."""

    def __init__(self) -> None:
        super().__init__(max_vacant=20)


@pytest.mark.parametrize("fleet", ["same", "mixed"])
@pytest.mark.parametrize("nests", ["shared", "own"])
def test_completes_every_job_once(fleet, nests):
    world = random_obstacles(14, 14, 0.2, seed=1)
    free = np.nonzero(~world.blocked)[0]
    starts = [int(free[0])] * 5 if nests == "shared" else [int(v) for v in free[:40:8]]
    agents = (uniform_agents(starts, 2.0, 9.0) if fleet == "same" else mixed_agents(world, 5, 1))
    policy = _EarlyEndGame()
    run = run_traversal(world, agents, policy, seed=1)
    assert run.complete and policy.sweep.parted > 0 and policy.plans > 0
    assert np.all(run.job_count[run.reachable] >= 1)
    assert run_metrics(run, 1.0)[0]["duplicate_jobs"] == 0


def test_completes_over_a_lossy_range_limited_channel():
    world = random_obstacles(12, 12, 0.2, seed=3)
    policy = _EarlyEndGame()
    run = run_traversal(world, mixed_agents(world, 4, 3), policy, seed=3,
                        channel=Channel(loss=0.3, range=4.0))
    assert run.complete and policy.sweep.parted > 0


def test_in_the_end_game_from_the_start_it_is_madgta_p_record_for_record():
    world = random_obstacles(12, 12, 0.2, seed=7)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(v) for v in free[:30:6]], 2.0, 9.0)
    ours = run_traversal(world, agents, pt.MadgtaK(max_vacant=1000), seed=7)
    theirs = run_traversal(world, agents, MadgtaP(max_vacant=1000), seed=7)
    assert ours.path_strings() == theirs.path_strings()
    assert run_metrics(ours, 1.0)[0] == run_metrics(theirs, 1.0)[0]


def test_the_sweep_changes_the_runs():
    """Not MADGTA in disguise: on a 14x14 map with own nests the sweep decides differently."""
    world = random_obstacles(14, 14, 0.2, seed=2)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(v) for v in free[:60:12]], 2.0, 9.0)
    ours = run_traversal(world, agents, pt.PartSweep(), seed=2)
    theirs = run_traversal(world, agents, "madgta", seed=2)
    assert ours.complete and ours.path_strings() != theirs.path_strings()


@pytest.mark.parametrize("base", [pt.PartSweep, _EarlyEndGame])
def test_never_writes_the_belief_and_is_deterministic(base):
    world = random_obstacles(12, 12, 0.2, seed=5)
    free = np.nonzero(~world.blocked)[0]
    spy = checking(base, 40)
    run = run_traversal(world, uniform_agents([int(v) for v in free[:40:10]], 2.0, 9.0), spy,
                        seed=5)
    assert run.complete and spy.checked > 20


def test_compiled_and_interpreted_give_the_same_run(tmp_path):
    code = """
    import json
    import numpy as np
    from swarmex.missions.traversal import run_traversal, run_metrics, uniform_agents
    from swarmex.missions.traversal.partition import MadgtaK
    from swarmex.worlds import random_obstacles
    world = random_obstacles(10, 10, 0.2, seed=2)
    free = np.nonzero(~world.blocked)[0]
    run = run_traversal(world, uniform_agents([int(v) for v in free[:40:10]], 2.0, 9.0),
                        MadgtaK(max_vacant=20), seed=2)
    print(json.dumps([run.path_strings(), run_metrics(run, 1.0)[0]["max_total_time"]]))
    """
    jit_and_python_agree(code, tmp_path)


# ---------------------------------------------------------------- the size gate (tip rule)


def _dead_end_belief():
    """A 4 x 3 grid (vertex = 4y + x), wall 0 known; agent 1 at 5 has done 5, 1 and 9;
    agent 2 stands at 8, done. Agent 1's vacant neighbours are 4 and 6. Vertex 4 is a tip
    (besides 5 its neighbours are the wall 0 and the done 8: no vacant one); 6 is not (2
    and 7 are vacant). Vacant in the belief: 2, 3, 4, 6, 7, 10, 11 (seven)."""
    from swarmex.missions.traversal.belief import TraversalBelief
    from swarmex.planning.fieldcache import KnownGraph
    from swarmex.worlds import empty_grid

    world = empty_grid(4, 3)
    belief = TraversalBelief(1, 2, KnownGraph(world.graph), np.array([0.0, 2.0, 2.0]),
                             np.array([0.0, 9.0, 9.0]))
    belief.see_obstacles([0])
    for v, by in ((5, 1), (1, 1), (9, 1), (8, 2)):
        belief.mark_done(v, by)
    belief.loc[1], belief.loc[2] = 5, 8
    return belief


def test_tip_rule_takes_the_dead_end_where_madgta_spreads_away():
    """MADGTA's max-min: 4 is 1 hop from the rival, 6 is 3 (8-9-10-6), both 1 from agent 1,
    so util(4) = 0 and util(6) = 2 x 2 s: MADGTA moves to 6. With the gate open (7 vacant
    > 2 x 3 rows), the tip rule keeps only 4. At 3 per agent (9 >= 7) the gate is shut and
    the decision is madgta-k's partition sweep's, as without the option."""
    from swarmex.missions.traversal.policies import Madgta

    rng = np.random.default_rng(0)
    assert Madgta().decide(_dead_end_belief(), rng) == pt.Decision("move", 6, 6, 2)
    tip = pt.PartSweep(tip_per_agent=2)
    assert tip.decide(_dead_end_belief(), rng) == pt.Decision("move", 4, 4, 2)
    assert tip.tipped == 1 and tip.parted == 0
    shut = pt.PartSweep(tip_per_agent=3)
    assert (shut.decide(_dead_end_belief(), rng)
            == pt.PartSweep().decide(_dead_end_belief(), rng))
    assert shut.tipped == 0 and shut.parted == 1


def test_tip_rule_leaves_madgta_alone_when_every_or_no_neighbour_is_a_tip():
    """If 6 is a tip too (2 and 7 done: one vacant neighbour left, 10), both neighbours are
    tips and MADGTA decides (6). With no wall known (an open lattice) the rule is off."""
    belief = _dead_end_belief()
    belief.mark_done(2, 1)
    belief.mark_done(7, 1)
    tip = pt.PartSweep(tip_per_agent=0)
    assert tip.decide(belief, np.random.default_rng(0)) == pt.Decision("move", 6, 6, 2)
    assert tip.tipped == 0
    # no wall known: corner 0 would be a tip for an agent at 1 (its only other neighbour
    # is 4), but on an open lattice the rule does not apply
    from swarmex.missions.traversal.belief import TraversalBelief
    from swarmex.planning.fieldcache import KnownGraph
    from swarmex.worlds import empty_grid

    open_ = TraversalBelief(1, 1, KnownGraph(empty_grid(4, 3).graph), np.array([0.0, 2.0]),
                            np.array([0.0, 9.0]))
    open_.loc[1] = 1
    open_.mark_done(1, 1)
    tip.decide(open_, np.random.default_rng(0))
    assert tip.tipped == 0
    open_.see_obstacles([11])  # a wall far away: now the rule applies and takes 0
    assert tip.decide(open_, np.random.default_rng(0)) == pt.Decision("move", 0, 0, 2)
    assert tip.tipped == 1


def test_tip_gate_option_selects_and_defaults_off():
    assert pt.MadgtaK().sweep.tip_per_agent is None
    assert pt.MadgtaK(tip_per_agent=60).sweep.tip_per_agent == 60
    with pytest.raises(ValueError):
        pt.MadgtaK(tip_per_agent=-1)


class _TipGate(pt.PartSweep):
    """The sweep with the gate always open on a small map (checking() builds it bare)."""

    def __init__(self) -> None:
        super().__init__(tip_per_agent=0)


def test_tip_gate_completes_and_is_deterministic():
    world = random_obstacles(14, 14, 0.25, seed=4)
    free = np.nonzero(~world.blocked)[0]
    spy = checking(_TipGate, 60)
    run = run_traversal(world, uniform_agents([int(v) for v in free[:50:10]], 2.0, 9.0), spy,
                        seed=4)
    assert run.complete and spy.checked > 20 and spy.tipped > 0
    assert np.all(run.job_count[run.reachable] >= 1)
    again = run_traversal(world, uniform_agents([int(v) for v in free[:50:10]], 2.0, 9.0),
                          _TipGate(), seed=4)
    assert again.path_strings() == run.path_strings()
