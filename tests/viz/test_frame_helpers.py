"""Small pieces behind the animations and the monitor, checked on hand-made inputs whose
answers are worked out here: the exploration frame's frontier paint, the foraging frame's
carrying / delivered / left counts, and the monitor's JSON for non-finite floats."""

from __future__ import annotations

import json

import numpy as np

from swarmex.viz.exploration import FRONTIER, Snapshot, rgb_frame
from swarmex.viz.foraging import carried_units
from swarmex.viz.monitor.server import dumps


def test_exploration_frame_paints_known_free_cells_next_to_unknown_as_frontier():
    # 0 unknown, 1 free, 2 occupied
    known = np.array(
        [
            [1, 1, 1, 1],
            [1, 1, 2, 0],
            [1, 1, 1, 1],
            [0, 1, 1, 1],
        ],
        dtype=np.uint8,
    )
    expected = np.zeros_like(known, dtype=bool)  # free with an unknown 4-neighbour, by hand
    expected[0, 3] = expected[2, 3] = True  # above and below the unknown (1, 3)
    expected[2, 0] = expected[3, 1] = True  # above and right of the unknown (3, 0)
    img = rgb_frame(Snapshot(0, known, [], []), [], np.ones(known.shape, dtype=bool))
    painted = np.all(img == FRONTIER, axis=-1)
    assert np.array_equal(painted, expected)


def test_carried_units_matches_drops_to_pickups_first_in_first_out():
    def job(t: int, kind: str) -> list:
        return [t, 0, 0, kind]

    record = {
        "params": {"food_units": 3},
        "agents": [
            {"jobs": [job(1, "pickup")]},  # hands its unit over (not recorded), never drops
            {"jobs": [job(2, "pickup"), job(4, "drop")]},
        ],
    }
    carrying, delivered, left = carried_units(record, 6)
    # the drop at 4 delivers the oldest unit in transit (robot 0's, picked at 1)
    assert carrying[0].tolist() == [False, True, True, True, False, False]
    assert carrying[1].tolist() == [False, False, True, True, True, True]
    assert delivered.tolist() == [0, 0, 0, 0, 1, 1]
    assert left.tolist() == [3, 2, 1, 1, 1, 1]
    # filled dots always equal the units in transit: picked minus delivered
    assert (carrying.sum(axis=0) == (3 - left) - delivered).all()


def test_monitor_json_sends_non_finite_floats_as_null():
    batch = [
        {"t": 1.0, "x": float("nan"), "metrics": {"rate": float("inf"), "n": (2, -float("inf"))}}
    ]
    text = dumps(batch)
    assert "NaN" not in text and "Infinity" not in text
    assert json.loads(text) == [{"t": 1.0, "x": None, "metrics": {"rate": None, "n": [2, None]}}]
    assert dumps([{"t": 2.5}]) == json.dumps([{"t": 2.5}])  # finite batches as they are
