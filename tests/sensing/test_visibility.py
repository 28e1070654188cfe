"""``first_sighting``: the first viewpoint along a move that sees the goal, checked against a
brute force over the same viewpoints with ``line_of_sight``."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.sensing.visibility import first_sighting, line_of_sight

NO_WALLS = np.zeros((0, 4))
# a wall along y = 2 from x = -1 to 9.5: of the viewpoints on (0, 0)-(10, 0), only the end
# sees (10, 5) past it
WALL = np.array([[-1.0, 2.0, 9.5, 2.0]])


def brute(a, b, goal, rng, spacing, edges) -> float:
    m = max(1, int(np.ceil(np.hypot(*(np.subtract(b, a))) / spacing)))
    for t in np.arange(m + 1) / m:
        p = np.add(a, t * np.subtract(b, a))
        if np.hypot(*(np.subtract(goal, p))) <= rng and line_of_sight(edges, p, goal)[0]:
            return float(t)
    return -1.0


@pytest.mark.parametrize(("goal", "edges", "want"), [
    ((20.0, 0.0), NO_WALLS, 1.0),   # in range only from the end of the move
    ((10.0, 5.0), WALL, 1.0),       # in view only from the end of the move
    ((5.0, 3.0), NO_WALLS, 0.0),    # seen from the start
    ((30.0, 0.0), NO_WALLS, -1.0),  # never in range
])
def test_the_end_of_the_move_is_a_viewpoint_too(goal, edges, want):
    """A goal seen only from where the move ends was reported unseen (-1), so the roadmap
    search would record the sighting a move late, or miss it where the agent stops."""
    got = first_sighting(0.0, 0.0, 10.0, 0.0, goal[0], goal[1], 10.0, 1.0, edges)
    assert got == want == brute((0.0, 0.0), (10.0, 0.0), goal, 10.0, 1.0, edges)
