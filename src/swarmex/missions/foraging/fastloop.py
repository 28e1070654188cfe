"""The transport tail of a run, compiled with numba.

Once every robot is in the Transportation phase (after the last one finished communicating),
each round is the same small computation — Look (join, hand-overs, drops, pick-ups), options,
collision resolution, move — and it is most of a run's rounds (each of k = 100 units crosses
the nest–food distance). This module is a line-by-line port of that part of
:class:`~swarmex.missions.foraging.sim.Mission` (``transport_look``, ``options``, ``step`` and
:func:`~swarmex.missions.foraging.resolve.resolve` with its priority order) to arrays, so the
result is identical to the pure-Python loop; the test suite checks that on many runs.

A *hooked* run (the PettingZoo environment: every round's moves come from the caller) cannot
play many rounds per call, so it gets one-round kernels instead: :func:`hooked_round` (every
robot transports) and :func:`explore_round` (nobody knows the food yet), each the pending
Move with the caller's moves, then the next Look and the seed's Compute, ported line by line
from ``Mission.hooked_step`` and sharing the tail's Look and options.

A plain run's communication phase (from the discovery until every robot transports, the
mixed rounds where some already carry included) is :func:`comm_rounds`, a line-by-line port
of ``Mission.look`` and ``step`` for those rounds under both rules of :mod:`.comm`: who
learns and from whom, the seed rule's word (bit sets per robot) and cross-off, the lists'
best order, the meeting goals, and the transport Look, options, priority and resolution
shared with the tail. Its frozen-crowd rule is ``Mission.step``'s for both phases: the tail's
``memo`` once everyone transports, else the ``mixed`` memory of the last two rounds' whole
state (:func:`_same_as_mixed`, ``Mission.mixed_key``). With many robots that phase was most
of a run in Python (1,024 robots on 1024²: about 1,200 rounds, 4 s of a 4.2 s run). A run
with frames plays it one round per call (each call stops after a Look); a hooked run (every
round's moves come from the caller) still plays it in Python.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel

# tmode codes (same as sim.py)
JOIN, RELAY, E2E, IDLE = 0, 1, 2, 3
MAXOPT = 6  # the longest list is 5 (4 side cells + stay): one slot left for the last resort

I64 = NDArray[np.int64]  # numba ignores these annotations (postponed); mypy checks the calls
Bools = NDArray[np.bool_]
I32 = NDArray[np.int32]


@kernel(cache=True)
def _sidesteps(opts: I64, k: int, x: int, y: int, g: int) -> int:
    for dx, dy in ((1, 0), (0, -1), (-1, 0), (0, 1)):
        nx, ny = x + dx, y + dy
        if 0 <= nx < g and 0 <= ny < g:
            opts[k, 0] = nx
            opts[k, 1] = ny
            k += 1
    return k


@kernel(cache=True)
def _free_sides(opts: I64, k: int, x: int, y: int, g: int) -> int:
    """Append the side cells not already among ``opts[:k]`` (the frozen-crowd rule)."""
    first = k
    for dx, dy in ((1, 0), (0, -1), (-1, 0), (0, 1)):
        nx, ny = x + dx, y + dy
        if not (0 <= nx < g and 0 <= ny < g):
            continue
        seen = False
        for j in range(first):
            if opts[j, 0] == nx and opts[j, 1] == ny:
                seen = True
        if not seen:
            opts[k, 0] = nx
            opts[k, 1] = ny
            k += 1
    return k


def transport_memo(key: tuple[Any, ...] | None, n: int) -> I64:
    """The compiled loop's copy of ``Mission.transport_key`` (its layout: see _same_as_memo)."""
    memo = np.full(3 + 5 * n, -1, dtype=np.int64)
    if key is not None:
        pos, carrying, tmode, pidx, units, delivered = key
        memo[:3] = (1, units, delivered)
        for a in range(n):
            memo[3 + 5 * a : 8 + 5 * a] = (*pos[a], int(carrying[a]), tmode[a], pidx[a])
    return memo


def memo_key(memo: I64, n: int) -> tuple[Any, ...] | None:
    """``Mission.transport_key`` back from a memo (:func:`transport_memo`'s inverse)."""
    if memo[0] != 1:
        return None
    rows = memo[3 : 3 + 5 * n].reshape(n, 5).tolist()
    return (
        tuple((x, y) for x, y, *_ in rows),
        tuple(bool(r[2]) for r in rows),
        tuple(r[3] for r in rows),
        tuple(r[4] for r in rows),
        int(memo[1]),
        int(memo[2]),
    )


@kernel(cache=True)
def _same_as_memo(
    memo: I64, pos: I64, carrying: Bools, tmode: I64, pidx: I64, units: int, delivered: int
) -> bool:
    """Whether the transport state equals the one stored in ``memo``; stores the new one.

    Layout: [valid, units, delivered, then per robot x, y, carrying, tmode, pidx].
    """
    same = memo[0] == 1 and memo[1] == units and memo[2] == delivered
    memo[0] = 1
    memo[1] = units
    memo[2] = delivered
    for a in range(pos.shape[0]):
        base = 3 + 5 * a
        vals = (pos[a, 0], pos[a, 1], 1 if carrying[a] else 0, tmode[a], pidx[a])
        for j in range(5):
            if memo[base + j] != vals[j]:
                same = False
            memo[base + j] = vals[j]
    return same


@kernel(cache=True)
def _toward(opts: I64, k: int, x: int, y: int, qx: int, qy: int) -> int:
    if qx != x:
        opts[k, 0] = x + (1 if qx > x else -1)
        opts[k, 1] = y
        k += 1
    if qy != y:
        opts[k, 0] = x
        opts[k, 1] = y + (1 if qy > y else -1)
        k += 1
    return k


@kernel(cache=True)
def _resolve(
    cur: I64, opts: I64, nopt: I64, order: I64, nest_x: int, nest_y: int, choice: I64,
    cells: I64,
) -> None:  # fmt: skip
    """Collision resolution (``resolve.resolve``): robots claim their wished cell in
    ``order``; on a clash one of the two is bumped to its next wish and the pass is played
    again. The pass before the bumped robot's rank is unchanged by the bump, so it resumes
    there (claims of later ranks are rolled back) instead of restarting: the same choices as
    a restart, in O(n) per bump instead of O(n) per bump *and* per claim. ``cells`` (g x g,
    all -1) maps a claimed cell to its robot and is all -1 again on return. A robot bumped
    past its list gets its own cell appended to ``opts``/``nopt`` as its last resort."""
    n = cur.shape[0]
    for a in range(n):
        choice[a] = 0
    rank = np.empty(n, np.int64)
    for r in range(n):
        rank[order[r]] = r
    owner_x = np.empty(n, np.int64)
    owner_y = np.empty(n, np.int64)
    owner_a = np.empty(n, np.int64)
    m = 0
    r = 0
    while r < n:
        a = order[r]
        cx = opts[a, choice[a], 0]
        cy = opts[a, choice[a], 1]
        if cx == nest_x and cy == nest_y:
            r += 1
            continue
        b = cells[cx, cy]
        if b < 0:
            cells[cx, cy] = a
            owner_x[m] = cx
            owner_y[m] = cy
            owner_a[m] = a
            m += 1
            r += 1
            continue
        stayer = -1
        if cx == cur[a, 0] and cy == cur[a, 1]:
            stayer = a
        elif cx == cur[b, 0] and cy == cur[b, 1]:
            stayer = b
        if stayer >= 0:
            other = b if stayer == a else a
            bumped = stayer if choice[stayer] + 1 < nopt[stayer] else other
        else:
            bumped = a
        choice[bumped] += 1
        if choice[bumped] == nopt[bumped]:
            # past its list (an idle robot hemmed in): its own cell is the last resort, as
            # in resolve.resolve; a free slot is left for it (MAXOPT > the longest list)
            k = nopt[bumped]
            if k >= opts.shape[1]:
                raise RuntimeError("collision resolution: no slot for the last resort")
            opts[bumped, k, 0] = cur[bumped, 0]
            opts[bumped, k, 1] = cur[bumped, 1]
            nopt[bumped] = k + 1
        r = rank[bumped]
        while m > 0 and rank[owner_a[m - 1]] >= r:
            m -= 1
            cells[owner_x[m], owner_y[m]] = -1
    for j in range(m):
        cells[owner_x[j], owner_y[j]] = -1


@kernel(cache=True)
def _resolved(
    cur: I64, opts: I64, nopt: I64, ranked: Bools, nest: I64, cells: I64
) -> I64:  # fmt: skip
    """Each robot's resolved wish (an index into its ``opts`` row): the priority order
    (:func:`_order`), then the claims (:func:`_resolve`). Per call: the round-per-call
    kernels' form; the transport tail reuses its own arrays."""
    n = cur.shape[0]
    order = np.empty(n, np.int64)
    choice = np.zeros(n, np.int64)
    _order(cur, opts, order, ranked, cells)
    _resolve(cur, opts, nopt, order, nest[0], nest[1], choice, cells)
    return choice


@kernel(cache=True)
def _order(cur: I64, opts: I64, out: I64, ranked: Bools, cells: I64) -> None:
    """Priority: swap pairs first, then route followers (``ranked``), then larger (x, y),
    then smaller id (resolve.priority). ``cells`` (g x g, all -1, left so) finds the robot
    standing on a cell in O(1): the last one by id, as the dict of ``resolve`` keeps it.
    The key is unique (the id is in it), so one integer per robot sorted by any algorithm
    gives the order of the tuples."""
    n = cur.shape[0]
    g = cells.shape[0]
    for c in range(n):
        cells[cur[c, 0], cur[c, 1]] = c
    key = np.empty(n, np.int64)
    for a in range(n):
        b = cells[opts[a, 0, 0], opts[a, 0, 1]]
        swap = b >= 0 and b != a and opts[b, 0, 0] == cur[a, 0] and opts[b, 0, 1] == cur[a, 1]
        k = (0 if swap else 1) * 2 + (0 if ranked[a] else 1)
        key[a] = ((k * g + (g - 1 - cur[a, 0])) * g + (g - 1 - cur[a, 1])) * n + a
    for c in range(n):
        cells[cur[c, 0], cur[c, 1]] = -1
    idx = np.argsort(key)
    for a in range(n):
        out[a] = idx[a]


@kernel(cache=True)
def _write_row(history: NDArray[np.integer[Any]], row: int, pos: I64) -> None:
    """Every robot's cell after this round's Look into row ``row`` of the trajectory."""
    for a in range(pos.shape[0]):
        history[row, a, 0] = pos[a, 0]
        history[row, a, 1] = pos[a, 1]


@kernel(cache=True)
def _relay_moved(a: int, nx: int, ny: int, path_of: I64, pidx: I64, tmode: I64) -> None:
    """``Mission._move`` for a relay robot that moved to ``(nx, ny)``: a step along the
    path moves its index; anywhere else (a side step) it leaves the relay, idle."""
    j = path_of[nx, ny]
    if j >= 0 and abs(j - pidx[a]) == 1:
        pidx[a] = j
    else:
        tmode[a] = IDLE


@kernel(cache=True)
def _transport_look_once(
    pos: I64, carrying: Bools, tmode: I64, pidx: I64, join_at: I64, state: I64, path: I64,
    nest: I64, food: I64, relay: bool, jobs: I64, handovers: I64, cells: I64,
) -> None:  # fmt: skip
    """:func:`_transport_look` with its scratch arrays made here: the round-per-call
    kernels' form (the transport tail keeps its own across rounds)."""
    n = pos.shape[0]
    was = np.empty(n, np.bool_)
    busy = np.zeros(n, np.bool_)
    _transport_look(
        pos, carrying, tmode, pidx, join_at, state, path, nest, food, relay, jobs, handovers,
        was, busy, cells,
    )  # fmt: skip


@kernel(cache=True)
def _transport_look(
    pos: I64, carrying: Bools, tmode: I64, pidx: I64, join_at: I64, state: I64, path: I64,
    nest: I64, food: I64, relay: bool, jobs: I64, handovers: I64, was: Bools, busy: Bools,
    cells: I64,
) -> None:  # fmt: skip
    """One round's Look (``Mission.transport_look``): join, hand-overs, drops, pick-ups;
    ``was`` and ``busy`` are scratch arrays of n, ``cells`` a g x g one (all -1, left so)."""
    n = pos.shape[0]
    t = state[0]
    if relay:
        for a in range(n):
            if tmode[a] == JOIN:
                j = join_at[a]
                if pos[a, 0] == path[j, 0] and pos[a, 1] == path[j, 1]:
                    tmode[a] = RELAY
                    pidx[a] = j
        for a in range(n):
            was[a] = carrying[a]
            busy[a] = False
        for c in range(n):  # the last RELAY robot on each cell, as the dict in sim.py
            if tmode[c] == RELAY:
                cells[pos[c, 0], pos[c, 1]] = c
        for b in range(n):
            if tmode[b] != RELAY or not was[b] or pidx[b] < 2:
                continue
            a = cells[path[pidx[b] - 1, 0], path[pidx[b] - 1, 1]]
            if a < 0 or was[a] or busy[a] or busy[b]:
                continue
            carrying[a] = True
            carrying[b] = False
            handovers[b] += 1
            busy[a] = True
            busy[b] = True
        for c in range(n):
            if tmode[c] == RELAY:
                cells[pos[c, 0], pos[c, 1]] = -1
    for a in range(n):
        if tmode[a] != RELAY and tmode[a] != E2E:
            continue
        if carrying[a] and pos[a, 0] == nest[0] and pos[a, 1] == nest[1]:
            carrying[a] = False
            state[2] += 1
            jobs[state[4], 0] = t
            jobs[state[4], 1] = a
            jobs[state[4], 2] = 1
            state[4] += 1
        elif (not carrying[a]) and pos[a, 0] == food[0] and pos[a, 1] == food[1] and state[1]:
            carrying[a] = True
            state[1] -= 1
            jobs[state[4], 0] = t
            jobs[state[4], 1] = a
            jobs[state[4], 2] = 0
            state[4] += 1


@kernel(cache=True)
def _transport_options(
    pos: I64, carrying: Bools, tmode: I64, pidx: I64, join_at: I64, units: int, path: I64,
    nest: I64, food: I64, g: int, frozen: bool, opts: I64, nopt: I64,
) -> None:  # fmt: skip
    """Every robot's ordered wishes (``Mission.options`` for the Transportation phase): cells
    in ``opts[a, :nopt[a]]``. A relay robot at the food end with no unit left goes idle."""
    n = pos.shape[0]
    L = path.shape[0]
    for a in range(n):
        x, y = pos[a, 0], pos[a, 1]
        k = 0
        tm = tmode[a]
        if tm == E2E:
            if (not carrying[a]) and units == 0:
                opts[a, 0, 0] = x
                opts[a, 0, 1] = y
                k = _sidesteps(opts[a], 1, x, y, g)
            else:
                if carrying[a]:
                    k = _toward(opts[a], 0, x, y, nest[0], nest[1])
                else:
                    k = _toward(opts[a], 0, x, y, food[0], food[1])
                if frozen and k > 0:
                    k = _free_sides(opts[a], k, x, y, g)
                opts[a, k, 0] = x
                opts[a, k, 1] = y
                k += 1
        elif tm == JOIN:
            j = join_at[a]
            k = _toward(opts[a], 0, x, y, path[j, 0], path[j, 1])
            opts[a, k, 0] = x
            opts[a, k, 1] = y
            k += 1
        elif tm == RELAY:
            i = pidx[a]
            if carrying[a]:
                if i > 0:
                    opts[a, 0, 0] = path[i - 1, 0]
                    opts[a, 0, 1] = path[i - 1, 1]
                    opts[a, 1, 0] = x
                    opts[a, 1, 1] = y
                    k = 2
                else:
                    opts[a, 0, 0] = x
                    opts[a, 0, 1] = y
                    k = 1
            elif i < L - 1:
                opts[a, 0, 0] = path[i + 1, 0]
                opts[a, 0, 1] = path[i + 1, 1]
                opts[a, 1, 0] = x
                opts[a, 1, 1] = y
                k = 2
            elif units == 0:
                tmode[a] = IDLE
                opts[a, 0, 0] = x
                opts[a, 0, 1] = y
                k = _sidesteps(opts[a], 1, x, y, g)
            else:
                opts[a, 0, 0] = x
                opts[a, 0, 1] = y
                k = 1
        else:
            opts[a, 0, 0] = x
            opts[a, 0, 1] = y
            k = _sidesteps(opts[a], 1, x, y, g)
        nopt[a] = k


@kernel(cache=True)
def transport_tail(
    pos: I64, carrying: Bools, tmode: I64, pidx: I64, join_at: I64, state: I64, path: I64,
    path_of: I64, nest: I64, food: I64, relay: bool, history: I64, jobs: I64, handovers: I64,
    memo: I64, cells: I64,
) -> int:  # fmt: skip
    """Play rounds until done or ``history`` is full.

    ``state`` = [t, units, delivered, k, n_jobs, rows_written, done]; positions after each
    Look are written to ``history``; jobs as rows (t, agent, kind 0=pickup 1=drop).
    ``memo`` holds the previous round's state after Look, for the frozen-crowd rule of
    ``Mission.step``; ``cells`` is a g x g scratch grid of -1 (left so), the index that keeps
    each round O(robots).
    """
    n = pos.shape[0]
    g = path_of.shape[0]
    opts = np.empty((n, MAXOPT, 2), np.int64)
    nopt = np.zeros(n, np.int64)
    order = np.empty(n, np.int64)
    choice = np.zeros(n, np.int64)
    was = np.empty(n, np.bool_)
    busy = np.zeros(n, np.bool_)
    unranked = np.zeros(n, np.bool_)  # no robot follows a route in this phase
    rows = 0
    while rows < history.shape[0]:
        t = state[0]
        # ---- Look: join, hand-overs, drops, pick-ups
        _transport_look(
            pos, carrying, tmode, pidx, join_at, state, path, nest, food, relay, jobs,
            handovers, was, busy, cells,
        )  # fmt: skip
        _write_row(history, rows, pos)
        rows += 1
        if state[2] >= state[3]:
            state[6] = 1
            break
        # ---- Compute: options
        frozen = _same_as_memo(memo, pos, carrying, tmode, pidx, state[1], state[2])
        _transport_options(
            pos, carrying, tmode, pidx, join_at, state[1], path, nest, food, g, frozen, opts,
            nopt,
        )  # fmt: skip
        # ---- Move
        _order(pos, opts, order, unranked, cells)
        _resolve(pos, opts, nopt, order, nest[0], nest[1], choice, cells)
        for a in range(n):
            nx, ny = opts[a, choice[a], 0], opts[a, choice[a], 1]
            if tmode[a] == RELAY and (nx != pos[a, 0] or ny != pos[a, 1]):
                _relay_moved(a, nx, ny, path_of, pidx, tmode)
            pos[a, 0] = nx
            pos[a, 1] = ny
        state[0] = t + 1
    state[5] = rows
    return rows


# ---------------------------------------------------------------- the hooked round
# hooked_round's answers (negative: -(a + 1), robot a's move is not a legal move code)
GOING, DONE, STOPPED, STALLED = 0, 1, 2, 3
STAY = 0
# (dx, dy) of the hook's move codes (hook.STEPS): stay, North, East, South, West
STEP_X = np.array([0, 0, 1, 0, -1], dtype=np.int64)
STEP_Y = np.array([0, -1, 0, 1, 0], dtype=np.int64)
# hooked_round's state vector: its slots
T, UNITS, DELIVERED, K, N_JOBS, ROW, STOP_AT, LIMIT, MOVED = range(9)


@kernel(cache=True)
def _entry_cell(path: I64, x: int, y: int) -> int:
    """``transport.entry_cell``: the path cell nearest (x, y), ties toward the food."""
    best, dist = 0, -1
    for i in range(path.shape[0]):
        d = abs(path[i, 0] - x) + abs(path[i, 1] - y)
        if dist < 0 or d <= dist:
            best, dist = i, d
    return best


@kernel(cache=True)
def _move_code(dx: int, dy: int) -> int:
    for m in range(5):
        if STEP_X[m] == dx and STEP_Y[m] == dy:
            return m
    return -1  # pragma: no cover - a wish is always the robot's cell or a neighbour


@kernel(cache=True)
def _bad_move(pos: I64, builtin: I64, moves: I64, g: int) -> int:
    """The first robot whose move (other than its seed move) is not a code or leaves the
    g×g grid, or -1 (``hook.hooked_options``'s checks)."""
    for a in range(pos.shape[0]):
        m = moves[a]
        if m == builtin[a]:
            continue
        if m < 0 or m > 4:
            return a
        nx, ny = pos[a, 0] + STEP_X[m], pos[a, 1] + STEP_Y[m]
        if not (0 <= nx < g and 0 <= ny < g):
            return a
    return -1


@kernel(cache=True)
def _hooked_wishes(
    pos: I64, opts: I64, nopt: I64, builtin: I64, moves: I64, chosen: I64, nchosen: I64,
    ranked: Bools,
) -> None:  # fmt: skip
    """``hook.hooked_options``: a robot whose move is its seed move keeps its wishes (staying
    as the last resort) and its rank; any other move is "that cell, else stay", unranked."""
    for a in range(pos.shape[0]):
        x, y = pos[a, 0], pos[a, 1]
        m = moves[a]
        if m == builtin[a]:
            k = nopt[a]
            for j in range(k):
                chosen[a, j, 0] = opts[a, j, 0]
                chosen[a, j, 1] = opts[a, j, 1]
            if opts[a, k - 1, 0] != x or opts[a, k - 1, 1] != y:
                chosen[a, k, 0] = x
                chosen[a, k, 1] = y
                k += 1
            nchosen[a] = k
            continue
        ranked[a] = False
        if m == STAY:
            chosen[a, 0, 0] = x
            chosen[a, 0, 1] = y
            nchosen[a] = 1
        else:
            chosen[a, 0, 0] = x + STEP_X[m]
            chosen[a, 0, 1] = y + STEP_Y[m]
            chosen[a, 1, 0] = x
            chosen[a, 1, 1] = y
            nchosen[a] = 2


@kernel(cache=True)
def hooked_round(
    pos: I64, carrying: Bools, tmode: I64, pidx: I64, join_at: I64, handovers: I64,
    state: I64, path: I64, path_of: I64, nest: I64, food: I64, relay: bool, opts: I64,
    nopt: I64, builtin: I64, moves: I64, history: I32, jobs: I64, memo: I64, cells: I64,
) -> int:  # fmt: skip
    """One round of a *hooked* run in the Transportation phase (every robot transports):
    the Move of the pending round with the caller's ``moves`` (when ``state[MOVED]``), then
    the next round's Look and Compute. A line-by-line port of ``Mission.hooked_step`` with
    :func:`~swarmex.missions.foraging.hook.hooked_options` (a robot whose move is its seed
    move keeps its wishes, any other move is "that cell, else stay"), the priority order and
    resolution, ``Mission._move``'s rule for a relay robot moved off the path (it re-joins at
    its nearest path cell), then ``transport_look`` and ``options`` as in
    :func:`transport_tail`.

    ``state`` = [t, units, delivered, k, n_jobs, row, stop_at, limit, moved]: the position
    after the Look goes to ``history[row]`` (row is then advanced); jobs as in
    :func:`transport_tail`. The seed's wishes are left in ``opts``/``nopt`` and their move
    codes in ``builtin``. Returns GOING (a Compute is pending), DONE (k units home),
    STOPPED (round ``stop_at`` reached), STALLED (round ``limit`` reached), or ``-(a + 1)``
    when robot ``a``'s move is not a code or leaves the grid (nothing is changed then).
    """
    n = pos.shape[0]
    g = path_of.shape[0]
    if state[MOVED]:
        bad = _bad_move(pos, builtin, moves, g)
        if bad >= 0:
            return -(bad + 1)
        chosen = np.empty((n, MAXOPT, 2), np.int64)
        nchosen = np.empty(n, np.int64)
        ranked = np.zeros(n, np.bool_)  # no robot follows a route in this phase
        _hooked_wishes(pos, opts, nopt, builtin, moves, chosen, nchosen, ranked)
        choice = _resolved(pos, chosen, nchosen, ranked, nest, cells)
        for a in range(n):
            nx, ny = chosen[a, choice[a], 0], chosen[a, choice[a], 1]
            if tmode[a] == RELAY and (nx != pos[a, 0] or ny != pos[a, 1]):
                j = path_of[nx, ny]
                if j >= 0 and abs(j - pidx[a]) == 1:
                    pidx[a] = j
                else:  # moved off the path by the hook: walk back and re-join
                    tmode[a] = JOIN
                    join_at[a] = _entry_cell(path, nx, ny)
            pos[a, 0] = nx
            pos[a, 1] = ny
        state[T] += 1
        state[MOVED] = 0
    # ---- Look
    _transport_look_once(
        pos, carrying, tmode, pidx, join_at, state, path, nest, food, relay, jobs, handovers,
        cells,
    )  # fmt: skip
    row = state[ROW]
    _write_row(history, row, pos)
    state[ROW] = row + 1
    if state[T] >= state[STOP_AT]:
        return STOPPED
    if state[DELIVERED] >= state[K]:
        return DONE
    if state[T] >= state[LIMIT]:
        return STALLED
    # ---- Compute: the seed's wishes and their moves
    frozen = _same_as_memo(memo, pos, carrying, tmode, pidx, state[UNITS], state[DELIVERED])
    _transport_options(
        pos, carrying, tmode, pidx, join_at, state[UNITS], path, nest, food, g, frozen, opts,
        nopt,
    )  # fmt: skip
    for a in range(n):
        builtin[a] = _move_code(opts[a, 0, 0] - pos[a, 0], opts[a, 0, 1] - pos[a, 1])
    return GOING


HANDOFF = 4  # explore_round: a robot stands on the food; the Look is the Python loop's


@kernel(cache=True)
def explore_round(
    pos: I64, delay: I64, displaced: Bools, state: I64, route: I32, t_end: int, g: int,
    nest: I64, food: I64, opts: I64, nopt: I64, following: Bools, builtin: I64, moves: I64,
    history: I32, cells: I64,
) -> int:  # fmt: skip
    """One round of a *hooked* run before anyone knows where the food is (every robot
    explores): the Move of the pending round with the caller's ``moves`` (when
    ``state[MOVED]``), then the next Look and Compute. A line-by-line port of
    ``Mission.hooked_step`` for that phase: ``options`` of an exploring robot (its route's
    next cell, the timetable ``route`` shifted by its ``delay``; once displaced from its
    route or past its end, stay or step aside), the hook's wishes, priority (route followers
    rank high) and resolution, ``_move``'s rules (a robot on its route that is held back
    waits: its delay grows; one that moves elsewhere is displaced). The Look is empty
    unless a robot stands on the food: then the Move is done, nothing else, and the answer
    is HANDOFF (the Python loop plays that Look, which informs it, and the rounds after).
    ``state`` and the other answers are :func:`hooked_round`'s."""
    n = pos.shape[0]
    if state[MOVED]:
        bad = _bad_move(pos, builtin, moves, g)
        if bad >= 0:
            return -(bad + 1)
        chosen = np.empty((n, MAXOPT, 2), np.int64)
        nchosen = np.empty(n, np.int64)
        ranked = following.copy()
        _hooked_wishes(pos, opts, nopt, builtin, moves, chosen, nchosen, ranked)
        choice = _resolved(pos, chosen, nchosen, ranked, nest, cells)
        for a in range(n):
            nx, ny = chosen[a, choice[a], 0], chosen[a, choice[a], 1]
            x, y = pos[a, 0], pos[a, 1]
            if not displaced[a]:  # on its route (every robot explores)
                _route_moved(a, x, y, nx, ny, opts, following, delay, displaced)
            pos[a, 0] = nx
            pos[a, 1] = ny
        state[T] += 1
        state[MOVED] = 0
    for a in range(n):
        if pos[a, 0] == food[0] and pos[a, 1] == food[1]:
            return HANDOFF
    row = state[ROW]
    _write_row(history, row, pos)
    state[ROW] = row + 1
    t = state[T]
    if t >= state[STOP_AT]:
        return STOPPED
    if t >= state[LIMIT]:
        return STALLED
    # ---- Compute: Mission.options of exploring robots
    for a in range(n):
        x, y = pos[a, 0], pos[a, 1]
        k = 1
        opts[a, 0, 0] = x
        opts[a, 0, 1] = y
        following[a] = False
        if not displaced[a]:
            k, following[a] = _route_wish(a, t, x, y, g, delay, route, t_end, opts)
        else:
            k = _sidesteps(opts[a], 1, x, y, g)
        nopt[a] = k
        builtin[a] = _move_code(opts[a, 0, 0] - x, opts[a, 0, 1] - y)
    return GOING


# ---------------------------------------------------------------- the timetable
@kernel(cache=True)
def timetable_rounds(
    flat: I64, start: I64, depart: I64, explore_from: I64, sync: bool, nest: I64, g: int,
    idx: I64, cur: I64, arrived: I64, state: I64, history: I32, cells: I64,
) -> int:  # fmt: skip
    """Play :func:`~swarmex.missions.foraging.timed.execute`'s rounds (every robot walks its
    route with no food) until all routes are walked or ``history`` is full; a line-by-line
    port of that loop, with the same options, priority and resolution as the Python rule.

    Robot ``a``'s route is ``flat[start[a]:start[a + 1]]``; ``idx`` its position on it,
    ``cur`` its cell, ``arrived`` the round it reached its Start-Cell (-1: not yet).
    ``state`` = [t, t_sync, done]; the cells after each round go to ``history``. Returns the
    rows written."""
    n = cur.shape[0]
    opts = np.empty((n, MAXOPT, 2), np.int64)
    nopt = np.zeros(n, np.int64)
    following = np.zeros(n, np.bool_)
    order = np.empty(n, np.int64)
    choice = np.zeros(n, np.int64)
    rows = 0
    while rows < history.shape[0]:
        going = False
        for a in range(n):
            if idx[a] < start[a + 1] - start[a] - 1:
                going = True
                break
        if not going:
            state[2] = 1
            break
        t = state[0]
        for a in range(n):
            if arrived[a] < 0 and idx[a] >= explore_from[a]:
                arrived[a] = t
        if state[1] < 0:
            everyone = True
            for a in range(n):
                if arrived[a] < 0:
                    everyone = False
                    break
            if everyone:
                state[1] = t
        for a in range(n):
            x, y = cur[a, 0], cur[a, 1]
            opts[a, 0, 0] = x
            opts[a, 0, 1] = y
            if idx[a] >= start[a + 1] - start[a] - 1:  # done: stay, else step aside
                nopt[a] = _sidesteps(opts[a], 1, x, y, g)
                following[a] = False
            elif t + 1 < depart[a] or (sync and idx[a] == explore_from[a] and state[1] < 0):
                nopt[a] = 1  # held in the nest or at the Start-Cell
                following[a] = True
            else:
                nxt = start[a] + idx[a] + 1
                opts[a, 0, 0] = flat[nxt, 0]
                opts[a, 0, 1] = flat[nxt, 1]
                opts[a, 1, 0] = x
                opts[a, 1, 1] = y
                nopt[a] = 2
                following[a] = True
        _order(cur, opts, order, following, cells)
        _resolve(cur, opts, nopt, order, nest[0], nest[1], choice, cells)
        for a in range(n):
            nx, ny = opts[a, choice[a], 0], opts[a, choice[a], 1]
            if idx[a] < start[a + 1] - start[a] - 1:
                nxt = start[a] + idx[a] + 1
                if nx == flat[nxt, 0] and ny == flat[nxt, 1]:
                    idx[a] += 1
            cur[a, 0] = nx
            cur[a, 1] = ny
            history[rows, a, 0] = nx
            history[rows, a, 1] = ny
        rows += 1
        state[0] = t + 1
    return rows


# ---------------------------------------------------------------- the communication phase
# Mission.mode codes (same as sim.py); NOT_YET: the tmode of a robot not transporting yet,
# which the transport Look must skip (sim.py's JOIN default would let it join the path)
EXPLORE, FOLLOW, COMM, TRANSPORT = 0, 1, 2, 3
NOT_YET = -1
# comm_rounds' state vector: transport_tail's first seven slots, then these
C_LIMIT, C_HOLDS, C_PENDING = 7, 8, 9
# comm_rounds' flags vector: its slots
F_OMNI, F_ONE_WAY, F_KEEP_EXPLORING, F_KEEP_DEPLOYING, F_RELAY_FOOD, F_T_SYNC = range(6)


@kernel(cache=True)
def _everyone_transports(mode: I64) -> bool:
    """Whether every robot is in the Transportation phase (the compiled tail's turn)."""
    for a in range(mode.shape[0]):  # noqa: SIM110 - numba compiles no generator in all()
        if mode[a] != TRANSPORT:
            return False
    return True


@kernel(cache=True)
def _on_route(mode: I64, displaced: Bools, a: int) -> bool:
    """``Mission.on_route``: exploring or following, and not pushed off its route."""
    return (not displaced[a]) and (mode[a] == EXPLORE or mode[a] == FOLLOW)


@kernel(cache=True)
def _meet_route(mx: int, my: int, route: I32, b: int, i0: int, t_end: int) -> tuple[int, int, int]:
    """``comm.meet`` on robot ``b``'s timetable from row ``i0`` (it stays at row ``t_end``):
    the earliest τ, and the future's cell at τ (its last cell when τ is past the end)."""
    last = t_end - i0
    d = 0
    for tau in range(last + 1):
        x = int(route[i0 + tau, b, 0])
        y = int(route[i0 + tau, b, 1])
        d = abs(x - mx) + abs(y - my) - 1
        if d <= tau:
            return tau, x, y
    return max(last, d), int(route[t_end, b, 0]), int(route[t_end, b, 1])


@kernel(cache=True)
def _meet_of(
    mx: int, my: int, b: int, t: int, omni: bool, pos: I64, mode: I64, displaced: Bools,
    delay: I64, route: I32, t_end: int,
) -> tuple[int, int, int]:  # fmt: skip
    """τ and cell of the meeting with ``b`` from (mx, my) at round ``t``: its future as the
    rule predicts it (seed: ``Mission.expected_future``; omniscient: ``Mission.future``, its
    cell once it has left its route)."""
    if omni and not _on_route(mode, displaced, b):
        qx, qy = int(pos[b, 0]), int(pos[b, 1])
        return max(abs(qx - mx) + abs(qy - my) - 1, 0), qx, qy  # a one-row future
    i0 = min(max(0, t - delay[b]), t_end)
    return _meet_route(mx, my, route, b, i0, t_end)


@kernel(cache=True)
def _best_order(
    a: int, t: int, targets: I64, ntarg: I64, omni: bool, pos: I64, mode: I64,
    displaced: Bools, delay: I64, route: I32, t_end: int,
) -> None:  # fmt: skip
    """``comm.best_order`` on robot ``a``'s list, in place: every order in
    ``itertools.permutations``' (lexicographic by position), the first with the earliest
    completion kept."""
    m = ntarg[a]
    if m < 2:
        return
    orig = targets[a, :m].copy()
    best = orig.copy()
    idx = np.arange(m)
    best_tc = -1
    while True:
        tc, px, py = t, pos[a, 0], pos[a, 1]
        for j in range(m):
            tau, px, py = _meet_of(
                px, py, orig[idx[j]], tc, omni, pos, mode, displaced, delay, route, t_end
            )
            tc += tau
        if best_tc < 0 or tc < best_tc:
            best_tc = tc
            for j in range(m):
                best[j] = orig[idx[j]]
        i = m - 2  # the next permutation of idx
        while i >= 0 and idx[i] >= idx[i + 1]:
            i -= 1
        if i < 0:
            break
        j = m - 1
        while idx[j] <= idx[i]:
            j -= 1
        idx[i], idx[j] = idx[j], idx[i]
        idx[i + 1 :] = idx[i + 1 :][::-1].copy()
    targets[a, :m] = best


@kernel(cache=True)
def _enter_transport(
    a: int, t: int, relay: bool, relay_food: bool, pos: I64, mode: I64, comm_done: I64,
    tmode: I64, pidx: I64, join_at: I64, path: I64,
) -> None:  # fmt: skip
    """``Mission.enter_transport`` (with ``try_join``)."""
    mode[a] = TRANSPORT
    comm_done[a] = t
    if not relay:
        tmode[a] = E2E
        return
    tmode[a] = JOIN
    j = path.shape[0] - 1 if relay_food else _entry_cell(path, pos[a, 0], pos[a, 1])
    join_at[a] = j
    if pos[a, 0] == path[j, 0] and pos[a, 1] == path[j, 1]:
        tmode[a] = RELAY
        pidx[a] = j


@kernel(cache=True)
def _inform(
    a: int, teller: int, t: int, flags: I64, relay: bool, nb_start: I64, nb_flat: I64,
    pos: I64, mode: I64, delay: I64, displaced: Bools, informed_at: I64, targets: I64,
    ntarg: I64, know: NDArray[np.uint64], hold_head: I64, hold_next: I64, hold_who: I64,
    hold_of: I64, state: I64, comm_done: I64, tmode: I64, pidx: I64, join_at: I64,
    path: I64, route: I32, t_end: int,
) -> None:  # fmt: skip
    """``Mission.inform``: robot ``a`` learns the food from ``teller`` (-1: it found it);
    its list (``comm.first_targets``), the word's record of it (``Word.learn``: the seed
    rule), then transport, keep to its route, or communicate."""
    omni = flags[F_OMNI] == 1
    informed_at[a] = t
    s, e = nb_start[a], nb_start[a + 1]
    k = 0
    if (not omni) and flags[F_ONE_WAY] == 1 and teller < 0 and e > s:
        targets[a, 0] = nb_flat[e - 1]
        k = 1
    else:
        for j in range(s, e):
            b = nb_flat[j]
            if b == teller or (omni and informed_at[b] >= 0):
                continue
            targets[a, k] = b
            k += 1
    ntarg[a] = k
    if not omni:
        if teller >= 0:
            for w in range(know.shape[1]):
                know[a, w] |= know[teller, w]
        know[a, a >> 6] |= np.uint64(1) << np.uint64(a & 63)
        if teller >= 0:
            know[teller, a >> 6] |= np.uint64(1) << np.uint64(a & 63)
        for j in range(k):  # a holds targets[a, j]: a linked list per listed robot
            h = state[C_HOLDS]
            b = targets[a, j]
            hold_who[h] = a
            hold_of[h] = b
            hold_next[h] = hold_head[b]
            hold_head[b] = h
            state[C_HOLDS] = h + 1
    if k == 0:
        _enter_transport(
            a, t, relay, flags[F_RELAY_FOOD] == 1, pos, mode, comm_done, tmode, pidx,
            join_at, path,
        )  # fmt: skip
        return
    exploring = t - delay[a] >= flags[F_T_SYNC]
    keeps = flags[F_KEEP_EXPLORING] == 1 if exploring else flags[F_KEEP_DEPLOYING] == 1
    if keeps and _on_route(mode, displaced, a):
        mode[a] = FOLLOW
    else:
        mode[a] = COMM  # Mission.start_comm
        _best_order(a, t, targets, ntarg, omni, pos, mode, displaced, delay, route, t_end)


@kernel(cache=True)
def _knows(know: NDArray[np.uint64], a: int, b: int) -> bool:
    """Whether robot ``a``'s bit set holds ``b`` (``Word.knows``)."""
    return ((know[a, b >> 6] >> np.uint64(b & 63)) & np.uint64(1)) == np.uint64(1)


@kernel(cache=True)
def _settled(
    a: int, b: int, know: NDArray[np.uint64], informed_at: I64, hold_head: I64,
    hold_next: I64, hold_who: I64,
) -> bool:  # fmt: skip
    """``Word.settled``: ``a`` knows ``b`` knows, or knows of a robot informed before it
    (earlier round, or the same round and a smaller id) that listed ``b``."""
    if _knows(know, a, b):
        return True
    h = hold_head[b]
    while h >= 0:
        x = hold_who[h]
        earlier = informed_at[x] < informed_at[a] or (informed_at[x] == informed_at[a] and x < a)
        if x != a and earlier and _knows(know, a, x):
            return True
        h = hold_next[h]
    return False


@kernel(cache=True)
def _exchange(
    pos: I64, informed_at: I64, know: NDArray[np.uint64], snap: NDArray[np.uint64],
    nest: I64, g: int, cells: I64,
) -> None:  # fmt: skip
    """``Word.exchange`` over ``comm.adjacent_pairs`` of the informed robots: each merges
    what the robots at distance ≤ 1 knew before this Look. The pairs' union is per cell
    (one robot a cell, but the nest, whose robots all pair with each other and with its four
    sides): ``snap`` holds the knowledge before, and the nest's robots' union is its last
    row. ``cells`` (g x g, all -1) is left so."""
    n, w = know.shape
    snap[:n] = know
    snap[n] = 0
    nest_any = False
    for b in range(n):
        if informed_at[b] < 0:
            continue
        if pos[b, 0] == nest[0] and pos[b, 1] == nest[1]:
            nest_any = True
            for j in range(w):
                snap[n, j] |= know[b, j]
        else:
            cells[pos[b, 0], pos[b, 1]] = b
    for a in range(n):
        if informed_at[a] < 0:
            continue
        x, y = pos[a, 0], pos[a, 1]
        if nest_any and x == nest[0] and y == nest[1]:
            for j in range(w):
                know[a, j] |= snap[n, j]
        for dx, dy in ((1, 0), (0, -1), (-1, 0), (0, 1)):
            nx, ny = x + dx, y + dy
            if not (0 <= nx < g and 0 <= ny < g):
                continue
            if nx == nest[0] and ny == nest[1]:
                if nest_any:
                    for j in range(w):
                        know[a, j] |= snap[n, j]
                continue
            b = cells[nx, ny]
            if b >= 0:
                for j in range(w):
                    know[a, j] |= snap[b, j]
    for b in range(n):
        if informed_at[b] >= 0:
            cells[pos[b, 0], pos[b, 1]] = -1


@kernel(cache=True)
def _cross_off(
    a: int, t: int, omni: bool, pos: I64, delay: I64, informed_at: I64, targets: I64,
    ntarg: I64, know: NDArray[np.uint64], hold_head: I64, hold_next: I64, hold_who: I64,
    route: I32, t_end: int,
) -> None:  # fmt: skip
    """``comm.cross_off`` for robot ``a`` (it is telling): the omniscient rule drops every
    neighbour that knows; the seed rule those ``Word.settled`` allows or that are
    ``comm.absent`` from where their pattern puts them (``Mission.expected``)."""
    k = 0
    mx, my = pos[a, 0], pos[a, 1]
    for j in range(ntarg[a]):
        b = targets[a, j]
        if omni:
            drop = informed_at[b] >= 0
        else:
            r = min(max(0, t - delay[b]), t_end)
            ex, ey = route[r, b, 0], route[r, b, 1]
            absent = (
                abs(mx - ex) + abs(my - ey) <= 1 and abs(pos[b, 0] - ex) + abs(pos[b, 1] - ey) > 1
            )
            drop = absent or _settled(a, b, know, informed_at, hold_head, hold_next, hold_who)
        if not drop:
            targets[a, k] = b
            k += 1
    ntarg[a] = k


@kernel(cache=True)
def _route_wish(
    a: int, t: int, x: int, y: int, g: int, delay: I64, route: I32, t_end: int, opts: I64,
) -> tuple[int, bool]:
    """``Mission.options`` of robot ``a`` on its route, at ``(x, y)`` with ``opts[a, 0]``
    already its cell: its timetable's next cell then a stay; a stay while the route pauses;
    a stay or a side step once the route has ended (then it no longer follows). The count
    of wishes and whether it follows its route."""
    i = t + 1 - delay[a]
    r = min(i, t_end)
    nx, ny = route[r, a, 0], route[r, a, 1]
    if nx != x or ny != y:
        opts[a, 0, 0] = nx
        opts[a, 0, 1] = ny
        opts[a, 1, 0] = x
        opts[a, 1, 1] = y
        return 2, True
    if i > t_end:
        return _sidesteps(opts[a], 1, x, y, g), False
    return 1, True


@kernel(cache=True)
def _route_moved(
    a: int, x: int, y: int, nx: int, ny: int, opts: I64, following: Bools, delay: I64,
    displaced: Bools,
) -> None:
    """``Mission._move`` for robot ``a`` on its route, from ``(x, y)`` to ``(nx, ny)``: made
    to wait when it wanted to move, its timetable is delayed a round; moving anywhere but
    its wish, or while not following its route, pushes it off the route for good."""
    wx, wy = opts[a, 0, 0], opts[a, 0, 1]
    moved = nx != x or ny != y
    if (nx != wx or ny != wy) and (wx != x or wy != y) and not moved:
        delay[a] += 1
    elif moved and ((not following[a]) or nx != wx or ny != wy):
        displaced[a] = True


@kernel(cache=True)
def _comm_options(
    a: int, t: int, omni: bool, g: int, pos: I64, mode: I64, delay: I64, displaced: Bools,
    targets: I64, ntarg: I64, route: I32, t_end: int, opts: I64,
) -> tuple[int, bool]:  # fmt: skip
    """``Mission.options`` of a robot not transporting: its wishes in ``opts[a]``, their
    count and whether it follows its route."""
    x, y = pos[a, 0], pos[a, 1]
    opts[a, 0, 0] = x
    opts[a, 0, 1] = y
    m = mode[a]
    if _on_route(mode, displaced, a):
        return _route_wish(a, t, x, y, g, delay, route, t_end, opts)
    if m == EXPLORE:  # pushed off its route after finishing it
        return _sidesteps(opts[a], 1, x, y, g), False
    if m != COMM or ntarg[a] == 0:  # pragma: no cover - a displaced FOLLOW robot
        raise RuntimeError("comm_rounds: a robot neither explores, follows nor tells")
    b = targets[a, 0]
    bx, by = pos[b, 0], pos[b, 1]
    if abs(x - bx) + abs(y - by) <= 1:  # they exchange in the next Look
        return 1, False
    tau, gx, gy = _meet_of(x, y, b, t, omni, pos, mode, displaced, delay, route, t_end)
    if (not omni) and tau == 0 and abs(bx - gx) + abs(by - gy) <= 1:  # comm.meet_goal
        gx, gy = bx, by
    if x == gx and y == gy:
        return 1, False
    k = _toward(opts[a], 0, x, y, gx, gy)
    opts[a, k, 0] = x
    opts[a, k, 1] = y
    return k + 1, False


@kernel(cache=True)
def _comm_look(
    pos: I64, mode: I64, delay: I64, displaced: Bools, informed_at: I64, targets: I64,
    ntarg: I64, know: NDArray[np.uint64], snap: NDArray[np.uint64], hold_head: I64,
    hold_next: I64, hold_who: I64, hold_of: I64, comm_done: I64, carrying: Bools,
    tmode: I64, pidx: I64, join_at: I64, handovers: I64, state: I64, flags: I64,
    relay: bool, nb_start: I64, nb_flat: I64, path: I64, route: I32, t_end: int,
    nest: I64, food: I64, jobs: I64, cells: I64,
) -> None:  # fmt: skip
    """``Mission.look``: finders learn, the lowest-id informed robot at distance ≤ 1 tells
    each uninformed one, the word is exchanged (seed rule), telling robots cross off and
    enter transport or leave their route, then the transport Look."""
    n = pos.shape[0]
    g = cells.shape[0]
    t = state[0]
    omni = flags[F_OMNI] == 1
    for a in range(n):
        if informed_at[a] < 0 and pos[a, 0] == food[0] and pos[a, 1] == food[1]:
            _inform(
                a, -1, t, flags, relay, nb_start, nb_flat, pos, mode, delay, displaced,
                informed_at, targets, ntarg, know, hold_head, hold_next, hold_who, hold_of,
                state, comm_done, tmode, pidx, join_at, path, route, t_end,
            )  # fmt: skip
    for b in range(n - 1, -1, -1):  # the lowest informed id per cell
        if informed_at[b] >= 0:
            cells[pos[b, 0], pos[b, 1]] = b
    new_a = np.empty(n, np.int64)
    new_b = np.empty(n, np.int64)
    m = 0
    for a in range(n):
        if informed_at[a] >= 0:
            continue
        x, y = pos[a, 0], pos[a, 1]
        best = -1
        for dx, dy in ((0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)):
            nx, ny = x + dx, y + dy
            if 0 <= nx < g and 0 <= ny < g:
                w = cells[nx, ny]
                if w >= 0 and (best < 0 or w < best):
                    best = w
        if best >= 0:
            new_a[m] = a
            new_b[m] = best
            m += 1
    for b in range(n):
        if informed_at[b] >= 0:
            cells[pos[b, 0], pos[b, 1]] = -1
    for j in range(m):
        _inform(
            new_a[j], new_b[j], t, flags, relay, nb_start, nb_flat, pos, mode, delay,
            displaced, informed_at, targets, ntarg, know, hold_head, hold_next, hold_who,
            hold_of, state, comm_done, tmode, pidx, join_at, path, route, t_end,
        )  # fmt: skip
    if not omni:
        _exchange(pos, informed_at, know, snap, nest, g, cells)
    for a in range(n):  # the telling robots (their modes change only in the next loop)
        if mode[a] == FOLLOW or mode[a] == COMM:
            _cross_off(
                a, t, omni, pos, delay, informed_at, targets, ntarg, know, hold_head,
                hold_next, hold_who, route, t_end,
            )  # fmt: skip
    for a in range(n):
        if mode[a] != FOLLOW and mode[a] != COMM:
            continue
        if ntarg[a] == 0:
            _enter_transport(
                a, t, relay, flags[F_RELAY_FOOD] == 1, pos, mode, comm_done, tmode, pidx,
                join_at, path,
            )  # fmt: skip
        elif mode[a] == FOLLOW and (displaced[a] or t - delay[a] >= t_end):
            mode[a] = COMM  # Mission.start_comm
            _best_order(a, t, targets, ntarg, omni, pos, mode, displaced, delay, route, t_end)
    _transport_look_once(
        pos, carrying, tmode, pidx, join_at, state, path, nest, food, relay, jobs, handovers,
        cells,
    )  # fmt: skip


@kernel(cache=True)
def _popcount(v: np.uint64) -> int:
    c = 0
    while v != np.uint64(0):
        v &= v - np.uint64(1)
        c += 1
    return c


MIXED_HEAD, MIXED_ROW = 4, 11  # a mixed key: [valid, units, delivered, known], 11 a robot


def mixed_memo(n: int) -> I64:
    """An empty memory for :func:`_same_as_mixed`: the keys of the last two rounds."""
    return np.full(1 + 2 * (MIXED_HEAD + MIXED_ROW * n), -1, dtype=np.int64)


@kernel(cache=True)
def _same_as_mixed(
    mixed: I64, pos: I64, carrying: Bools, mode: I64, tmode: I64, pidx: I64, join_at: I64,
    relay: bool, displaced: Bools, informed_at: I64, delay: I64, t: int, t_end: int,
    ntarg: I64, know: NDArray[np.uint64], units: int, delivered: int,
) -> bool:  # fmt: skip
    """Whether the mixed phase's state equals the one of the previous round or of the round
    before it, both stored in ``mixed`` (``Mission.mixed_key``: positions, loads, modes,
    transport modes, path indices, relay entry cells, displaced, informed, each robot's clock
    ``t - delay`` clamped to ``0 … t_end``, list lengths, the word's total count of known
    robots, units, delivered); stores the new one in place of the older. Layout: which slot
    holds the previous round's key (-1: neither, a fresh memory), then two slots, each
    MIXED_HEAD values, then MIXED_ROW per robot; a slot is valid when its first value is 1."""
    size = (mixed.shape[0] - 1) // 2
    prev = 1 if mixed[0] == 1 else 0
    p = 1 + prev * size  # the previous round's key
    o = 1 + (1 - prev) * size  # the one before it: overwritten with this round's
    known = 0
    for a in range(know.shape[0]):
        for j in range(know.shape[1]):
            known += _popcount(know[a, j])
    head = (1, units, delivered, known)
    same1 = True
    same2 = True
    for j in range(MIXED_HEAD):
        v = head[j]
        same1 = same1 and mixed[p + j] == v
        same2 = same2 and mixed[o + j] == v
        mixed[o + j] = v
    for a in range(pos.shape[0]):
        base = MIXED_HEAD + MIXED_ROW * a
        vals = (
            pos[a, 0], pos[a, 1], 1 if carrying[a] else 0, mode[a], tmode[a], pidx[a],
            join_at[a] if relay and mode[a] == TRANSPORT else -1, 1 if displaced[a] else 0,
            1 if informed_at[a] >= 0 else 0, min(max(0, t - delay[a]), t_end), ntarg[a],
        )  # fmt: skip
        for j in range(MIXED_ROW):
            v = vals[j]
            same1 = same1 and mixed[p + base + j] == v
            same2 = same2 and mixed[o + base + j] == v
            mixed[o + base + j] = v
    mixed[0] = 1 - prev
    return same1 or same2


@kernel(cache=True)
def _comm_step(
    pos: I64, mode: I64, delay: I64, displaced: Bools, targets: I64, ntarg: I64,
    carrying: Bools, tmode: I64, pidx: I64, join_at: I64, state: I64, flags: I64,
    path: I64, path_of: I64, route: I32, t_end: int, nest: I64, food: I64, memo: I64,
    cells: I64, informed_at: I64, know: NDArray[np.uint64], mixed: I64, relay: bool,
    everyone: bool,
) -> None:  # fmt: skip
    """``Mission.step`` (after the Look of round ``state[0]``): every robot's options
    (a frozen crowd is the transport ``memo``'s repeat when ``everyone`` transports, else the
    ``mixed`` memo's, ``Mission.mixed_key``), the priority order, resolution, and
    ``_move``'s rules (a route follower held back waits, one pushed off is displaced; a
    relay robot moved off the path goes idle)."""
    n = pos.shape[0]
    g = cells.shape[0]
    t = state[0]
    if everyone:
        frozen = _same_as_memo(memo, pos, carrying, tmode, pidx, state[1], state[2])
        mixed[:] = -1  # Mission.mixed_key is None: a fresh memory
    else:
        memo[0] = -1  # Mission.transport_key is None: the mixed key decides
        frozen = _same_as_mixed(
            mixed, pos, carrying, mode, tmode, pidx, join_at, relay, displaced, informed_at,
            delay, t, t_end, ntarg, know, state[1], state[2],
        )  # fmt: skip
    opts = np.empty((n, MAXOPT, 2), np.int64)
    nopt = np.zeros(n, np.int64)
    following = np.zeros(n, np.bool_)
    _transport_options(
        pos, carrying, tmode, pidx, join_at, state[1], path, nest, food, g, frozen, opts, nopt
    )  # fmt: skip
    for a in range(n):
        if mode[a] != TRANSPORT:
            nopt[a], following[a] = _comm_options(
                a, t, flags[F_OMNI] == 1, g, pos, mode, delay, displaced, targets, ntarg,
                route, t_end, opts,
            )  # fmt: skip
    choice = _resolved(pos, opts, nopt, following, nest, cells)
    for a in range(n):
        nx, ny = opts[a, choice[a], 0], opts[a, choice[a], 1]
        x, y = pos[a, 0], pos[a, 1]
        if _on_route(mode, displaced, a):
            _route_moved(a, x, y, nx, ny, opts, following, delay, displaced)
        elif mode[a] == TRANSPORT and tmode[a] == RELAY and (nx != x or ny != y):
            _relay_moved(a, nx, ny, path_of, pidx, tmode)
        pos[a, 0] = nx
        pos[a, 1] = ny
    state[0] = t + 1


@kernel(cache=True)
def comm_rounds(
    pos: I64, mode: I64, delay: I64, displaced: Bools, informed_at: I64, targets: I64,
    ntarg: I64, know: NDArray[np.uint64], hold_head: I64, hold_next: I64, hold_who: I64,
    hold_of: I64, comm_done: I64, carrying: Bools, tmode: I64, pidx: I64, join_at: I64,
    handovers: I64, state: I64, flags: I64, relay: bool, nb_start: I64, nb_flat: I64,
    path: I64, path_of: I64, route: I32, t_end: int, nest: I64, food: I64, jobs: I64,
    memo: I64, mixed: I64, history: I32, cells: I64,
) -> int:  # fmt: skip
    """Play a plain run's rounds from the discovery until every robot transports (the
    Python loop of ``Mission.rounds`` with ``Mission.look`` and ``step``), or the run ends,
    or ``history`` is full; a line-by-line port with the transport Look, options, priority
    and resolution shared with :func:`transport_tail`.

    ``state`` = [t, units, delivered, k, n_jobs, rows, status, limit, holds, pending]:
    positions after each Look go to ``history`` (rows: how many), jobs as in
    :func:`transport_tail`. Status GOING: ``history`` is full, the state is the one after
    the last Look and its Compute and Move are ``pending`` (the next call makes them first;
    with a one-row ``history``, a call per round, the caller sees every Look's state, as
    ``on_frame`` does); DONE: k units home; STALLED: round ``limit`` reached; HANDOFF: every
    robot transports, the tail's turn (``memo`` is its frozen-crowd memory; ``mixed`` the
    mixed phase's, :func:`mixed_memo`). A robot's list
    is ``targets[a, :ntarg[a]]``; ``informed_at`` is -1 until it learns, ``comm_done`` until
    it transports, and ``tmode`` NOT_YET. The seed rule's word: ``know`` (n x words bit
    sets) and, per listed robot b, the robots that listed it (``hold_head[b]``, then
    ``hold_next``; ``hold_who``/``hold_of`` in the order listed). ``flags``: see F_OMNI …;
    ``cells`` a g x g scratch grid of -1 (left so)."""
    n = pos.shape[0]
    snap = np.empty((n + 1, know.shape[1]), np.uint64)
    rows = 0
    while True:
        everyone = _everyone_transports(mode)  # a Compute and Move change no mode
        if state[C_PENDING]:
            _comm_step(
                pos, mode, delay, displaced, targets, ntarg, carrying, tmode, pidx, join_at,
                state, flags, path, path_of, route, t_end, nest, food, memo, cells,
                informed_at, know, mixed, relay, everyone,
            )  # fmt: skip
            state[C_PENDING] = 0
        if everyone:
            state[6] = HANDOFF
            break
        _comm_look(
            pos, mode, delay, displaced, informed_at, targets, ntarg, know, snap, hold_head,
            hold_next, hold_who, hold_of, comm_done, carrying, tmode, pidx, join_at,
            handovers, state, flags, relay, nb_start, nb_flat, path, route, t_end, nest, food,
            jobs, cells,
        )  # fmt: skip
        _write_row(history, rows, pos)
        rows += 1
        if state[2] >= state[3]:
            state[6] = DONE
            break
        if state[0] >= state[C_LIMIT]:
            state[6] = STALLED
            break
        state[C_PENDING] = 1
        if rows == history.shape[0]:
            state[6] = GOING
            break
    state[5] = rows
    return rows
