"""``madgta-s`` (swarmex.missions.traversal.followed.MadgtaS): madgta-f whose agents share
one end-game team plan by broadcasting it.

What is pinned: the name selects it; under a perfect broadcast the plan messages give
exactly the runs of a team that keeps its plan in one common memory (an independent route:
no message, no belief, the policy's own store shared by key), and they are counted in the
record, bytes and all; over a lossy, range-limited or delayed channel every job is still
done (test_followed.py); a belief keeps the newest plan it hears; the networked runtime
carries the plan in its decisions' frames (its run is the simulated one:
tests/net/test_protocol.py, tests/e2e/test_net_traversal.py) and checks it, and an early
finisher's ``leave`` on its C09.
"""

from __future__ import annotations

import numpy as np
import pytest

import swarmex
from swarmex.missions.traversal import make_policy, run_traversal, uniform_agents
from swarmex.missions.traversal.belief import TeamPlan, TraversalBelief
from swarmex.missions.traversal.followed import MadgtaF, MadgtaS
from swarmex.missions.traversal.policies import POLICIES
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds import empty_grid, random_obstacles


def _team(world, m: int) -> list:
    free = np.nonzero(~world.blocked)[0]
    return uniform_agents([int(v) for v in free[:m]], 2.0, 9.0)


class _OneMemory(dict):
    """A kept-plan store with one slot for the whole team: every agent writes and reads the
    same plan. It counts the plans written and the bytes a ``plan`` message of each would
    take (14, plus 4 per planned vertex and 2 per route length)."""

    def __init__(self) -> None:
        super().__init__()
        self.plans = 0
        self.bytes = 0
        self.before: list = []  # what the slot held before each write

    def __setitem__(self, key, value) -> None:
        self.before.append(super().get(0))
        super().__setitem__(0, value)

    def get(self, key, default=None):
        return super().get(0, default)

    def settle(self, finished: bool) -> None:
        """After a decision: a finishing agent's plan is not shared (madgta-s sends a plan
        only with a job or a move), else it is counted as one message."""
        for old in self.before:
            if finished:
                if old is None:
                    self.pop(0)
                else:
                    super().__setitem__(0, old)
            else:
                lens = super().get(0)[1]
                self.plans += 1
                self.bytes += 14 + 4 * int(lens.sum()) + 2 * lens.size
        self.before.clear()


class _TeamMemory(MadgtaF):
    """madgta-s's settings without messages: madgta-f, followed everywhere, whose agents
    keep their plan in one common memory."""

    def __init__(self) -> None:
        super().__init__(follow=True, idle="stop", detour=True, slack=1.5)
        self._kept = _OneMemory()

    def decide(self, belief, rng):
        d = super().decide(belief, rng)
        self._kept.settle(d.kind == "finish")
        return d


def test_registered_and_selectable():
    assert POLICIES["madgta-s"] is MadgtaS
    policy = make_policy("madgta-s")
    assert isinstance(policy, MadgtaF) and policy.name == "madgta-s"
    assert (policy.follow, policy.share, policy.keep, policy.ils) == (True, True, True, 30)
    assert (policy.idle, policy.detour, policy.announce_leave) == ("stop", True, True)
    assert (policy.slack, policy.trade) == (1.5, 0.5)
    with pytest.raises(ValueError, match="share needs keep"):
        MadgtaS(keep=False)
    rec = swarmex.run("traversal", grid="8x7", obstacles="2,1;2,2;2,3;5,4", agents=3,
                      algorithm="madgta-s", seed=1).to_dict()
    assert rec["algorithm"] == "madgta-s" and rec["complete"]


@pytest.mark.parametrize(("world", "seed"), [
    (random_obstacles(14, 14, 0.2, seed=2), 2),
    (empty_grid(9, 9), 5),
], ids=["walls", "open"])
def test_messages_give_the_common_memory_runs_and_are_counted(world, seed):
    agents = _team(world, 5)
    ours = run_traversal(world, agents, MadgtaS(), seed=seed)
    memory = _TeamMemory()
    theirs = run_traversal(world, agents, memory, seed=seed)
    assert ours.complete and memory._kept.plans > 0
    assert ours.path_strings() == theirs.path_strings()
    assert ours.messages == theirs.messages + memory._kept.plans
    assert ours.message_bytes == theirs.message_bytes + memory._kept.bytes
    # and sharing changes the runs: each agent on its own plan moves differently
    alone = run_traversal(world, agents, MadgtaF(follow=True), seed=seed)
    assert alone.path_strings() != ours.path_strings()


def test_a_belief_keeps_the_newest_plan_it_hears():
    world = empty_grid(3, 3)
    belief = TraversalBelief(1, 2, KnownGraph(world.graph), np.ones(3), np.ones(3))
    assert belief.plan is None
    routes, lens = np.full((3, 2), -1, dtype=np.int64), np.zeros(3, dtype=np.int64)
    newer, older = TeamPlan(5.0, routes, lens), TeamPlan(4.0, routes, lens)
    belief.hear_plan(newer)
    belief.hear_plan(older)  # a delayed plan made before the one held
    assert belief.plan is newer
    latest = TeamPlan(5.0, routes.copy(), lens.copy())
    belief.hear_plan(latest)  # made at the same time, heard later: the team's last word
    assert belief.plan is latest


def test_the_networked_runtime_carries_the_plan_and_checks_it():
    """On the wire a plan rides on the decision it follows; the server refuses one with the
    wrong number of routes or a vertex off the map; over a lossy radio (serve
    --inject-loss) every vertex is still done."""
    from swarmex.net.traversal import Mission, check_broadcast, run_inprocess
    from swarmex.net.wire import Broadcast, EncodingError

    world = random_obstacles(8, 8, 0.15, seed=3)
    mission = Mission(world, _team(world, 3), algorithm="madgta-f@share=true", seed=2)
    cores, recorder = run_inprocess(mission, loss=0.3)
    free = ~world.blocked
    assert (recorder.job_count[free] >= 1).all() and (recorder.job_count[~free] == 0).all()
    heard = [core.belief.plan for core in cores.values()]
    assert all(p is not None for p in heard)  # every agent heard or made a plan
    ok = Broadcast("C05", 1, 3, t=1.0, eta=2.0, plan=(0.5, np.array([0, 1, 0, 1]),
                                                      np.array([5, 6])))
    check_broadcast(ok, mission)
    for plan, says in (((0.5, np.array([0, 1, 1]), np.array([5, 6])), "one route per agent"),
                       ((0.5, np.array([1, 0, 0, 1]), np.array([5, 6])), "one route per agent"),
                       ((0.5, np.array([0, 1, 0, 1]), np.array([5, 64])), "outside the map"),
                       ((0.5, np.array([0, 65, 0, 0]), np.zeros(65, dtype=np.int64)),
                        "more vertices than the map")):
        with pytest.raises(EncodingError, match=says):
            check_broadcast(Broadcast("C05", 1, 3, t=1.0, eta=2.0, plan=plan), mission)


@pytest.mark.parametrize("algorithm", ["madgta-h", "madgta-s@idle=stop,detour=true"])
def test_the_networked_runtime_carries_a_leave_on_the_finish(algorithm):
    """An agent that may stop while vertices remain (madgta-h; madgta-s with
    ``idle="stop"``) says ``leave``; on the wire it is its C09's job bit. The networked run is
    the simulated one, leaves counted as messages, and some agent did leave early."""
    from swarmex.missions.traversal.agents import AgentSpec
    from swarmex.net.traversal import Mission, run_inprocess

    world = random_obstacles(8, 8, 0.15, seed=1)
    free = np.nonzero(~world.blocked)[0]
    agents = [AgentSpec(int(free[0]), 0.4, 4.0), AgentSpec(int(free[1]), 0.9, 11.0),
              AgentSpec(int(free[2]), 0.6, 7.0), AgentSpec(int(free[3]), 0.5, 9.0)]
    run = run_traversal(world, agents, algorithm, seed=3)
    cores, recorder = run_inprocess(Mission(world, agents, algorithm, seed=3))
    for sim_log, (_, core) in zip(run.agents, sorted(cores.items()), strict=True):
        assert core.log.trajectory == sim_log.trajectory and core.log.jobs == sim_log.jobs
        assert core.log.finished_at == sim_log.finished_at
    assert recorder.messages == run.messages and run.complete
