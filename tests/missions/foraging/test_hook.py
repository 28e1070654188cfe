"""The hooked run's move rules (missions/foraging/hook.py) and its generator protocol."""

import numpy as np
import pytest

from swarmex.missions.foraging.hook import drive, hooked_options, seed_moves
from swarmex.missions.foraging.run import forage_rounds, run_forage
from swarmex.missions.foraging.sim import Compute


def test_seed_moves_are_the_directions_of_the_first_wishes():
    pos = [(3, 3), (3, 3), (3, 3), (3, 3), (3, 3)]
    opts = [[(3, 3)], [(3, 2)], [(4, 3), (3, 3)], [(3, 4)], [(2, 3)]]
    assert seed_moves(pos, opts).tolist() == [0, 1, 2, 3, 4]


def test_a_changed_move_becomes_that_cell_else_stay_without_rank():
    pos = [(0, 0), (2, 2)]
    opts = [[(1, 0)], [(2, 1), (3, 2)]]
    following = [True, True]
    builtin = seed_moves(pos, opts)
    same, ranks = hooked_options(pos, opts, following, builtin, builtin, 4)
    assert same == [[(1, 0), (0, 0)], [(2, 1), (3, 2), (2, 2)]] and ranks == following
    moved, ranks = hooked_options(pos, opts, following, builtin, np.array([3, 0]), 4)
    assert moved == [[(0, 1), (0, 0)], [(2, 2)]] and ranks == [False, False]
    assert opts == [[(1, 0)], [(2, 1), (3, 2)]]  # the seed's lists are not changed
    with pytest.raises(ValueError, match="leaves the 4×4 grid"):
        hooked_options(pos, opts, following, builtin, np.array([4, 1]), 4)
    with pytest.raises(ValueError, match="not a move code"):
        hooked_options(pos, opts, following, builtin, np.array([3, 7]), 4)


def test_the_generator_stepped_by_hand_equals_run_forage():
    """Stepping forage_rounds with send() (as the env does) gives run_forage's positions."""
    args = ("sectors", 12, 4, (8, 3), 3, "relay-food")
    rounds = forage_rounds(*args)
    request = next(rounds)
    asks = 0
    try:
        while True:
            assert isinstance(request, Compute) and request.t == asks
            asks += 1
            request = rounds.send(request.builtin)
    except StopIteration as stop:
        stepped = stop.value
    plain = run_forage(*args)
    assert asks == len(stepped.outcome.positions) - 1  # one Compute per round but the last
    np.testing.assert_array_equal(stepped.outcome.positions, plain.outcome.positions)
    assert stepped.metrics == plain.metrics


def test_drive_needs_a_decide_for_a_hooked_run():
    with pytest.raises(RuntimeError, match="needs a decide"):
        drive(forage_rounds("sectors", 12, 4, (8, 3), 3), None)


def _play(args, fast, seed, share, stop_at=300):
    """A hooked run stepped by hand: each robot makes its seed move with probability
    ``share``, else a random move that stays on the grid. Returns every Compute as seen
    (round, seed moves, positions and the Mission's lists) and the record."""
    from swarmex.missions.foraging.hook import STEPS
    from swarmex.missions.foraging.run import to_record

    g = args[1]
    rng = np.random.default_rng(seed)
    rounds = forage_rounds(*args, fast=fast, stop_at=stop_at)
    request = next(rounds)
    seen, compiled = [], [0, 0]  # rounds compiled before anyone knew, and in transport
    try:
        while True:
            m = request.mission
            if m._live is not None:
                compiled[all(mode == 3 for mode in m.mode)] += 1
            seen.append((request.t, request.builtin.tolist(), request.positions.tolist(),
                         list(m.pos), list(m.carrying), list(m.tmode), list(m.pidx),
                         dict(m.join_at), list(m.handovers), [list(j) for j in m.jobs],
                         m.delivered, m.units))  # fmt: skip
            moves = request.builtin.copy()
            for a, (x, y) in enumerate(request.positions.tolist()):
                if rng.random() >= share:
                    legal = [k for k, (dx, dy) in enumerate(STEPS)
                             if 0 <= x + dx < g and 0 <= y + dy < g]  # fmt: skip
                    moves[a] = legal[rng.integers(len(legal))]
            request = rounds.send(moves)
    except StopIteration as stop:
        record = to_record(stop.value, 0, {}).to_dict()
    record.pop("wall_seconds")
    return seen, record, compiled


@pytest.mark.parametrize(
    ("algorithm", "transport", "g", "n"),
    [("sectors", "relay-food", 8, 4), ("strips", "end-to-end", 8, 4),
     ("spiral", "relay-path", 6, 8), ("zigzag", "relay-food", 8, 16)],
)  # fmt: skip
def test_the_compiled_transport_rounds_are_the_python_rounds(algorithm, transport, g, n):
    """A hooked run's rounds played compiled — before anyone knows where the food is
    (fastloop.explore_round) and once everyone transports (fastloop.hooked_round) — give,
    round by round, the Computes, the Mission's state and the record of the Python rounds
    (Mission.hooked_step), under the seed's moves, random moves and mixes of both, truncated
    runs (stop_at) included."""
    compiled = np.zeros(2, dtype=int)
    for seed, share in [(0, 0.0), (1, 0.5), (2, 0.9), (3, 1.0)]:
        food = (1, 2) if seed % 2 else (g - 2, 1)
        args = (algorithm, g, n, food, 3, transport)
        fast = _play(args, True, seed, share)
        slow = _play(args, False, seed, share)
        assert fast[:2] == slow[:2]
        assert slow[2] == [0, 0]
        compiled += fast[2]
    assert compiled.min() > 10  # both compiled phases were played


@pytest.mark.parametrize(
    ("algorithm", "n"),
    [("hilbert", 4), ("rings", 4), ("loop-strips", 4), ("modified-zigzag", 8), ("sectors", 16)],
)
def test_the_compiled_rounds_of_other_patterns_are_the_python_rounds(algorithm, n):
    """The same comparison for the remaining patterns (random and mixed moves)."""
    compiled = np.zeros(2, dtype=int)
    for seed, (share, transport) in enumerate([(0.3, "relay-path"), (0.95, "end-to-end")]):
        args = (algorithm, 8, n, (6, 2), 3, transport)
        fast = _play(args, True, seed, share)
        assert fast[:2] == _play(args, False, seed, share)[:2]
        compiled += fast[2]
    assert compiled.min() > 0


def test_a_bad_move_in_a_compiled_round_raises_as_in_python():
    for fast in (True, False):  # exploring: every robot is in the nest (4, 4)
        rounds = forage_rounds("sectors", 8, 4, (6, 1), 3, "end-to-end", fast=fast)
        request = next(rounds)
        assert (request.mission._live is not None) == fast
        moves = request.builtin.copy()
        moves[1] = 7
        with pytest.raises(ValueError, match="robot 1: move 7 is not a move code"):
            rounds.send(moves)
    for fast in (True, False):
        rounds = forage_rounds("sectors", 8, 4, (6, 1), 3, "end-to-end", fast=fast)
        request = next(rounds)
        while any(m != 3 for m in request.mission.mode):  # until everyone transports
            request = rounds.send(request.builtin)
        request = rounds.send(request.builtin)  # the first round that starts so
        assert (request.mission._live is not None) == fast
        a = 2
        x, y = request.positions[a]
        off = 1 if y == 0 else 2 if x == 7 else 3 if y == 7 else 4 if x == 0 else None
        moves = request.builtin.copy()
        if off is None:  # not on the border: a code that is no move
            moves[a] = 9
            why = "robot 2: move 9 is not a move code"
        else:
            moves[a] = off
            why = f"robot 2: move {off} from \\({x}, {y}\\) leaves the 8×8 grid"
        with pytest.raises(ValueError, match=why):
            rounds.send(moves)
