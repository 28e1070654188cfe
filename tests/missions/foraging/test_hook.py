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
