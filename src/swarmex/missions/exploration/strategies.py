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
* ``adaptive-exclusion`` — ours (issue 17 item 2): the thesis's GOAL messages, zones and
  priorities throughout, and four rules, each from a measured cause (docs/exploration.md):

  - *re-plan when the goal's region has vanished*: the robot keeps the cells of its goal's
    frontier region and re-plans at once (an unscheduled plan, ``"seen"``) when none of
    them borders the unknown any more — its own or a teammate's scan has seen what lay
    behind. greedy-exclusion walks on to such a goal until it arrives or its 2 s timer
    fires: in rooms and aisles, which a robot sees from the door long before it reaches the
    frontier cell it chose, that walk is most of the wasted time. A region that only
    shrinks (the open world's long frontier) does not trigger it: re-planning whenever the
    goal *cell* is seen made the robots chase the receding frontier (1637 steps against
    942 with the short radio);

  - *the assignment by team size*: with at least :data:`ASSIGN_MIN_TEAM` robots in the team
    (the robot counts the ids it has heard) it is ``hungarian-exclusion``; below, it is
    greedy-exclusion with the two rules below. The assignment's gain grows with the team
    even with an unlimited radio (open 20 × 20 m world, laser 1.5 m: 5 robots +4 %, 6 −3 %,
    7 −7 %, 10 −18 %, 3–8 seeds each); room-32-32-4's team of 6 took 65.0 steps with the
    switch at 6 against 68.0 at 7 on seeds 0–19, and 63.8 against 65.4 on seeds 20–39;
  - *pockets first*: a frontier cell next to an unknown *pocket* (an 8-connected unknown
    component, bounded by known cells and the map's edge, at least half of the known cells
    around it free (an opening, not an obstacle's inside), of at most π·laser² cells: one
    visit clears it) costs half its path length. Greedy follows the big frontier and leaves
    slivers at walls that a whole team later crosses the map for (a 30-cell one left at
    tick 550 kept five robots busy until tick 1066);
  - *a rendezvous for a lonely robot*: a robot that has heard no teammate for
    :data:`ALONE_TICKS` ticks walks back to its start, once per contact (the start is the one
    place every robot knows and the team's paths cross; with a short radio a robot that
    lost the team otherwise re-explores alone what the others mapped: +430 steps in one
    seed).

  No extra message. Cost: a full distance field per plan (as ``hungarian``), the unknown
  components once per map state, a test of the goal region's cells per tick, and the
  assignment's fields in large teams.

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
from typing import Any

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
    # ``OccupancyGrid.derived`` of the robot's map: ``derived(key, make)`` is
    # ``make(logodds)``, computed once per map state
    derived: Callable[[Any, Callable[[np.ndarray], Any]], Any] | None = None
    start: Cell | None = None  # where the robot was deployed
    team_size: int = 1  # 1 + the highest robot id it has heard (ids are 0 … n − 1)
    alone: int = 0  # ticks since it last heard a teammate (0 once it has been back at start)


def _nearest(ctx: GoalContext, idx: np.ndarray) -> Cell | None:
    """The candidate with the fewest steps; ties keep the current goal, then (y, x) order."""
    return _cheapest(ctx, idx, ctx.dist[idx])


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
    """The candidate of least ``cost``; ties keep the current goal, then (y, x) order."""
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


#: a frontier cell next to an unknown pocket costs this share of its path length
POCKET_DISCOUNT = 0.5
#: team size from which ``adaptive-exclusion`` assigns (``hungarian-exclusion``)
ASSIGN_MIN_TEAM = 6
#: ticks without hearing a teammate after which a robot walks back to its start
ALONE_TICKS = 150


#: a pocket is an opening: at least this share of the known cells around it are free
POCKET_FREE_SHARE = 0.5


def _unknown_components(lo: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """8-connected components of the unknown cells: (labels, cells per label), label 0 is
    known. A component whose known surroundings (its known 8-neighbours) are less than
    :data:`POCKET_FREE_SHARE` free is the inside of an obstacle seen from outside (a shelf
    whose faces the laser hit), which no visit clears: its size is given as the largest
    integer, so it is never a pocket. Without this test, the warehouse's shelf insides drew
    a team of 4 robots to frontiers it could not clear (586 steps against greedy-exclusion's
    516, 10 seeds; with it 411)."""
    from scipy import ndimage

    unknown = lo == 0
    lab, count = ndimage.label(unknown, structure=np.ones((3, 3), dtype=bool))
    h, w = lo.shape
    padded = np.pad(lab, 1)
    free = np.zeros(count + 1)
    occupied = np.zeros(count + 1)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx or dy:
                near = padded[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w]
                rim = ~unknown & (near > 0)
                free += np.bincount(near[rim & (lo < 0)], minlength=count + 1)
                occupied += np.bincount(near[rim & (lo > 0)], minlength=count + 1)
    sizes = np.bincount(lab.ravel(), minlength=count + 1)
    opening = free >= POCKET_FREE_SHARE * np.maximum(free + occupied, 1)
    return lab, np.where(opening, sizes, np.iinfo(np.int64).max)


def pocket_cells(ctx: GoalContext, idx: np.ndarray) -> np.ndarray:
    """Which candidates border only unknown openings of at most π·laser² cells (pockets)."""
    if ctx.derived is None or idx.size == 0:
        return np.zeros(idx.size, dtype=bool)
    lab, sizes = ctx.derived(("unknown-openings", POCKET_FREE_SHARE), _unknown_components)
    h, w = lab.shape
    xs, ys = ctx.frontiers.xs[idx], ctx.frontiers.ys[idx]
    biggest = np.zeros(idx.size, dtype=np.int64)
    for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        near = lab[np.clip(ys + dy, 0, h - 1), np.clip(xs + dx, 0, w - 1)]
        biggest = np.maximum(biggest, np.where(near > 0, sizes[near], 0))
    return biggest <= math.pi * ctx.laser_cells**2


def pocket_exclusion(ctx: GoalContext, discount: float = POCKET_DISCOUNT) -> Cell | None:
    """greedy-exclusion's candidates by path length, a pocket's multiplied by ``discount``
    (with the short radio 0.5 gave 956 steps and 0.25 gave 1028, 20 seeds; lower values
    send robots back for pockets they have just passed)."""
    idx = exclusion_candidates(ctx)
    if idx.size == 0:
        return None
    cost = ctx.dist[idx].astype(np.float64)
    cost[pocket_cells(ctx, idx)] *= discount
    return _cheapest(ctx, idx, cost)


def adaptive_exclusion(ctx: GoalContext) -> Cell | None:
    """The rendezvous if the robot has been alone :data:`ALONE_TICKS` ticks (its start, when
    its map knows a way back), else ``hungarian-exclusion`` in a team of at least
    :data:`ASSIGN_MIN_TEAM`, else :func:`pocket_exclusion` (see the module docstring)."""
    if not ctx.eligible.any():
        return None  # finished: no rendezvous walk would un-finish it
    home = ctx.start
    if (ctx.alone >= ALONE_TICKS and home is not None and ctx.pos != home
            and ctx.field_from is not None and ctx.field_from(ctx.pos)[home[1], home[0]] > 0):
        return home  # a path back exists on its map
    if ctx.team_size >= ASSIGN_MIN_TEAM:
        return hungarian_exclusion(ctx)
    return pocket_exclusion(ctx)


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
    # re-plan at once when the goal's frontier region has vanished from the map (what lay
    # behind it has been seen), instead of walking on to the goal or the timer
    replan_when_seen: bool = False


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
    "adaptive-exclusion": Strategy(
        "adaptive-exclusion", adaptive_exclusion, exclusion=True, priorities=True,
        needs_rivals=True, replan_when_seen=True,
    ),
}


def get_strategy(name: str) -> Strategy:
    try:
        return STRATEGIES[name]
    except KeyError:
        raise InputError(
            f"--strategy must be one of {', '.join(STRATEGIES)}, got {name!r}"
        ) from None
