"""Execute a :class:`Plan` with no food: every robot's position at every round.

Until the food is found nothing a robot does depends on the food, so this timetable is the
exact prefix of every run of the pattern, whatever the food location; it is computed once per
``(algorithm, g, n)`` and shared by all runs (that is what makes a 128×128 sweep cheap: the
exploration phase is a table look-up). It is also what an informed robot "computes" when it
plans to meet a neighbour (ch. 4: agents can determine where any other agent is).

The same collision rule as the rest of the mission (:mod:`.resolve`) applies, so patterns whose
joins can cross (Spiral near the nest, Sectors' bridges) stagger robots instead of colliding.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from swarmex.missions.foraging.grid import Cell
from swarmex.missions.foraging.patterns import build_plan
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.resolve import priority, resolve, sidesteps


@dataclass(frozen=True)
class Timed:
    plan: Plan
    pos: np.ndarray  # (t_end + 1, n, 2) int32; robots stay put after t_end
    t_end: int
    t_sync: int  # round at which synchronised patterns start exploring (0 if not synced)
    explore_start: np.ndarray  # (n,) time each robot stands on its Start-Cell, ready

    def at(self, t: int) -> np.ndarray:
        return self.pos[min(t, self.t_end)]

    def first_visits(self) -> np.ndarray:
        """Every cell's discovery round, ``[x, y]``: the first round a robot stands on it,
        which is the exploration time of a food placed there (-1 for the nest, where every
        robot starts, and for cells never visited). Its mean over the cells is the exact
        mean exploration time for uniform food, without a sample's error."""
        g, n = self.plan.g, self.plan.n
        codes = (self.pos[:, :, 0].astype(np.int64) * g + self.pos[:, :, 1]).ravel()
        cells, first = np.unique(codes, return_index=True)  # first index: time-major order
        flat = np.full(g * g, -1, dtype=np.int64)
        flat[cells] = first // n
        out = flat.reshape(g, g)
        out[self.plan.nest] = -1
        return out


def execute(plan: Plan, max_rounds: int | None = None, *, compiled: bool = True) -> Timed:
    """The timetable of ``plan``: compiled (:func:`.fastloop.timetable_rounds`, the default)
    or this module's Python loop, which is the rule as written and the tests' reference
    (the two give the same table)."""
    if compiled:
        return _execute_compiled(plan, max_rounds)
    n, g, nest = plan.n, plan.g, plan.nest
    routes = plan.routes
    idx = [0] * n
    cur: list[Cell] = [nest] * n
    history = [list(cur)]
    arrived = [-1] * n
    t_sync = 0 if not plan.sync else -1
    t = 0
    limit = max_rounds or 20 * g * g + 1000
    while any(idx[a] < len(routes[a]) - 1 for a in range(n)):
        for a in range(n):
            if arrived[a] < 0 and idx[a] >= plan.explore_from[a]:
                arrived[a] = t
        if t_sync < 0 and min(arrived) >= 0:
            t_sync = t
        opts: list[list[Cell]] = []
        following = []
        for a in range(n):
            r = routes[a]
            done = idx[a] >= len(r) - 1
            held = t + 1 < plan.depart[a] or (
                plan.sync and idx[a] == plan.explore_from[a] and t_sync < 0
            )
            if done:
                opts.append([cur[a], *sidesteps(cur[a], g)])
                following.append(False)
            elif held:
                opts.append([cur[a]])
                following.append(True)
            else:
                opts.append([r[idx[a] + 1], cur[a]])
                following.append(True)
        new = resolve(cur, opts, priority(cur, following, opts), nest)
        for a in range(n):
            if idx[a] < len(routes[a]) - 1 and new[a] == routes[a][idx[a] + 1]:
                idx[a] += 1
        cur = new
        t += 1
        history.append(list(cur))
        if t > limit:  # pragma: no cover - a pattern bug, not user input
            raise RuntimeError(f"{plan.algorithm}: exploration did not finish in {limit} rounds")
    for a in range(n):
        if arrived[a] < 0:
            arrived[a] = t
    if t_sync < 0:
        t_sync = max(arrived)
    pos = np.asarray(history, dtype=np.int32)
    return Timed(plan, pos, t, t_sync, np.asarray(arrived, dtype=np.int64))


def _execute_compiled(plan: Plan, max_rounds: int | None) -> Timed:
    from swarmex.missions.foraging.fastloop import timetable_rounds

    n, g = plan.n, plan.g
    lengths = np.asarray([len(r) for r in plan.routes], dtype=np.int64)
    start = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(lengths, out=start[1:])
    flat = np.concatenate([np.asarray(r, dtype=np.int64).reshape(-1, 2) for r in plan.routes])
    depart = np.asarray(plan.depart, dtype=np.int64)
    explore_from = np.asarray(plan.explore_from, dtype=np.int64)
    nest = np.asarray(plan.nest, dtype=np.int64)
    cur = np.tile(nest, (n, 1))
    idx = np.zeros(n, dtype=np.int64)
    arrived = np.full(n, -1, dtype=np.int64)
    state = np.asarray([0, 0 if not plan.sync else -1, 0], dtype=np.int64)
    cells = np.full((g, g), -1, dtype=np.int64)
    limit = max_rounds or 20 * g * g + 1000
    chunks = [cur[None].astype(np.int32)]
    rows = max(64, int(lengths.max()) + 1)  # most patterns end within their longest route
    while not state[2]:
        history = np.empty((rows, n, 2), dtype=np.int32)
        done = timetable_rounds(
            flat, start, depart, explore_from, plan.sync, nest, g, idx, cur, arrived, state,
            history, cells,
        )  # fmt: skip
        chunks.append(history[:done])
        if state[0] > limit:  # pragma: no cover - a pattern bug, not user input
            raise RuntimeError(f"{plan.algorithm}: exploration did not finish in {limit} rounds")
    t = int(state[0])
    arrived[arrived < 0] = t
    t_sync = int(state[1]) if state[1] >= 0 else int(arrived.max())
    pos = np.concatenate(chunks)
    return Timed(plan, pos, t, t_sync, arrived)


@lru_cache(maxsize=32)
def timed_plan(algorithm: str, g: int, n: int) -> Timed:
    return execute(build_plan(algorithm, g, n))
