"""The thesis's grid numbering (seed 000 §3.2.4): node 1 bottom-left, row-major upwards."""

from __future__ import annotations

import numpy as np

from swarmex.worlds import GridWorld


def tid_to_node(k: int, w: int, h: int) -> int:
    x, yb = (k - 1) % w, (k - 1) // w
    return (h - 1 - yb) * w + x


def node_to_tid(n: int, w: int, h: int) -> int:
    x, y = n % w, n // w
    return (h - 1 - y) * w + x + 1


def thesis_grid(w: int, h: int, obstacles=()) -> GridWorld:
    free = np.ones((h, w), dtype=bool)
    for k in obstacles:
        n = tid_to_node(k, w, h)
        free[n // w, n % w] = False
    return GridWorld(free)
