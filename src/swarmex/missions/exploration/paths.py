"""Grid motion planning for one robot's belief: inflation, distance fields, paths.

The thesis's framework "starts with inflating the obstacles in the grid by a radius of the
robot", builds a graph from the grid and runs "a search algorithm" (§3.1); which one is open
(spec §6.11). swarmex:

* **Footprint.** The robot is a disc of radius ``r`` (cells) centred on its cell. A cell is
  *traversable* when it is known free and no known-occupied cell's square comes closer than
  ``r`` to its centre, nor does the map's edge (outside the map is wall). With 5 cm cells and
  the default 0.1 m radius that blocks a 5×5 block minus its corners around every obstacle;
  with cells wider than the robot it blocks nothing but the obstacle itself.
* **Moves.** One tick moves the robot to one of its 8 neighbours; a diagonal step needs both
  cells it squeezes between to be traversable (no corner cutting). Travel time is therefore
  the 8-connected *step count*, and the distance field from the robot is a breadth-first
  search, exact for that metric and a few milliseconds on 400×400 cells (a Dijkstra/A* with
  √2 diagonals would optimise a length the tick-based motion does not pay).
* **Paths** descend the field from the goal, preferring at each step the predecessor nearest
  (Euclidean) to the robot, which straightens the staircases BFS leaves — the role of the
  framework's smoothing.
* **Unknown cells are not traversable**: a robot plans through what it has seen free.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.planning.distance import scratch

_DY = np.array([-1, 1, 0, 0, -1, -1, 1, 1], dtype=np.int64)
_DX = np.array([0, 0, -1, 1, -1, 1, -1, 1], dtype=np.int64)


def footprint_offsets(radius_cells: float) -> np.ndarray:
    """Offsets (dy, dx) of the cells whose square lies closer than ``radius`` to a centre."""
    r = float(radius_cells)
    k = int(math.ceil(r + 0.5))
    d = np.arange(-k, k + 1)
    dy, dx = np.meshgrid(d, d, indexing="ij")
    gap = np.maximum(np.abs(dy) - 0.5, 0) ** 2 + np.maximum(np.abs(dx) - 0.5, 0) ** 2
    keep = gap < r * r
    keep[k, k] = True
    return np.stack([dy[keep], dx[keep]], axis=1).astype(np.int64)


@kernel(cache=True, nogil=True)
def _inflate(
    occupied: NDArray[Any], offsets: NDArray[np.int64], out: NDArray[np.bool_]
) -> None:  # pragma: no cover - compiled
    h, w = occupied.shape
    m = offsets.shape[0]
    for y in range(h):
        for x in range(w):
            if occupied[y, x] > 0:
                for k in range(m):
                    yy = y + offsets[k, 0]
                    xx = x + offsets[k, 1]
                    if 0 <= yy < h and 0 <= xx < w:
                        out[yy, xx] = True


@lru_cache(maxsize=8)
def _edge_band(shape: tuple[int, int], offsets_key: bytes) -> np.ndarray:
    """Cells whose footprint leaves the map (the edge is wall); fixed per map and robot."""
    offsets = np.frombuffer(offsets_key, dtype=np.int64).reshape(-1, 2)
    h, w = shape
    ys, xs = np.arange(h)[:, None], np.arange(w)[None, :]
    out = np.zeros(shape, dtype=bool)
    for dy, dx in offsets:
        out |= (ys + dy < 0) | (ys + dy >= h) | (xs + dx < 0) | (xs + dx >= w)
    return out


def inflate(occupied: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Cells a robot centre may not occupy: near a known obstacle or the map's edge.

    ``occupied`` is a bool mask or a log-odds grid (``> 0`` is an obstacle).
    """
    offsets = np.ascontiguousarray(offsets, dtype=np.int64)
    out = _edge_band(tuple(occupied.shape), offsets.tobytes()).copy()
    _inflate(np.ascontiguousarray(occupied), offsets, out)
    return out


def distance_steps(traversable: np.ndarray, x: int, y: int) -> np.ndarray:
    """Steps (8-connected, no corner cutting) from cell (x, y) to every cell; -1 unreachable.

    The source itself radiates even if it is not traversable (a robot that finds itself
    inside a freshly inflated zone can still leave it).
    """
    h, w = traversable.shape
    stride = w + 2
    padded = np.zeros((h + 2, stride), dtype=np.bool_)
    padded[1:-1, 1:-1] = traversable
    n = (h + 2) * stride
    out = np.empty(n, dtype=np.int32)
    _bfs8(padded.ravel(), (int(y) + 1) * stride + int(x) + 1, stride, out,
          scratch("queue", n, np.int32), _NO_STOP, _NO_GOAL, 0)
    return out.reshape(h + 2, stride)[1:-1, 1:-1]


_NO_STOP = np.zeros(0, dtype=np.bool_)  # _bfs8 without stop cells
_NO_GOAL = np.zeros(0, dtype=np.int32)  # _bfs8 without a goal to keep to


@kernel(cache=True, nogil=True)
def _bfs8(
    trav: NDArray[np.bool_], src: int, stride: int, out: NDArray[np.int32],
    q: NDArray[np.int32], stop: NDArray[np.bool_], to_goal: NDArray[np.int32], total: int,
) -> None:  # pragma: no cover - compiled
    """BFS on a padded, flattened grid (the padding ring is never traversable): 8-connected,
    a diagonal only between two traversable cells; ``q`` a queue of n cells.

    Two optional limits (an empty array: none):

    * ``stop``: end when a stop cell leaves the queue. Cells leave it in order of distance,
      so when the first stop cell (distance D) leaves it, every cell at distance D - 1 has
      left too: every cell within D steps holds its exact distance, every other cell -1 or
      its exact distance (D + 1);
    * ``to_goal``: keep only the cells of shortest paths to a goal, those whose distance
      plus their distance to the goal (``to_goal``) is ``total``."""
    n = trav.shape[0]
    for i in range(n):
        out[i] = -1
    use_stop = stop.shape[0] > 0
    use_goal = to_goal.shape[0] > 0
    step = (-stride, stride, -1, 1, -stride - 1, -stride + 1, stride - 1, stride + 1)
    side_a = (0, 0, 0, 0, -stride, -stride, stride, stride)
    side_b = (0, 0, 0, 0, -1, 1, -1, 1)
    out[src] = 0
    q[0] = src
    head = 0
    tail = 1
    while head < tail:
        u = q[head]
        head += 1
        if use_stop and stop[u]:
            return
        d = out[u] + 1
        for k in range(8):
            v = u + step[k]
            if out[v] >= 0 or not trav[v]:
                continue
            if k >= 4 and not (trav[u + side_a[k]] and trav[u + side_b[k]]):
                continue
            if use_goal:
                g = to_goal[v]
                if g < 0 or d + g != total:
                    continue
            out[v] = d
            q[tail] = v
            tail += 1


def field_padded(trav_padded: np.ndarray, x: int, y: int) -> np.ndarray:
    """:func:`distance_steps` from (x, y) on a padded grid, padded ((h + 2, w + 2))."""
    hp, stride = trav_padded.shape
    n = hp * stride
    out = np.empty(n, dtype=np.int32)  # kept (a map state's shared field): not a scratch one
    _bfs8(trav_padded.ravel(), (int(y) + 1) * stride + int(x) + 1, stride, out,
          scratch("queue", n, np.int32), _NO_STOP, _NO_GOAL, 0)
    return out.reshape(hp, stride)


def steps_via_field(trav_padded: np.ndarray, field: np.ndarray, x: int, y: int) -> int:
    """Steps from (x, y) to the source of ``field`` (:func:`field_padded` from a traversable
    cell), as :func:`distance_steps` from (x, y) counts them; -1 if unreachable.

    Moves are reversible (a diagonal needs the same two cells free both ways), so over
    traversable cells the distance is symmetric; an untraversable (x, y) is left by one
    legal step, as the search from it does, and never re-entered."""
    yy, xx = int(y) + 1, int(x) + 1
    if trav_padded[yy, xx]:
        return int(field[yy, xx])
    best = -1
    for k in range(8):
        dy, dx = int(_DY[k]), int(_DX[k])
        if not trav_padded[yy + dy, xx + dx]:
            continue
        if k >= 4 and not (trav_padded[yy + dy, xx] and trav_padded[yy, xx + dx]):
            continue
        f = int(field[yy + dy, xx + dx])
        if f >= 0 and (best < 0 or f + 1 < best):
            best = f + 1
    return best


def distance_toward(
    trav_padded: np.ndarray, x: int, y: int, goal_field: np.ndarray, total: int
) -> np.ndarray:
    """Padded steps from (x, y), exact on every cell of a shortest path to the goal
    ``goal_field`` is measured from (``total`` steps away), -1 elsewhere: all that
    :func:`path_to_padded` reads of a field on its way down from the goal (a cell one step
    nearer to the robot than a cell of such a path lies on one too). In a buffer this
    thread reuses at its next call, like :func:`distance_until`'s."""
    hp, stride = trav_padded.shape
    n = hp * stride
    out = scratch("toward", n, np.int32)
    _bfs8(trav_padded.ravel(), (int(y) + 1) * stride + int(x) + 1, stride, out,
          scratch("queue", n, np.int32), _NO_STOP, goal_field.ravel(), int(total))
    return out.reshape(hp, stride)


def padded(traversable: np.ndarray) -> np.ndarray:
    """``traversable`` with a ring of untraversable cells round it (what the searches walk)."""
    h, w = traversable.shape
    out = np.zeros((h + 2, w + 2), dtype=np.bool_)
    out[1:-1, 1:-1] = traversable
    return out


def distance_until(
    trav_padded: np.ndarray, x: int, y: int, stop_xs: np.ndarray, stop_ys: np.ndarray
) -> np.ndarray:
    """Steps from (x, y) as :func:`distance_steps` gives them, up to the nearest stop cell.

    Exact for every cell no farther than the nearest stop cell (D steps); farther cells
    hold -1 or their exact distance. Enough to pick the nearest of the stop cells and to
    walk a path to one at distance D (:func:`path_to_padded`) when a plan needs nothing
    else from the field: the search visits the cells within D steps instead of the whole
    known map. Returns the *padded* field ((h + 2, w + 2): cell (x, y) at [y + 1, x + 1]),
    in a buffer this thread reuses at its next call: read it (or copy it) before then.
    """
    hp, stride = trav_padded.shape
    n = hp * stride
    stop = scratch("stop", n, np.bool_)  # all False between calls
    cells = (np.asarray(stop_ys, np.int64) + 1) * stride + np.asarray(stop_xs, np.int64) + 1
    stop[cells] = True
    out = scratch("until", n, np.int32)
    try:
        _bfs8(trav_padded.ravel(), (int(y) + 1) * stride + int(x) + 1, stride, out,
              scratch("queue", n, np.int32), stop, _NO_GOAL, 0)
    finally:
        stop[cells] = False
    return out.reshape(hp, stride)


def labels4(traversable: np.ndarray) -> np.ndarray:
    """Connected pieces of the traversable cells (int32, 0 off them).

    4-connected is exact for the robot's moves: a diagonal step needs both cells it squeezes
    between traversable, and they join its two ends by straight steps already. So a cell is
    reachable from the robot's cell iff it lies in a piece the robot's cell is in or touches
    (the robot's own cell may be untraversable: it still leaves it, :func:`distance_steps`)."""
    from scipy import ndimage  # here: only the planners that use it pay for the import

    lab, _ = ndimage.label(traversable)
    return np.asarray(lab, dtype=np.int32)


def reachable_pieces(traversable: np.ndarray, lab: np.ndarray, x: int, y: int) -> list[int]:
    """Labels (:func:`labels4`) of the pieces a search from (x, y) reaches."""
    if traversable[y, x]:
        return [int(lab[y, x])]
    h, w = traversable.shape
    out = {int(lab[y + dy, x + dx]) for dx, dy in ((0, -1), (0, 1), (-1, 0), (1, 0))
           if 0 <= x + dx < w and 0 <= y + dy < h and traversable[y + dy, x + dx]}
    return sorted(out)


@kernel(cache=True, nogil=True)
def _descend(
    dist: NDArray[np.integer[Any]], trav: NDArray[np.bool_], gy: int, gx: int, sy: int, sx: int,
    out: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    h, w = dist.shape
    y = gy
    x = gx
    n = dist[gy, gx]
    for i in range(n - 1, -1, -1):
        out[i, 0] = x
        out[i, 1] = y
        best = -1
        bd = np.inf
        for k in range(8):
            yy = y + _DY[k]
            xx = x + _DX[k]
            if yy < 0 or xx < 0 or yy >= h or xx >= w or dist[yy, xx] != i:
                continue
            # the edge (yy,xx)->(y,x) is legal iff it was legal for the BFS
            if k >= 4 and not (trav[y, xx] and trav[yy, x]):
                continue
            e = (yy - sy) ** 2 + (xx - sx) ** 2
            if e < bd:
                bd = e
                best = k
        y = y + _DY[best]
        x = x + _DX[best]


def path_to(
    dist: np.ndarray, traversable: np.ndarray, gx: int, gy: int, sx: int, sy: int
) -> NDArray[np.int64]:
    """Cells (x, y) from the first step after (sx, sy) to the goal (gx, gy), as (n, 2) ints."""
    n = int(dist[gy, gx])
    out = np.empty((max(n, 0), 2), dtype=np.int64)
    if n > 0:
        _descend(np.ascontiguousarray(dist), np.ascontiguousarray(traversable), int(gy),
                 int(gx), int(sy), int(sx), out)
    return out


def path_to_padded(
    dist_padded: np.ndarray, trav_padded: np.ndarray, gx: int, gy: int, sx: int, sy: int
) -> NDArray[np.int64]:
    """:func:`path_to` on padded arrays (:func:`distance_until`, :func:`padded`): the same
    cells, without copying an unpadded field first."""
    n = int(dist_padded[gy + 1, gx + 1])
    out = np.empty((max(n, 0), 2), dtype=np.int64)
    if n > 0:
        _descend(dist_padded, trav_padded, int(gy) + 1, int(gx) + 1, int(sy) + 1,
                 int(sx) + 1, out)
        out -= 1
    return out


@kernel(cache=True, nogil=True)
def footprint_clear(
    occupied: NDArray[Any], y: int, x: int, offsets: NDArray[np.int64]
) -> bool:  # pragma: no cover - compiled
    """True if no known obstacle (or the map edge) is inside the footprint at (x, y).

    ``occupied`` is a bool mask or a log-odds grid (``> 0`` is an obstacle), so the motion
    check reads the robot's map directly, without building a mask every tick.
    """
    h, w = occupied.shape
    for k in range(offsets.shape[0]):
        yy = y + offsets[k, 0]
        xx = x + offsets[k, 1]
        if yy < 0 or xx < 0 or yy >= h or xx >= w or occupied[yy, xx] > 0:
            return False
    return True
