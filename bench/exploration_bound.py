"""A makespan no exploration strategy can beat, per scenario (issue 17 item 2).

Is a 10 % gain over greedy-exclusion possible at all in a scenario? Two lower bounds on the
makespan (steps until every robot finished), from the true map, the starts, the laser and
the robots' speed only:

* **sight bound** — every reachable free cell must be sensed by some robot: a scan marks a
  cell free only if a beam *passed* it, and robots scan from the cells they stand on (at
  tick 0 and after every move). A robot moves at most one cell per tick (8 directions, no
  corner cutting: the simulator's ``legal_step`` on the true free cells, which every plan
  obeys). So cell ``c`` cannot be known before ``min over p seeing c of D(p)``, where
  ``D(p)`` = steps from the nearest start (one multi-source BFS on the true free cells),
  and "p sees c" is the simulator's own sensing: the laser's Amanatides–Woo walk from the
  centre of ``p`` (its 360 beams, the same angles), cells entered before the first wall
  and before the range. The bound is the maximum of that over the cells. Walls are used
  exactly (a room behind a wall is not seen through it).
* **sweep bound** — each tick a robot adds at most ``Δ`` new cells to what the team knows,
  ``Δ`` = the most reachable free cells a scan from ``p'`` holds that the scan from an
  adjacent ``p`` (the robot's previous cell, which it scanned) does not. With the ``U``
  cells the starts' scans already hold, the team of ``n`` needs at least
  ``(cells − U) / (n Δ)`` ticks. ``Δ`` is taken over every legal move of the map (on the
  open world, whose free space is convex, at one position: a scan there is the same
  pattern everywhere, cut by the outer wall).

Both need the run to map every reachable free cell (``explored_fraction`` = 1, which the
strategy table checks for every run); a finishing robot could in principle leave a frontier
region smaller than its diameter unseen, and then the bound would not bind that run.
Delivery of scans is instantaneous, so sensing is the only constraint used: the bound
ignores the radio, the planning timer and every other limit, and is therefore loose where
those matter (the short radio). Starts are the mission's default (a compact group near the
centre), the same for every seed, so the bound is one number per scenario.

    .venv/bin/python bench/exploration_bound.py                     # bounds only
    .venv/bin/python bench/exploration_bound.py --json runs.json    # with the makespans

``--json`` reads :mod:`compare_exploration_strategies`'s ``--json`` output (makespans per
scenario, strategy and seed) and prints each strategy's mean, the bound and their ratio.
"""

from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.missions.exploration.paths import distance_steps
from swarmex.missions.exploration.sim import reachable_free
from swarmex.sensing.laser import _axis, _cross

UNSEEN = np.iinfo(np.int64).max


@kernel(cache=True, nogil=True, inline="always")
def _can_step(
    free: NDArray[np.bool_], x0: int, y0: int, mx: int, my: int,
) -> bool:  # pragma: no cover - compiled
    """The simulator's ``legal_step`` from (x0, y0) by (mx, my): one 8-neighbour move onto a
    free cell of the grid, a diagonal only between two free cells."""
    h, w = free.shape
    x1 = x0 + mx
    y1 = y0 + my
    if (mx == 0 and my == 0) or x1 < 0 or y1 < 0 or x1 >= w or y1 >= h or not free[y1, x1]:
        return False
    return mx == 0 or my == 0 or (free[y0, x1] and free[y1, x0])


@kernel(cache=True, nogil=True)
def _scan_into(
    free: NDArray[np.bool_], x0: int, y0: int, angles: NDArray[np.float64], max_cells: float,
    stamp: NDArray[np.int64], mark: int,
) -> None:  # pragma: no cover - compiled
    """``stamp[y, x] = mark`` for every cell the scan from (x0, y0) passes: the start cell and
    the cells a beam enters before its first non-free cell and before ``max_cells`` — the
    laser's walk (``cast_rays_cells``) and the rasteriser's "passed" rule in one loop."""
    h, w = free.shape
    stamp[y0, x0] = mark
    for b in range(angles.shape[0]):
        sx, ddx = _axis(math.cos(angles[b]))
        sy, ddy = _axis(math.sin(angles[b]))
        kx = 0
        ky = 0
        cx = x0
        cy = y0
        while True:
            t, kx, ky, cx, cy = _cross(kx, ky, cx, cy, sx, sy, ddx, ddy)
            if t >= max_cells or cx < 0 or cy < 0 or cx >= w or cy >= h or not free[cy, cx]:
                break
            stamp[cy, cx] = mark


@kernel(cache=True, nogil=True)
def _first_sight(
    free: NDArray[np.bool_], order_x: NDArray[np.int64], order_y: NDArray[np.int64],
    d: NDArray[np.int64], angles: NDArray[np.float64], max_cells: float,
    target: NDArray[np.bool_], seen: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """``seen[c]`` = the least ``d`` of a cell whose scan passes c. Cells are visited in
    increasing ``d``, so the first scan to reach a cell sets it; stops when every target
    cell is set."""
    h, w = free.shape
    stamp = np.full((h, w), -1, dtype=np.int64)
    left = 0
    for y in range(h):
        for x in range(w):
            if target[y, x]:
                left += 1
    reach = int(math.ceil(max_cells)) + 1
    for i in range(order_x.shape[0]):
        x0 = order_x[i]
        y0 = order_y[i]
        _scan_into(free, x0, y0, angles, max_cells, stamp, i)
        for y in range(max(0, y0 - reach), min(h, y0 + reach + 1)):
            for x in range(max(0, x0 - reach), min(w, x0 + reach + 1)):
                if stamp[y, x] == i and seen[y, x] == UNSEEN:
                    seen[y, x] = d[i]
                    if target[y, x]:
                        left -= 1
        if left == 0:
            return


@kernel(cache=True, nogil=True)
def _max_gain(
    free: NDArray[np.bool_], xs: NDArray[np.int64], ys: NDArray[np.int64],
    angles: NDArray[np.float64], max_cells: float, target: NDArray[np.bool_],
) -> int:  # pragma: no cover - compiled
    """The most target cells a scan from a cell of (xs, ys) adds to the scan from an
    adjacent cell a legal move away (8 directions, no corner cutting)."""
    h, w = free.shape
    here = np.full((h, w), -1, dtype=np.int64)
    there = np.full((h, w), -1, dtype=np.int64)
    reach = int(math.ceil(max_cells)) + 2
    best = 0
    k = 0
    for i in range(xs.shape[0]):
        x0 = xs[i]
        y0 = ys[i]
        _scan_into(free, x0, y0, angles, max_cells, here, i)
        for mx in range(-1, 2):
            for my in range(-1, 2):
                x1 = x0 + mx
                y1 = y0 + my
                if not _can_step(free, x0, y0, mx, my):
                    continue
                _scan_into(free, x1, y1, angles, max_cells, there, k)
                gain = 0
                for y in range(max(0, y1 - reach), min(h, y1 + reach + 1)):
                    for x in range(max(0, x1 - reach), min(w, x1 + reach + 1)):
                        if there[y, x] == k and here[y, x] != i and target[y, x]:
                            gain += 1
                k += 1
                if gain > best:
                    best = gain
    return best


@kernel(cache=True, nogil=True)
def _seers(
    free: NDArray[np.bool_], reach_ok: NDArray[np.bool_], cx: int, cy: int,
    angles: NDArray[np.float64], max_cells: float, stamp: NDArray[np.int64], mark0: int,
    out: NDArray[np.bool_],
) -> int:  # pragma: no cover - compiled
    """``out[p] = True`` for every reachable cell p whose scan passes (cx, cy); returns the
    next unused stamp mark."""
    h, w = free.shape
    reach = int(math.ceil(max_cells)) + 1
    mark = mark0
    for y in range(max(0, cy - reach), min(h, cy + reach + 1)):
        for x in range(max(0, cx - reach), min(w, cx + reach + 1)):
            if not reach_ok[y, x]:
                continue
            _scan_into(free, x, y, angles, max_cells, stamp, mark)
            if stamp[cy, cx] == mark:
                out[y, x] = True
            mark += 1
    return mark


@kernel(cache=True, nogil=True)
def _bfs_from_set(free: NDArray[np.bool_], src: NDArray[np.bool_],
                  out: NDArray[np.int64]) -> None:  # pragma: no cover - compiled
    """Steps from the nearest cell of ``src`` (8 moves on free cells, no corner cutting, as
    the simulator's ``legal_step``); -1 unreachable."""
    h, w = free.shape
    qx = np.empty(h * w, dtype=np.int64)
    qy = np.empty(h * w, dtype=np.int64)
    head = 0
    tail = 0
    for y in range(h):
        for x in range(w):
            out[y, x] = -1
            if src[y, x]:
                out[y, x] = 0
                qx[tail] = x
                qy[tail] = y
                tail += 1
    while head < tail:
        x0 = qx[head]
        y0 = qy[head]
        head += 1
        for mx in range(-1, 2):
            for my in range(-1, 2):
                x1 = x0 + mx
                y1 = y0 + my
                if not _can_step(free, x0, y0, mx, my) or out[y1, x1] >= 0:
                    continue
                out[y1, x1] = out[y0, x0] + 1
                qx[tail] = x1
                qy[tail] = y1
                tail += 1


def pair_bound(free: np.ndarray, starts: tuple[tuple[int, int], ...], angles: np.ndarray,
               laser_cells: float, tries: int = 8) -> int:
    """The pigeonhole bound: of n + 1 cells, some robot of n must sense two.

    For cells i, j let ``T_i`` be the earliest tick any robot can sense i (the sight bound's
    value at i) and ``G_ij`` the fewest steps between a cell that sees i and one that sees
    j. The robot that senses both, whichever first, cannot finish that before
    ``min(T_i, T_j) + G_ij``; so for any n + 1 cells the makespan is at least the least of
    that over their pairs. Any choice of cells gives a valid bound; they are chosen far
    apart (farthest-point order from ``tries`` different first cells, by steps between the
    cells themselves), and the best set's value is returned.
    """
    n = len(starts)
    target = reachable_free(free, starts)
    f = np.ascontiguousarray(free)
    a = np.asarray(angles, np.float64)
    d = nearest_start_steps(free, starts)
    ys, xs = np.nonzero(target)
    stamp = np.full(free.shape, -1, dtype=np.int64)
    mark = 0
    # cell -> (T, its seers, steps from them)
    seers: dict[tuple[int, int], tuple[int, np.ndarray, np.ndarray]] = {}

    def seer_field(c: tuple[int, int]) -> tuple[int, np.ndarray, np.ndarray]:
        nonlocal mark
        if c not in seers:
            v = np.zeros(free.shape, dtype=bool)
            mark = _seers(f, target, c[0], c[1], a, float(laser_cells), stamp, mark, v)
            g = np.empty(free.shape, dtype=np.int64)
            _bfs_from_set(f, v, g)
            seers[c] = (int(d[v].min()), v, g)
        return seers[c]

    rng = np.random.default_rng(0)
    far = np.argsort(-d[ys, xs], kind="stable")
    firsts = [int(far[0])] + [int(i) for i in rng.choice(ys.size, tries - 1, replace=False)]
    best = 0
    for first in firsts:
        chosen = [(int(xs[first]), int(ys[first]))]
        near = np.full(free.shape, np.iinfo(np.int64).max, dtype=np.int64)
        while len(chosen) < n + 1:
            g = np.empty(free.shape, dtype=np.int64)
            src = np.zeros(free.shape, dtype=bool)
            src[chosen[-1][1], chosen[-1][0]] = True
            _bfs_from_set(f, src, g)
            near = np.minimum(near, np.where(g >= 0, g, near))
            near[~target] = -1
            k = int(np.argmax(near))
            chosen.append((k % free.shape[1], k // free.shape[1]))
        value = None
        for i, ci in enumerate(chosen):
            ti, _, gi = seer_field(ci)
            for cj in chosen[i + 1:]:
                tj, vj, _ = seer_field(cj)
                # G_ij: steps from i's seers to the nearest of j's seers
                gij = int(gi[vj & (gi >= 0)].min())
                pair = min(ti, tj) + gij
                value = pair if value is None else min(value, pair)
        best = max(best, value or 0)
    return best


@dataclass(frozen=True)
class Bound:
    sight: int  # the last reachable free cell's earliest sighting (steps)
    sweep: int  # cells over the team's best sensing rate (steps)
    pair: int  # of n + 1 far cells, some robot senses two (steps)
    cells: int  # reachable free cells
    gain: int  # most new cells one step adds (Δ)

    @property
    def steps(self) -> int:
        return max(self.sight, self.sweep, self.pair)


def nearest_start_steps(free: np.ndarray, starts: tuple[tuple[int, int], ...]) -> np.ndarray:
    """Steps from the nearest start to every cell on the true free cells (-1 unreachable)."""
    best = np.full(free.shape, -1, dtype=np.int64)
    for x, y in starts:
        d = distance_steps(free, x, y).astype(np.int64)
        better = (d >= 0) & ((best < 0) | (d < best))
        best[better] = d[better]
    return best


def sight_bound(free: np.ndarray, starts: tuple[tuple[int, int], ...], angles: np.ndarray,
                laser_cells: float) -> int:
    """The largest earliest-sighting time over the reachable free cells (see the module)."""
    target = reachable_free(free, starts)
    d = nearest_start_steps(free, starts)
    ys, xs = np.nonzero(d >= 0)
    order = np.lexsort((xs, ys, d[ys, xs]))
    seen = np.full(free.shape, UNSEEN, dtype=np.int64)
    _first_sight(np.ascontiguousarray(free), xs[order].astype(np.int64),
                 ys[order].astype(np.int64), d[ys, xs][order].astype(np.int64),
                 np.asarray(angles, np.float64), float(laser_cells), target, seen)
    if (seen[target] == UNSEEN).any():
        raise ValueError("a reachable cell is seen from no reachable cell")
    return int(seen[target].max()) if target.any() else 0


def convex_free(free: np.ndarray) -> bool:
    """Whether the free cells are one filled rectangle (the open world: no inner wall)."""
    ys, xs = np.nonzero(free)
    if ys.size == 0:
        return False
    box = free[ys.min():ys.max() + 1, xs.min():xs.max() + 1]
    return bool(box.all())


def sweep_bound(free: np.ndarray, starts: tuple[tuple[int, int], ...], angles: np.ndarray,
                laser_cells: float) -> tuple[int, int, int]:
    """(steps, reachable cells, Δ): ``ceil((cells − U) / (n Δ))`` (see the module)."""
    target = reachable_free(free, starts)
    a = np.asarray(angles, np.float64)
    f = np.ascontiguousarray(free)
    init = np.full(free.shape, -1, dtype=np.int64)
    for x, y in starts:
        _scan_into(f, int(x), int(y), a, float(laser_cells), init, 0)
    known0 = int(((init == 0) & target).sum())
    if convex_free(free):
        # one position far from the walls stands for all: the scan pattern is the same
        # everywhere and the outer wall only cuts it
        r = int(math.ceil(laser_cells)) + 3
        big = np.ones((2 * r + 3, 2 * r + 3), dtype=bool)
        c = np.array([r + 1], dtype=np.int64)
        gain = _max_gain(big, c, c, a, float(laser_cells), big)
    else:
        ys, xs = np.nonzero(target)
        gain = _max_gain(f, xs.astype(np.int64), ys.astype(np.int64), a, float(laser_cells),
                         target)
    cells = int(target.sum())
    n = len(starts)
    steps = -(-(cells - known0) // (n * gain)) if gain else 0
    return int(steps), cells, int(gain)


def bound_for(free: np.ndarray, starts: tuple[tuple[int, int], ...], angles: np.ndarray,
              laser_cells: float) -> Bound:
    sweep, cells, gain = sweep_bound(free, starts, angles, laser_cells)
    return Bound(sight_bound(free, starts, angles, laser_cells), sweep,
                 pair_bound(free, starts, angles, laser_cells), cells, gain)


def scenario_bound(world: dict[str, Any], robots: int, laser: float) -> Bound:
    """The bound of one scenario of the study (its world, team size and laser, default
    starts and robot radius, as the mission builds them)."""
    from swarmex.missions.exploration.mission import build_world
    from swarmex.missions.exploration.params import default_starts
    from swarmex.missions.registry import get
    from swarmex.sensing.laser import Laser
    from swarmex.studies.exploration.design import world_options

    params = get("exploration").params(**world_options(world), robots=robots,
                                       laser_range=laser)
    grid = build_world(params)
    laser_ = Laser(params.laser_range, params.beams, grid.cell)
    starts = params.starts or default_starts(grid, params.robots, params.robot_radius)
    return bound_for(grid.free, tuple(starts), laser_.angles, laser_.range_cells)


def main(argv: list[str] | None = None) -> int:
    import _cli  # here: the tests load this file without bench/ on sys.path
    from swarmex.studies.exploration.design import SCENARIOS, maps_dir

    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="makespans from compare_exploration_strategies.py --json")
    ap.add_argument("--only", help="comma-separated scenario indices (0-based)")
    args = ap.parse_args(argv)
    runs: dict[str, dict[str, list[int]]] = {}
    if args.json:
        with open(args.json) as fh:
            runs = json.load(fh)
    scenarios = SCENARIOS
    if args.only:
        scenarios = [SCENARIOS[i] for i in _cli.indices(args.only, len(SCENARIOS))]
    strategies = sorted({st for by in runs.values() for st in by},
                        key=lambda s: (s != "greedy-exclusion", s))
    head = "| scenario | cells | Δ | sight | sweep | pair | bound |"
    head += "".join(f" {st} (mean, ratio) |" for st in strategies)
    print(head)
    print("|---|" + "---:|" * (6 + len(strategies)))
    for name, world, n, laser, _comm in scenarios:
        if "map" in world and not (maps_dir() / world["map"]).exists():
            print(f"skipped {name}: map not found", file=sys.stderr)
            continue
        c0 = time.process_time()
        b = scenario_bound(world, n, laser)
        row = f"| {name} | {b.cells} | {b.gain} | {b.sight} | {b.sweep} | {b.pair} "
        row += f"| **{b.steps}** |"
        for st in strategies:
            v = runs.get(name, {}).get(st)
            row += f" {np.mean(v):.0f}, {np.mean(v) / b.steps:.2f} |" if v else " |"
        print(row)
        print(f"  ({time.process_time() - c0:.1f} s CPU)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    import _cli

    _cli.run(main)
