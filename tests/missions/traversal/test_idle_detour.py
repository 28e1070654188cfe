"""A followed team plan's rules for its agents (``swarmex.missions.traversal.teamplan``):
``idle="stop"`` (an agent with no route of its own stops, saying ``leave``), ``detour``
(on the way to a distant planned vertex, a first step that is not a teammate's planned
vertex) and ``slack`` (the plan followed is the shared one after a pass that lowers its
sum).

What is pinned: the environment's ``retires`` says exactly when ``decide`` stops early
(checked at every decision of whole runs), and such stops happen; every job is still done,
under a perfect broadcast and over a lossy, range-limited radio (where a lost ``leave``
must not make the others leave a vertex to an agent that is gone); the on-time test on its
own; a detour step avoids a teammate's vertex when an equally short step does, and only
then; the options are checked; with ``slack`` the shared plan is exactly the plan made
without it, and the followed one (every vertex once) differs from it on some decisions.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.comm.channel import Channel
from swarmex.missions.traversal import run_traversal, uniform_agents
from swarmex.missions.traversal.belief import TraversalBelief, route_cells
from swarmex.missions.traversal.followed import MadgtaS
from swarmex.missions.traversal.teamplan import MadgtaP, _holders_on_time
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import empty_grid, random_obstacles


class _Witness(MadgtaS):
    """madgta-s that asks ``retires`` before every decision, as traversal_v0 does."""

    def __init__(self, **options: object) -> None:
        super().__init__(**options)
        self.retired = 0
        self.mismatch = 0

    def decide(self, belief, rng):
        retires = self.retires(belief)
        d = super().decide(belief, rng)
        self.retired += retires
        self.mismatch += retires and d.kind != "finish"
        return d


def _free_mask_done(run, world) -> bool:
    free = ~world.blocked
    return bool((run.job_count[free] >= 1).all() and (run.job_count[~free] == 0).all())


@pytest.mark.parametrize("seed", [4, 5])
def test_retires_is_when_decide_stops_and_every_job_is_done(seed):
    world = random_obstacles(5, 5, 0.15, seed=seed)
    agents = uniform_agents([int(np.nonzero(~world.blocked)[0][0])] * 3, 2.0, 9.0)
    policy = _Witness()  # madgta-s: idle="stop"
    run = run_traversal(world, agents, policy, seed=seed)
    assert policy.retired >= 1 and policy.mismatch == 0
    assert run.complete and _free_mask_done(run, world)
    plain = _Witness(idle="madgta")  # never retires, sends no leave
    base = run_traversal(world, agents, plain, seed=seed)
    assert plain.retired == 0 and base.complete


@pytest.mark.parametrize(
    "channel", [Channel(loss=0.3), Channel(loss=0.3, range=3.0), Channel(delay=2.0)],
    ids=["lossy", "lossy-short", "delayed"],
)
def test_every_job_is_done_over_an_imperfect_radio(channel):
    world = random_obstacles(8, 8, 0.15, seed=2)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(v) for v in free[:4]], 2.0, 9.0)
    retired = 0
    for seed in range(3):
        policy = _Witness()
        run = run_traversal(world, agents, policy, seed=seed, channel=channel)
        assert run.complete and _free_mask_done(run, world), (channel, seed)
        retired += policy.retired
    assert retired >= 1  # agents did stop early on this radio, and no vertex was left


def _belief(now: float) -> TraversalBelief:
    world = empty_grid(4, 4)
    belief = TraversalBelief(1, 3, KnownGraph(world.graph), np.ones(4), np.ones(4))
    belief.now = now
    belief.loc[1:] = [0, 5, 10]
    belief.free_at[1:] = [now, now + 2.0, now + 3.0]
    return belief


def test_a_route_holder_must_be_heard_and_on_time():
    routes = np.full((4, 3), -1, dtype=np.int64)
    routes[2, :2] = [6, 7]
    routes[3, :1] = [11]
    lens = np.array([0, 0, 2, 1])
    belief = _belief(10.0)
    assert _holders_on_time(belief, routes, lens)
    belief.free_at[3] = 10.0  # its announced event is now: maybe it stopped unheard
    assert not _holders_on_time(belief, routes, lens)
    belief = _belief(10.0)
    belief.loc[2] = -1  # it left
    assert not _holders_on_time(belief, routes, lens)
    belief = _belief(10.0)
    belief.free_at[1] = 0.0  # me (no route): my own time does not matter
    lens[1] = 0
    assert _holders_on_time(belief, routes, lens)


def test_a_detour_step_avoids_a_teammates_vertex_only_when_it_can():
    belief = _belief(0.0)
    belief.loc[1] = 0  # me at (0, 0); f = 5 at (1, 1): first steps 1 and 4, equally short
    policy = MadgtaP(follow=True, detour=True)
    rng = np.random.default_rng(0)
    theirs = np.zeros(16, dtype=bool)
    for taken, expect in ((1, {4}), (4, {1})):
        theirs[:] = False
        theirs[taken] = True
        picks = {policy._towards(belief, 5, rng, theirs).node for _ in range(20)}
        assert picks == expect
    theirs[[1, 4]] = True  # both are theirs: any shortest step still goes
    picks = {policy._towards(belief, 5, rng, theirs).node for _ in range(40)}
    assert picks == {1, 4}
    picks = {policy._towards(belief, 5, rng, None).node for _ in range(40)}
    assert picks == {1, 4}


def test_the_options_are_checked():
    with pytest.raises(ValueError, match="idle must be one of madgta, stop"):
        MadgtaP(follow=True, idle="wait")
    with pytest.raises(ValueError, match="need follow"):
        MadgtaP(idle="stop")
    with pytest.raises(ValueError, match="need follow"):
        MadgtaP(detour=True)
    with pytest.raises(ValueError, match="commit"):
        MadgtaP(follow=True, commit=True, idle="stop")
    with pytest.raises(ValueError, match="slack and trade must be >= 0"):
        MadgtaP(slack=-1.0)
    with pytest.raises(ValueError, match="slack and trade must be >= 0"):
        MadgtaS(trade=-0.5)
    assert MadgtaS(idle="stop").announce_leave and not MadgtaS(idle="madgta").announce_leave


class _SlackWitness(MadgtaS):
    """madgta-s that, at every end-game decision, also makes the plan without the sum pass
    (``slack=0``) from the same belief, to compare."""

    def __init__(self, **options: object) -> None:
        super().__init__(**options)
        self._lexical = MadgtaS(slack=0.0)
        self.planned = 0
        self.moved = 0  # decisions whose followed plan is not the shared one

    def _plan(self, belief, vacant):
        p = super()._plan(belief, vacant)
        q = self._lexical._plan(belief, vacant)
        assert np.array_equal(p.routes, q.routes) and np.array_equal(p.lens, q.lens)
        assert np.array_equal(q.own, q.routes) and np.array_equal(q.own_lens, q.lens)
        planned = np.sort(p.routes[route_cells(p.lens, p.routes.shape[1])])
        assert np.array_equal(planned, np.sort(p.own[route_cells(p.own_lens, p.own.shape[1])]))
        self.planned += 1
        self.moved += not (np.array_equal(p.own, p.routes) and np.array_equal(p.own_lens, p.lens))
        return p


@pytest.mark.parametrize(("size", "seed"), [(4, 2), (6, 1)])
def test_the_sum_pass_changes_the_followed_plan_not_the_shared_one(size, seed):
    """``slack``: the plan an agent shares (and the team searches on) is the min-max one,
    exactly the plan made without the sum pass; the agent follows that plan after the sum
    pass, which keeps every vertex planned once and does change it on these runs."""
    world = random_obstacles(size, size, 0.15, seed=seed)
    agents = uniform_agents([int(np.nonzero(~world.blocked)[0][0])] * 3, 2.0, 9.0)
    policy = _SlackWitness()
    run = run_traversal(world, agents, policy, seed=seed)
    assert run.complete and _free_mask_done(run, world)
    assert policy.planned > 0 and policy.moved > 0
