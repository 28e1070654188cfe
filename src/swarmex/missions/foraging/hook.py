"""The Compute hook of a foraging run: the seed's moves out, the caller's moves in.

Why: a learned policy (the PettingZoo environment) chooses each robot's move every round, while
everything else stays the mission's own rules. A hooked run (:class:`~.sim.Mission` with
``hooked=True``) is a generator: at each round's Compute it yields the seed's move of every
robot (:func:`seed_moves`, the direction of the first of its ordered wishes) and takes every
robot's move back (``generator.send``). The caller drives the run itself, one round per call,
in its own thread: no worker thread and no hand-over (:func:`drive` does it for a callable).

How a move becomes the robot's wishes for the collision resolution (:func:`hooked_options`):
a robot whose move is the seed's keeps the seed's whole decision (its fallbacks and its rank as
a route follower); a robot that yields its cell (an idle one: stay, else a side cell) keeps its
own cell as the last resort, which the resolution reaches only where it would otherwise run out
of options; any other move becomes the wish "that cell, else stay", without a route follower's
rank.

Move codes (the environment's actions): 0 stay, 1 North (y − 1), 2 East (x + 1), 3 South
(y + 1), 4 West (x − 1).
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import Any, TypeVar

import numpy as np

from swarmex.missions.foraging.grid import Cell

STAY = 0
STEPS: tuple[Cell, ...] = ((0, 0), (0, -1), (1, 0), (0, 1), (-1, 0))  # (dx, dy) of each move
_CODE: dict[Cell, int] = {d: k for k, d in enumerate(STEPS)}

T = TypeVar("T")
Request = TypeVar("Request")


def seed_moves(pos: list[Cell], opts: list[list[Cell]]) -> np.ndarray:
    """(n,) int64: the move code that takes each robot to its first wish."""
    code = _CODE
    return np.array(
        [code[(o[0][0] - p[0], o[0][1] - p[1])] for o, p in zip(opts, pos, strict=True)],
        dtype=np.int64,
    )


def hooked_options(
    pos: list[Cell],
    opts: list[list[Cell]],
    following: list[bool],
    builtin: np.ndarray,
    moves: np.ndarray,
    g: int,
) -> tuple[list[list[Cell]], list[bool]]:
    """The wishes and route-follower ranks of the robots given their ``moves`` (module
    docstring); ``builtin`` is :func:`seed_moves` of ``opts``. New lists: the inputs stay the
    seed's. Raises ValueError for a move that is not a code or leaves the g×g grid."""
    chosen = [o if o[-1] == p else [*o, p] for o, p in zip(opts, pos, strict=True)]
    differ = np.flatnonzero(moves != builtin).tolist()
    if not differ:
        return chosen, following
    ranked = list(following)
    for a in differ:
        x, y = p = pos[a]
        m = int(moves[a])
        if not 0 <= m < len(STEPS):
            raise ValueError(f"robot {a}: move {m} is not a move code (0..4)")
        if m == STAY:
            chosen[a] = [p]
        else:
            dx, dy = STEPS[m]
            if not (0 <= x + dx < g and 0 <= y + dy < g):
                raise ValueError(f"robot {a}: move {m} from {p} leaves the {g}×{g} grid")
            chosen[a] = [(x + dx, y + dy), p]
        ranked[a] = False
    return chosen, ranked


def drive(
    rounds: Generator[Request, np.ndarray, T], decide: Callable[[Request], Any] | None
) -> T:
    """Play a run generator to its end, answering each request with ``decide(request)``;
    returns the generator's value. Without ``decide`` the run must not ask."""
    try:
        request = next(rounds)
        while True:
            if decide is None:
                rounds.close()
                raise RuntimeError("a hooked run needs a decide callable")
            request = rounds.send(decide(request))
    except StopIteration as stop:
        return stop.value
