"""Goal choice among reachable frontier cells: the thesis's greedy rules and stronger ones.

Every strategy is a pure function of one robot's :class:`GoalContext` (its own candidates
and distances, and what it has heard from neighbours) and returns a goal cell or ``None``.

* ``greedy`` — Yamauchi's nearest frontier, uncoordinated: the fewest steps from the robot.
* ``greedy-exclusion`` — the thesis (§3.3.4): greedy, but never a cell within the laser
  range of a goal a neighbour has announced; "prefers" a free zone, so when every candidate
  is excluded it falls back to plain greedy over all of them. Priority conflicts and
  ``CHANGE_GOAL`` are handled by the robot (they are message reactions, not goal choice).
* ``utility`` — Burgard et al. 2005, "Coordinated multi-robot exploration" (IEEE T-RO 21(3)),
  run decentrally: the robot replays the paper's sequential assignment (its Table I) over itself
  and the neighbours whose positions it knows — repeatedly take the (robot, target) pair
  maximising ``U_t − β·V_t^i`` and lower the utility of targets near the chosen one,
  ``U_t' −= P(‖t − t'‖)``, until the robot itself is assigned. ``V`` is path length
  normalised by the largest finite one, ``β = 1``, and ``P(d) = max(0, 1 − d / laser
  range)``: the chance that a target is seen from the other (the paper estimates it from
  visibility statistics; linear decay is the common simplification).
* ``minpos`` — Bautin, Simonin & Charpillet 2012, "MinPos: a novel frontier allocation
  algorithm for multi-robot exploration" (ICIRA): for each target, its *rank* is the number
  of neighbours nearer to it (by path) than the robot; take the lowest rank, then the
  nearest. Robots spread over frontiers without negotiating.
* ``hungarian`` — an optimal assignment of the known robots to targets minimising the sum of
  path lengths (``scipy.optimize.linear_sum_assignment``); targets are repeated when robots
  outnumber them.
* ``hungarian-exclusion`` — ours (issue 17 item 2): the thesis's goal messages, exclusion
  zones and priorities, with the assignment deciding *where* inside the free zone when the
  robot has at least two rivals in view. Why: the assignment strategies coordinate on
  neighbours' positions only, so robots with different maps or neighbours pick the same
  place, while greedy-exclusion coordinates on the announced goals but picks myopically.
  Here the Hungarian assignment runs over the targets outside every announced goal's zone
  (all targets when none is outside), and the robot heads for the nearest frontier cell
  within laser range of its assigned target (the target is a region's representative, the
  nearest cell of it is where the robot starts seeing it). With fewer than two rivals in view
  the assignment has nothing to balance and the choice is greedy-exclusion's.
* ``pocket-exclusion`` — ours (issue 17 item 2, aimed at the short radio): greedy-exclusion
  (same GOAL messages, zones and priorities) with two changes against the run's *tail*, which
  in the short-radio world is often a quarter of the makespan. (1) A frontier region that
  fits in a square of the laser range's side (a *pocket*: one visit clears it) costs half
  its path length, so a robot clears a pocket it passes instead of leaving it behind for a
  long trip at the end (greedy follows the big frontier, and a 30-cell sliver left at a wall
  at tick 550 kept a whole team busy until tick 1066). (2) A robot that has finished (no
  reachable frontier on its map) walks back to its start, staying finished: the starts are
  the one meeting point every robot knows, so a robot that missed the team's scans can find
  them there. No extra message; cost: one full distance field per plan (as ``hungarian``),
  and one more for the walk home. The measured effect is nil (docs/exploration.md): the
  pockets and lonely robots are real, but these two rules do not shorten the runs.

The assignment-style strategies work on *targets*: one representative cell per piece of a
frontier region (:func:`swarmex.sensing.frontiers.chunk_targets`), so that a long frontier
offers several places and a small one a single place. Distances from neighbours are path
lengths on *this robot's* map from the neighbour's last reported cell; a neighbour in a part
of the map this robot does not know is simply not a rival for any target.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.errors import InputError
from swarmex.sensing.frontiers import Frontiers, chunk_targets

Cell = tuple[int, int]


@dataclass
class GoalContext:
    """What one robot knows when it chooses a goal (cells are (x, y))."""

    me: int
    pos: Cell
    frontiers: Frontiers
    eligible: np.ndarray  # bool per frontier cell: traversable and reachable
    dist: np.ndarray  # steps from the robot per frontier cell (-1 unreachable)
    laser_cells: float
    team_goals: dict[int, Cell] = field(default_factory=dict)
    team_pos: dict[int, Cell] = field(default_factory=dict)
    current_goal: Cell | None = None
    field_from: Callable[[Cell], np.ndarray] | None = None  # step field from a cell
    # goals of the robots that beat this one in a conflict since its last plan (only with
    # ``conflict_yield``): their zones stay closed even when every candidate is excluded
    winners: dict[int, Cell] = field(default_factory=dict)


def _nearest(ctx: GoalContext, idx: np.ndarray) -> Cell | None:
    """The candidate with the fewest steps; ties keep the current goal, then (y, x) order."""
    if idx.size == 0:
        return None
    d = ctx.dist[idx]
    best = idx[d == d.min()]
    if ctx.current_goal is not None:
        gx, gy = ctx.current_goal
        same = best[(ctx.frontiers.xs[best] == gx) & (ctx.frontiers.ys[best] == gy)]
        if same.size:
            return (gx, gy)
    i = best[np.lexsort((ctx.frontiers.xs[best], ctx.frontiers.ys[best]))[0]]
    return int(ctx.frontiers.xs[i]), int(ctx.frontiers.ys[i])


def greedy(ctx: GoalContext) -> Cell | None:
    return _nearest(ctx, greedy_candidates(ctx))


#: announced goals from which a zone test uses the goals sorted by column (below: one pass
#: over the candidates per goal)
ZONE_TREE_FROM = 8


@kernel(cache=True, nogil=True)
def _in_zones(
    xs: NDArray[np.int64], ys: NDArray[np.int64], gxs: NDArray[np.int64],
    gys: NDArray[np.int64], r2: float, reach: int, out: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """``out[i]``: candidate i is within ``r2`` (squared cells) of some goal; goals sorted
    by column, and only those within ``reach`` columns of the candidate are tried."""
    m = gxs.shape[0]
    for i in range(xs.shape[0]):
        x = xs[i]
        y = ys[i]
        lo = 0
        hi = m
        while lo < hi:  # the first goal at column >= x - reach
            mid = (lo + hi) // 2
            if gxs[mid] < x - reach:
                lo = mid + 1
            else:
                hi = mid
        hit = False
        j = lo
        while j < m and gxs[j] <= x + reach:
            dx = x - gxs[j]
            dy = y - gys[j]
            if dx * dx + dy * dy <= r2:
                hit = True
                break
            j += 1
        out[i] = hit


def _within(ctx: GoalContext, idx: np.ndarray, goals: dict[int, Cell]) -> np.ndarray:
    """Which candidates lie within the laser range (a zone) of any of ``goals``.

    With many goals (a large team in radio range) a pass per goal costs O(candidates ×
    goals) per plan; with the goals sorted by column, each candidate is tested (exactly as
    before, in integers) against the goals within the laser range of its column only."""
    r2 = ctx.laser_cells**2
    xs, ys = ctx.frontiers.xs[idx], ctx.frontiers.ys[idx]
    if len(goals) < ZONE_TREE_FROM or idx.size == 0:
        out = np.zeros(idx.size, dtype=bool)
        for gx, gy in goals.values():
            out |= (xs - gx) ** 2 + (ys - gy) ** 2 <= r2
        return out
    g = np.array(list(goals.values()), dtype=np.int64)
    g = g[np.argsort(g[:, 0], kind="stable")]
    out = np.empty(idx.size, dtype=bool)
    reach = math.isqrt(math.floor(r2)) + 1  # |dx| beyond this cannot be within r2
    _in_zones(np.ascontiguousarray(xs, dtype=np.int64), np.ascontiguousarray(ys, dtype=np.int64),
              np.ascontiguousarray(g[:, 0]), np.ascontiguousarray(g[:, 1]), float(r2), reach,
              out)
    return out


def excluded(ctx: GoalContext, idx: np.ndarray) -> np.ndarray:
    """Which candidates lie within the laser range of a neighbour's announced goal."""
    return _within(ctx, idx, ctx.team_goals)


def greedy_candidates(ctx: GoalContext) -> np.ndarray:
    """``greedy``'s candidates: every eligible frontier cell."""
    return np.nonzero(ctx.eligible)[0]


def exclusion_candidates(ctx: GoalContext) -> np.ndarray:
    """``greedy-exclusion``'s candidates: the eligible cells outside every neighbour's zone;
    if there is none, those outside the zones of the robots that just beat this one
    (``ctx.winners``, empty unless ``conflict_yield``), and only then all ("prefers")."""
    idx = np.nonzero(ctx.eligible)[0]
    free_zone = idx[~excluded(ctx, idx)]
    if free_zone.size:
        return free_zone
    if ctx.winners:
        yielded = idx[~_within(ctx, idx, ctx.winners)]
        if yielded.size:
            return yielded
    return idx


def greedy_exclusion(ctx: GoalContext) -> Cell | None:
    """Nearest candidate outside every neighbour's zone; if there is none, the nearest
    outside the zones of the robots that just beat this one (``ctx.winners``, empty unless
    ``conflict_yield``), and only then the nearest of all ("prefers")."""
    return _nearest(ctx, exclusion_candidates(ctx))


def nearest_candidate(ctx: GoalContext, idx: np.ndarray) -> Cell | None:
    """The goal a nearest-candidate strategy picks among ``idx`` (:func:`_nearest`)."""
    return _nearest(ctx, idx)


def _rivals_and_costs(ctx: GoalContext) -> tuple[np.ndarray, np.ndarray]:
    """Targets and a (robots × targets) step matrix; row 0 is this robot (inf unreachable)."""
    targets = chunk_targets(ctx.frontiers, ctx.eligible, ctx.laser_cells)
    rows = [ctx.dist[targets].astype(np.float64)]
    if ctx.field_from is not None:
        ty, tx = ctx.frontiers.ys[targets], ctx.frontiers.xs[targets]
        for rid in sorted(ctx.team_pos):
            f = ctx.field_from(ctx.team_pos[rid])
            rows.append(f[ty, tx].astype(np.float64))
    cost = np.vstack(rows)
    cost[cost < 0] = np.inf
    return targets, cost


def _cell(ctx: GoalContext, i: int) -> Cell:
    return int(ctx.frontiers.xs[i]), int(ctx.frontiers.ys[i])


def utility(ctx: GoalContext, beta: float = 1.0) -> Cell | None:
    targets, cost = _rivals_and_costs(ctx)
    if targets.size == 0 or not np.isfinite(cost[0]).any():
        return None
    finite = cost[np.isfinite(cost)]
    v = cost / max(float(finite.max()), 1.0)
    tx = ctx.frontiers.xs[targets].astype(np.float64)
    ty = ctx.frontiers.ys[targets].astype(np.float64)
    u = np.ones(targets.size)
    free_robots = list(range(cost.shape[0]))
    while free_robots:
        score = u[None, :] - beta * v[free_robots]
        score[~np.isfinite(score)] = -np.inf
        flat = int(np.argmax(score))  # ties: lowest robot row, then lowest target
        r, t = divmod(flat, targets.size)
        robot = free_robots[r]
        if not np.isfinite(score[r, t]):
            break
        if robot == 0:
            return _cell(ctx, int(targets[t]))
        free_robots.pop(r)
        d = np.hypot(tx - tx[t], ty - ty[t])
        u -= np.clip(1.0 - d / ctx.laser_cells, 0.0, 1.0)
    return _nearest(ctx, np.nonzero(ctx.eligible)[0])


def minpos(ctx: GoalContext) -> Cell | None:
    targets, cost = _rivals_and_costs(ctx)
    mine = cost[0]
    ok = np.isfinite(mine)
    if not ok.any():
        return None
    rank = (cost[1:] < mine[None, :]).sum(axis=0)
    order = np.lexsort((targets, mine, rank))
    order = order[ok[order]]
    return _cell(ctx, int(targets[order[0]]))


def hungarian(ctx: GoalContext) -> Cell | None:
    from scipy.optimize import linear_sum_assignment  # here: scipy.optimize is slow to import

    targets, cost = _rivals_and_costs(ctx)
    if targets.size == 0 or not np.isfinite(cost[0]).any():
        return None
    n_r, n_t = cost.shape
    reps = -(-n_r // n_t)
    big = np.where(np.isfinite(cost), cost, 1e9)
    rows, cols = linear_sum_assignment(np.tile(big, (1, reps)))
    col = int(cols[rows.tolist().index(0)]) % n_t
    if not np.isfinite(cost[0, col]):
        return _nearest(ctx, np.nonzero(ctx.eligible)[0])
    return _cell(ctx, int(targets[col]))


def _assignment(ctx: GoalContext) -> Cell | None:
    """The target the minimum-sum assignment gives this robot (row 0), over the targets
    outside the neighbours' goal zones when this robot can reach one of them."""
    from scipy.optimize import linear_sum_assignment

    targets, cost = _rivals_and_costs(ctx)
    if targets.size == 0 or not np.isfinite(cost[0]).any():
        return None
    free = ~excluded(ctx, targets)
    if free.any() and np.isfinite(cost[0, free]).any():
        targets, cost = targets[free], cost[:, free]
    n_r, n_t = cost.shape
    reps = -(-n_r // n_t)
    big = np.where(np.isfinite(cost), cost, 1e9)
    rows, cols = linear_sum_assignment(np.tile(big, (1, reps)))
    col = int(cols[rows.tolist().index(0)]) % n_t
    return _cell(ctx, int(targets[col])) if np.isfinite(cost[0, col]) else None


#: rivals in view from which ``hungarian-exclusion`` assigns (below: greedy-exclusion)
ASSIGN_MIN_RIVALS = 2


def hungarian_exclusion(ctx: GoalContext) -> Cell | None:
    if len(ctx.team_pos) < ASSIGN_MIN_RIVALS:
        return greedy_exclusion(ctx)
    target = _assignment(ctx)
    if target is None:
        return greedy_exclusion(ctx)
    idx = np.nonzero(ctx.eligible)[0]
    near = idx[_within(ctx, idx, {0: target})]
    return _nearest(ctx, near) if near.size else target


def _cheapest(ctx: GoalContext, idx: np.ndarray, cost: np.ndarray) -> Cell | None:
    """The candidate of least ``cost``; ties as :func:`_nearest` (current goal, then (y, x))."""
    if idx.size == 0:
        return None
    best = idx[cost == cost.min()]
    if ctx.current_goal is not None:
        gx, gy = ctx.current_goal
        same = best[(ctx.frontiers.xs[best] == gx) & (ctx.frontiers.ys[best] == gy)]
        if same.size:
            return (gx, gy)
    i = best[np.lexsort((ctx.frontiers.xs[best], ctx.frontiers.ys[best]))[0]]
    return int(ctx.frontiers.xs[i]), int(ctx.frontiers.ys[i])


#: a pocket's path cost is multiplied by this (``pocket-exclusion``)
POCKET_DISCOUNT = 0.5


def pocket_regions(fr: Frontiers, extent: float) -> np.ndarray:
    """Per region: whether it fits in a square of side ``extent`` cells (one visit clears it)."""
    k = fr.n_regions
    if k == 0:
        return np.zeros(0, dtype=bool)
    big = np.iinfo(np.int64).max
    lo_x = np.full(k, big, dtype=np.int64)
    lo_y = np.full(k, big, dtype=np.int64)
    hi_x = np.full(k, -1, dtype=np.int64)
    hi_y = np.full(k, -1, dtype=np.int64)
    np.minimum.at(lo_x, fr.region, fr.xs)
    np.minimum.at(lo_y, fr.region, fr.ys)
    np.maximum.at(hi_x, fr.region, fr.xs)
    np.maximum.at(hi_y, fr.region, fr.ys)
    return np.maximum(hi_x - lo_x, hi_y - lo_y) <= extent


def pocket_exclusion(ctx: GoalContext, discount: float = POCKET_DISCOUNT,
                     extent: float = 1.0) -> Cell | None:
    """greedy-exclusion's candidates, ranked by path length with a pocket's (a region within
    ``extent`` laser ranges square) multiplied by ``discount``; ties as :func:`_nearest`.
    0.5 and 1 were the best of 0.15–0.5 and 1–2 on the short-radio world (4 seeds)."""
    idx = exclusion_candidates(ctx)
    if idx.size == 0:
        return None
    cost = ctx.dist[idx].astype(np.float64)
    pocket = pocket_regions(ctx.frontiers, extent * ctx.laser_cells)[ctx.frontiers.region[idx]]
    cost[pocket] *= discount
    return _cheapest(ctx, idx, cost)


@dataclass(frozen=True)
class Strategy:
    name: str
    choose: Callable[[GoalContext], Cell | None]
    exclusion: bool = False  # honours neighbours' goals (and so wants GOAL messages)
    priorities: bool = False  # resolves goal conflicts by distance priority / CHANGE_GOAL
    needs_rivals: bool = False  # needs distance fields from neighbours' cells
    # the goal is the nearest (by steps, ``_nearest``'s ties) of these candidates, which
    # depend on positions only: a planner then needs distances only up to the nearest one
    # (ctx.dist unset when it is called) and does not call ``choose``; a copy that
    # replaces ``choose`` must set this to None
    candidates: Callable[[GoalContext], np.ndarray] | None = None
    # a finished robot walks back to its start (still finished: its map has no frontier),
    # where the team's finished robots meet and a robot that missed their scans finds them
    home_when_done: bool = False


STRATEGIES: dict[str, Strategy] = {
    "greedy": Strategy("greedy", greedy, candidates=greedy_candidates),
    "greedy-exclusion": Strategy(
        "greedy-exclusion", greedy_exclusion, exclusion=True, priorities=True,
        candidates=exclusion_candidates,
    ),
    "utility": Strategy("utility", utility, needs_rivals=True),
    "minpos": Strategy("minpos", minpos, needs_rivals=True),
    "hungarian": Strategy("hungarian", hungarian, needs_rivals=True),
    "hungarian-exclusion": Strategy(
        "hungarian-exclusion", hungarian_exclusion, exclusion=True, priorities=True,
        needs_rivals=True,
    ),
    "pocket-exclusion": Strategy(
        "pocket-exclusion", pocket_exclusion, exclusion=True, priorities=True,
        home_when_done=True,
    ),
}


def get_strategy(name: str) -> Strategy:
    try:
        return STRATEGIES[name]
    except KeyError:
        raise InputError(
            f"--strategy must be one of {', '.join(STRATEGIES)}, got {name!r}"
        ) from None
