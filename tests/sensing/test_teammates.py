"""team_view: each robot's view of its teammates within a Manhattan distance, checked against
the pairwise definition written out in plain Python."""

import numpy as np
import pytest

from swarmex.sensing.teammates import team_view


@pytest.mark.parametrize(("n", "g", "radius"), [(1, 4, 2), (5, 3, 1), (16, 32, 2), (9, 6, 0)])
def test_team_view_is_the_pairwise_rule(n, g, radius):
    rng = np.random.default_rng(n * g + radius)
    for _ in range(20):
        pos = rng.integers(0, g, size=(n, 2))
        view = team_view(pos, radius)
        assert view.shape == (n, n, 2) and view.dtype == np.int64
        for i in range(n):
            for j in range(n):
                d = abs(int(pos[i, 0] - pos[j, 0])) + abs(int(pos[i, 1] - pos[j, 1]))
                expect = tuple(pos[j]) if i != j and d <= radius else (-1, -1)
                assert tuple(view[i, j]) == expect


def test_team_view_takes_any_integer_array():
    pos = np.array([[0, 0], [0, 1], [3, 3]], dtype=np.int32)[:, ::-1]  # not contiguous
    assert team_view(pos, 1).tolist() == [
        [[-1, -1], [1, 0], [-1, -1]],
        [[0, 0], [-1, -1], [-1, -1]],
        [[-1, -1], [-1, -1], [-1, -1]],
    ]
