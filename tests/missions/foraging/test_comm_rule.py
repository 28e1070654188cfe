"""The communication rules of :mod:`swarmex.missions.foraging.comm`: the seed's (no robot
knows what it was not told or cannot see) and the older omniscient one."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.foraging import comm as C
from swarmex.missions.foraging.run import run_forage


def test_finder_tells_all_neighbours_a_told_robot_all_but_its_teller():
    informed = [True, False, True, False]
    assert C.first_targets(C.SEED, [1, 2], None, informed) == [1, 2]
    assert C.first_targets(C.SEED, [0, 3], 0, informed) == [3]
    # the omniscient rule also leaves out robots that already know (here 2)
    assert C.first_targets(C.OMNISCIENT, [1, 2], None, informed) == [1]
    # Spiral with 4 or 8 robots: the word goes one way round the ring (the finder's successor)
    assert C.one_way(C.SEED, "spiral", 8) and not C.one_way(C.SEED, "spiral", 16)
    assert C.first_targets(C.SEED, [3, 1], None, informed, one_way=True) == [1]


def test_seed_rule_crosses_off_only_what_the_robot_knows_or_sees():
    """Robot 0 must tell 1 and 2. Robot 2 has learned from robot 3 far away: under the seed
    rule robot 0 cannot know that, so 2 stays on its list; the omniscient rule drops it."""
    pos = [(10, 10), (11, 10), (30, 30), (31, 30)]
    where = {1: (11, 10), 2: (30, 30)}  # the patterns put 1 and 2 where they are
    informed = [True, True, True, True]
    word = C.Word(4)
    word.learn(3, 5, None, [2])
    word.learn(0, 6, None, [1, 2])
    word.learn(2, 7, 3, [])
    word.learn(1, 7, 0, [])
    # robot 0 meets robot 1 (distance 1): they exchange, 0 now knows 1 knows
    word.exchange(C.adjacent_pairs(pos, [0, 1]))
    seed_lists = [[1, 2], [], [], []]
    C.cross_off(C.SEED, seed_lists, informed, pos, where.__getitem__, [0], word)
    assert word.settled(0, 1) and not word.settled(0, 2)  # 0 never heard of robot 3's news
    assert seed_lists[0] == [2]
    # once 1 and 2's news reach 0 (here: 0 meets 2), it is crossed off as well
    word.exchange([(0, 2)])
    C.cross_off(C.SEED, seed_lists, informed, pos, where.__getitem__, [0], word)
    assert seed_lists[0] == []
    omni = [[1, 2], [], [], []]
    C.cross_off(C.OMNISCIENT, omni, informed, pos, where.__getitem__, [0])
    assert omni[0] == []


def test_absent_robot_is_crossed_off_only_when_seen_missing():
    # robot 0 stands next to where 1's pattern puts it, and 1 is not there: it left its route,
    # which only a robot that knows the food does
    assert C.absent((5, 5), (20, 20), (5, 6))
    assert not C.absent((5, 5), (5, 7), (5, 6))  # next to its expected cell: still there
    assert not C.absent((0, 0), (20, 20), (5, 6))  # too far to see


def test_meet_goal_heads_for_the_earliest_meeting():
    future = np.array([[10 - t, 0] for t in range(10)])  # walking toward us
    # from (0, 0) the earliest t with |me - future[t]| - 1 <= t is t = 5 (cell (5, 0))
    assert C.meet((0, 0), future) == 5
    assert C.meet_goal((0, 0), (10, 0), future) == (5, 0)
    # a neighbour seen next to its expected cell when the meeting is now: go to it
    assert C.meet_goal((5, 5), (5, 7), np.array([[5, 6]])) == (5, 7)


@pytest.mark.parametrize("algorithm", ["zigzag", "sectors"])
def test_thesis_42_four_robots_enter_transport_together(algorithm):
    """§4.2: with four ZigZag robots (Sectors with 4 is ZigZag) the word goes round on the
    regular meetings and all four enter Transportation in the same round."""
    run = run_forage(algorithm, 32, 4, (3, 20), 6, "relay-food")
    done = run.outcome.comm_done
    assert None not in done and len(set(done)) == 1
    assert run.metrics["comm_transport_overlap"] == 0


def _comm_end(run) -> int:
    """Rounds from the discovery until the last robot has finished communicating."""
    return run.metrics["communication_time"] + run.metrics["comm_transport_overlap"]


def test_seed_rule_takes_longer_than_the_omniscient_one():
    """Knowing less delays the end of the communication phase (the seed rule's robots walk to
    neighbours that may already know, and ZigZag/Hilbert robots finish their route first);
    the rules agree where the route meetings carry the word (Strips). Spiral with 8 robots is
    left out: its one-way chain (seed rule) ends the first robot's phase sooner."""
    cells = [(3, 20), (28, 4), (25, 27), (6, 6), (16, 30)]
    for algorithm, n in (("hilbert", 16), ("zigzag", 16), ("sectors", 8)):
        seed = sum(_comm_end(run_forage(algorithm, 32, n, f, 6)) for f in cells)
        omni = sum(_comm_end(run_forage(algorithm, 32, n, f, 6, comm="omniscient")) for f in cells)
        assert seed > omni, algorithm
    s = run_forage("strips", 32, 4, (28, 4), 6)
    o = run_forage("strips", 32, 4, (28, 4), 6, comm="omniscient")
    assert s.outcome.comm_done == o.outcome.comm_done


@pytest.mark.parametrize(("algorithm", "n", "keeps"), [
    ("hilbert", 4, False),  # ch. 4: shortest path to the neighbour; §7.1: fast with 4
    ("hilbert", 16, True),  # the author's simulator, which Figs. 78-79 match at 16
    ("zigzag", 4, True),  # §4.2: "keeps following its exploration path"
    ("zigzag", 16, True),
    ("sectors", 8, False),  # §4.4: plans the meeting at once
])
def test_which_robots_finish_their_route_before_telling(algorithm, n, keeps):
    assert C.keeps_route(C.SEED, algorithm, False, True, n) is keeps
    assert C.keeps_route(C.SEED, algorithm, False, False, n) is False  # still deploying


def test_hilbert_with_four_robots_is_not_all_in_transport_at_once():
    # Figs. 78-79 give Hilbert-4 a non-zero COMM+TRANS: its robots leave communication at
    # different rounds (finishing their routes first, all four left it together: 0)
    cells = [(3, 20), (28, 4), (25, 27), (6, 6), (16, 30)]
    overlap = [run_forage("hilbert", 32, 4, f, 6).metrics["comm_transport_overlap"]
               for f in cells]
    assert sum(overlap) > 0


def test_best_order_keeps_the_first_of_equally_early_orders():
    """Among orders of the neighbours that complete in the same round, ``best_order`` keeps
    the first in ``permutations`` order: the tie-break changes whole runs, so it is pinned."""
    from itertools import permutations

    futures = {1: np.array([[3, 0]]), 2: np.array([[0, 3]]), 3: np.array([[-3, 0]])}

    def future_of(b, t):
        return futures[b]

    def completion(order):  # brute force: walk the order meeting by meeting
        tc, p = 0, (0, 0)
        for b in order:
            fut = future_of(b, tc)
            tau = C.meet(p, fut)
            tc += tau
            p = tuple(int(v) for v in fut[min(tau, len(fut) - 1)])
        return tc

    for targets in ([1, 2], [2, 1], [1, 3, 2]):
        ends = {perm: completion(perm) for perm in permutations(targets)}
        least = min(ends.values())
        ties = [list(perm) for perm, tc in ends.items() if tc == least]
        assert len(ties) >= 2  # the case is a real tie
        assert C.best_order((0, 0), 0, targets, future_of) == (ties[0], least)


def test_word_exchange_goes_both_ways_from_the_snapshot():
    """Word.exchange: two informed robots at distance 1 merge what each knew *before* this
    Look, both ways; news does not travel two hops in one Look along a chain of pairs."""
    word = C.Word(4)
    word.learn(0, 1, None, [])
    word.learn(2, 1, None, [])
    word.learn(3, 2, 2, [])  # 3 learned from 2: 2 and 3 know each other
    word.exchange([(0, 1), (1, 2)])  # 1 knows nothing yet: it gets 0's and 2's sets
    assert word.knows(1, 0) and word.knows(1, 2) and word.knows(1, 3)
    assert not word.knows(0, 2)  # one hop only: 2's news does not reach 0 through 1 yet
    word.exchange([(0, 2)])
    assert word.knows(0, 2) and word.knows(0, 3)  # 0 gets 2's set ...
    assert word.knows(2, 0)  # ... and 2 gets 0's
    assert not word.knows(3, 0)  # 3 was not in the pair


def test_adjacent_pairs_include_vertical_and_horizontal_neighbours_only():
    """Robots at distance 1 exchange, whether side by side in x or in y; a diagonal pair is
    at distance 2 and does not."""
    pos = [(5, 5), (6, 5), (5, 6), (6, 7), (9, 9)]
    got = {frozenset(p) for p in C.adjacent_pairs(pos, [0, 1, 2, 3, 4])}
    assert got == {frozenset((0, 1)), frozenset((0, 2))}
    assert {frozenset(p) for p in C.adjacent_pairs([(2, 3), (2, 4)], [0, 1])} == {
        frozenset((0, 1))
    }


def test_one_way_finder_tells_only_its_successor():
    """Spiral with 4 or 8 robots (seed rule): the finder tells only its last listed
    neighbour, its successor on the ring; a robot told by one neighbour tells the other."""
    informed = [False] * 8
    assert C.one_way(C.SEED, "spiral", 4)
    assert C.first_targets(C.SEED, [7, 1], None, informed, one_way=True) == [1]
    assert C.first_targets(C.SEED, [5, 3, 6], None, informed, one_way=True) == [6]
    assert C.first_targets(C.SEED, [0, 2], 0, informed, one_way=True) == [2]


def test_a_held_up_neighbour_is_predicted_where_its_route_put_it_delay_rounds_ago():
    """``predicted``: the pattern's position at round ``t`` shifted by the ``delay`` rounds
    the robot was held up, i.e. its timetable at ``t - delay`` (not before round 0, and
    halted at ``t_end``)."""
    pos = np.array([[x, 0] for x in range(10)])  # one cell east per round, rounds 0 .. 9
    assert C.predicted(pos, 9, 0, 5) == (5, 0)
    assert C.predicted(pos, 9, 2, 5) == (3, 0)  # held up 2 rounds: 2 cells behind
    assert C.predicted(pos, 9, 7, 5) == (0, 0)  # not yet left: its first cell
    assert C.predicted(pos, 9, 2, 30) == (9, 0)  # route over: halted at its end
