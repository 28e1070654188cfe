"""Seeded map generators, so the demo and the unit tests never need a file.

Each generator takes a ``numpy.random.Generator`` (or an int seed) and returns a
:class:`GridWorld` whose free cells form one connected component (unreachable pockets are
filled), because every mission here assumes the free space can be reached from the starts.
"""

from __future__ import annotations

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.grid import GridWorld


def _rng(seed: int | np.random.Generator) -> np.random.Generator:
    return seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)


def keep_largest_component(free: np.ndarray) -> np.ndarray:
    """Blocks every free cell outside the largest 4-connected free component."""
    from scipy import ndimage  # imported here: ~0.25 s that most commands never need

    labels, count = ndimage.label(free)
    if count <= 1:
        return free.copy()
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return labels == int(np.argmax(sizes))


def empty_grid(width: int, height: int) -> GridWorld:
    if width < 1 or height < 1:
        raise InputError(f"grid size must be positive, got {width}x{height}")
    return GridWorld(np.ones((height, width), dtype=bool), source=f"empty {width}x{height}")


def random_obstacles(
    width: int, height: int, density: float, seed: int | np.random.Generator = 0
) -> GridWorld:
    """Independent random obstacle cells at the given density, largest component kept."""
    if not 0.0 <= density < 1.0:
        raise InputError(f"obstacle density must be in [0, 1), got {density}")
    free = _rng(seed).random((height, width)) >= density
    return GridWorld(
        keep_largest_component(free), source=f"random {width}x{height} d={density:g}"
    )


def rooms(
    width: int, height: int, room: int = 8, door: int = 2, seed: int | np.random.Generator = 0
) -> GridWorld:
    """A grid of square rooms separated by one-cell walls, with a door in every wall."""
    if room < 2 or door < 1 or door > room:
        raise InputError("rooms need room >= 2 and 1 <= door <= room")
    rng = _rng(seed)
    free = np.ones((height, width), dtype=bool)
    period = room + 1
    for y in range(room, height, period):
        free[y, :] = False
        for x0 in range(0, width, period):
            start = x0 + int(rng.integers(0, max(1, min(room, width - x0) - door + 1)))
            free[y, start : start + door] = True
    for x in range(room, width, period):
        free[:, x] = False
        for y0 in range(0, height, period):
            start = y0 + int(rng.integers(0, max(1, min(room, height - y0) - door + 1)))
            free[start : start + door, x] = True
    return GridWorld(keep_largest_component(free), source=f"rooms {width}x{height}")


def maze(width: int, height: int, seed: int | np.random.Generator = 0) -> GridWorld:
    """A perfect maze (randomised depth-first carving) on odd-sized cells."""
    rng = _rng(seed)
    cw, ch = max(1, (width - 1) // 2), max(1, (height - 1) // 2)
    free = np.zeros((height, width), dtype=bool)
    seen = np.zeros((ch, cw), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    free[1, 1] = True
    while stack:
        cx, cy = stack[-1]
        options = [
            (cx + dx, cy + dy)
            for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
            if 0 <= cx + dx < cw and 0 <= cy + dy < ch and not seen[cy + dy, cx + dx]
        ]
        if not options:
            stack.pop()
            continue
        nx_, ny_ = options[int(rng.integers(len(options)))]
        seen[ny_, nx_] = True
        free[2 * ny_ + 1, 2 * nx_ + 1] = True
        free[cy + ny_ + 1, cx + nx_ + 1] = True
        stack.append((nx_, ny_))
    return GridWorld(free, source=f"maze {width}x{height}")
