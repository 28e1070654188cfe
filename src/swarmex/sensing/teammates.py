"""Which teammates each robot of a grid team sees: the cells of those within a Manhattan
distance, one row per robot.

Why compiled: a PettingZoo step builds this view for every robot every round; with numpy it is
half a dozen (n, n) temporaries (about 10 µs for 16 robots, as much as the rest of the step),
with numba one pass over the pairs.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel

I64 = NDArray[np.int64]


@kernel(cache=True)
def _fill(pos: I64, radius: int, out: I64) -> None:
    n = pos.shape[0]
    for i in range(n):
        xi, yi = pos[i, 0], pos[i, 1]
        for j in range(n):
            if j != i and abs(pos[j, 0] - xi) + abs(pos[j, 1] - yi) <= radius:
                out[i, j, 0] = pos[j, 0]
                out[i, j, 1] = pos[j, 1]
            else:
                out[i, j, 0] = -1
                out[i, j, 1] = -1


def team_view(pos: I64, radius: int) -> I64:
    """(n, n, 2) int64: row ``i`` holds the cell of each robot ``j`` within Manhattan distance
    ``radius`` of robot ``i`` (``pos``: (n, 2) cells), and (−1, −1) for the others and for
    ``i`` itself."""
    n = pos.shape[0]
    out = np.empty((n, n, 2), dtype=np.int64)
    _fill(np.ascontiguousarray(pos, dtype=np.int64), int(radius), out)
    return out
