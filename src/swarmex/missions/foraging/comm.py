"""Communication phase (thesis ch. 4): whom to tell, in which order, and where to meet.

* A robot that learns the food location — by standing on it or from a robot at distance 1 —
  must tell its pattern neighbours (``Plan.neighbours``): all of them if it found the food,
  all but the one that told it otherwise (§4.2, §4.4; Strips' "the other neighbour" is the same
  rule). Any two robots at distance ≤ 1 exchange the location whenever one knows it (the
  released simulator does this every tick); communication is the only thing that needs
  adjacency.
* The message carries the food cell and the round it was found. Everything is deterministic
  from there, so an informed robot can compute where any robot is and whether it already
  knows (the thesis's Computational Module); it drops a neighbour from its list as soon as that
  neighbour is informed by anyone.
* Strips and ZigZag with 4 robots need no detour (§4.1, §4.2): the robot keeps following its
  route, which meets both neighbours regularly. If its route ends first it falls back to
  walking to them.
* Otherwise (§4.2) the robot tries every order of its remaining neighbours (at most 4! = 24)
  and keeps the one with the earliest completion; for each it computes the earliest round at
  which it can stand next to the neighbour's predicted position, walks there by Alg. 1, and
  re-plans every round.
* When the list is empty the robot enters Transportation.
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import permutations

import numpy as np

from swarmex.missions.foraging.grid import Cell


def meet(me: Cell, future: np.ndarray) -> int:
    """Earliest τ ≥ 0 at which a robot now at ``me`` can be next to ``future[τ]``.

    ``future`` is the neighbour's predicted position for τ = 0, 1, …; it stays at the last
    entry afterwards.
    """
    d = np.abs(future[:, 0] - me[0]) + np.abs(future[:, 1] - me[1]) - 1
    ok = d <= np.arange(len(future))
    if ok.any():
        return int(np.argmax(ok))
    return int(max(len(future) - 1, d[-1]))


def best_order(
    me: Cell, t: int, targets: list[int], future_of: Callable[[int, int], np.ndarray]
) -> tuple[list[int], int]:
    """Order of ``targets`` with the earliest completion; ``future_of(b, t)`` predicts ``b``."""
    best: tuple[int, list[int]] | None = None
    for perm in permutations(targets):
        tc, p = t, me
        for b in perm:
            fut = future_of(b, tc)
            tau = meet(p, fut)
            tc += tau
            last = fut[min(tau, len(fut) - 1)]
            p = (int(last[0]), int(last[1]))
        if best is None or tc < best[0]:
            best = (tc, list(perm))
    assert best is not None
    return best[1], best[0]
