"""Seeded map generators, so the demo and the unit tests never need a file.

Each generator takes a ``numpy.random.Generator`` (or an int seed) and returns a
:class:`GridWorld` whose free cells form one connected component (unreachable pockets are
filled), because every mission here assumes the free space can be reached from the starts.
"""

from __future__ import annotations

import sys

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.grid import GridWorld


def _rng(seed: int | np.random.Generator) -> np.random.Generator:
    return seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)


# Up to this many cells a flood fill in Python (~10 ms for 64x64) beats importing
# scipy.ndimage (0.3-0.5 s), which is most of `swarmex demo`'s map generation otherwise.
SMALL_LABEL_CELLS = 16384


def keep_largest_component(free: np.ndarray) -> np.ndarray:
    """Blocks every free cell outside the largest 4-connected free component (of equal
    largest ones, the one whose first cell in row-major order comes first)."""
    if free.size <= SMALL_LABEL_CELLS and "scipy.ndimage" not in sys.modules:
        return _largest_component_small(free)
    from scipy import ndimage  # imported here: ~0.4 s that most commands never need

    labels, count = ndimage.label(free)
    if count <= 1:
        return free.copy()
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return labels == int(np.argmax(sizes))


def _largest_component_small(free: np.ndarray) -> np.ndarray:
    """:func:`keep_largest_component` by a depth-first flood fill from each unlabelled free
    cell in row-major order: components are numbered as ``ndimage.label`` numbers them, and
    the first largest wins as ``argmax`` picks it."""
    height, width = free.shape
    cells = free.ravel().tolist()
    label = [0] * len(cells)
    count, best, best_size = 0, 0, 0
    for start, is_free in enumerate(cells):
        if not is_free or label[start]:
            continue
        count += 1
        label[start] = count
        stack, size = [start], 0
        while stack:
            v = stack.pop()
            size += 1
            x = v % width
            for u, ok in ((v - width, v >= width), (v + width, v + width < len(cells)),
                          (v - 1, x > 0), (v + 1, x + 1 < width)):
                if ok and cells[u] and not label[u]:
                    label[u] = count
                    stack.append(u)
        if size > best_size:
            best, best_size = count, size
    if count <= 1:
        return free.copy()
    return (np.array(label, dtype=np.int64) == best).reshape(height, width)


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
