"""The thesis's closed forms and the exact settings they are proved for.

* Theorem 5.3.1 (End-to-End): n robots spaced ``x`` apart on a bent nest–food path of length
  ``(n+1)x``, n units: ``x(2n+1)`` rounds.
* Theorem 5.3.7 (Relay): n robots spaced ``2i+1`` apart on a straight path of length
  ``(n+1)(2i+1)``, n units: ``i(4n+2)+3`` rounds.
* Worst-case exploration times behind the competitive ratios (Thm. 3.1.1, 3.3.1, 3.4.1),
  as functions of ``g`` and ``n``. The thesis counts the deployment as ``T_dep``; our robots
  start from the single nest cell ``(g/2, g/2)``, which is one step farther from the West and
  North borders than the thesis's formulas assume, so our ``T_dep`` can exceed the formula by
  one or two rounds. :func:`deployment_offset` measures that difference, and the property
  tests check ``exploration ≤ bound + offset`` with the offset itself pinned to ≤ 2.
"""

from __future__ import annotations

import math

from swarmex.missions.foraging.grid import Cell
from swarmex.missions.foraging.sim import E2E, RELAY, TRANSPORT, Mission
from swarmex.missions.foraging.timed import timed_plan
from swarmex.missions.foraging.transport import END_TO_END, RELAY_FOOD, relay_path


def _transport_only(
    g: int, nest: Cell, food: Cell, starts: list[Cell], units: int, kind: str
) -> Mission:
    m = Mission(g, nest, food, units, kind, starts, t=0, timed=None)
    for a in range(len(starts)):
        m.mode[a] = TRANSPORT
        m.informed[a] = True
        m.informed_at[a] = 0
        m.comm_done[a] = 0
        if kind == END_TO_END:
            m.tmode[a] = E2E
        else:
            m.tmode[a] = RELAY
            m.pidx[a] = m.path_index[starts[a]]
    return m


def relay_setting(n: int, i: int) -> Mission:
    """Fig. 54: nest at L_0, food at L_{(n+1)(2i+1)}, Agent_k at L_{k(2i+1)}, straight path."""
    length = (n + 1) * (2 * i + 1)
    g = 2 * (length + 4)
    nest = (g // 2, g // 2)
    food = (nest[0] + length, nest[1])
    path = relay_path(nest, food)
    starts = [path[k * (2 * i + 1)] for k in range(1, n + 1)]
    return _transport_only(g, nest, food, starts, n, RELAY_FOOD)


def end_to_end_setting(n: int, x: int) -> Mission:
    """Fig. 51: robots ``x`` apart on the bent x-then-y nest–food path, nest and food not
    collinear."""
    length = (n + 1) * x
    a = max(1, length // 2)
    b = length - a
    if b < 1:
        raise ValueError("the path needs a bend: (n+1)·x ≥ 2")
    g = 2 * (length + 4)
    nest = (g // 2, g // 2)
    food = (nest[0] + a, nest[1] + b)
    path = relay_path(nest, food)
    starts = [path[k * x] for k in range(1, n + 1)]
    return _transport_only(g, nest, food, starts, n, END_TO_END)


def theorem_5_3_1(n: int, x: int) -> int:
    return x * (2 * n + 1)


def theorem_5_3_7(n: int, i: int) -> int:
    return i * (4 * n + 2) + 3


def thesis_t_dep(algorithm: str, g: int, n: int) -> int:
    """The thesis's deployment time (the round all robots start exploring together)."""
    if algorithm == "strips":
        return g - 1 if n % 2 else g - g // n
    if algorithm in ("zigzag", "hilbert") and n > 4:
        return 3 * g // 2 - 2 * g // math.isqrt(n)
    return 0


def worst_case_exploration(algorithm: str, g: int, n: int) -> float:
    """Thm. 3.1.1 / 3.3.1 / 3.4.1: exploration time at the pattern's worst food cell."""
    if algorithm == "strips":
        return thesis_t_dep(algorithm, g, n) + g * g / n
    if algorithm in ("zigzag", "hilbert"):
        if n == 4:
            return g * g / 4
        return thesis_t_dep(algorithm, g, n) + g * g / n
    if algorithm == "sectors":
        if n == 4:
            return g * g / 4
        return g * g / n + 2 * g  # "approximately g²/n": we allow an O(g) term of 2g
    raise ValueError(f"the thesis gives no worst case for {algorithm}")


def deployment_offset(algorithm: str, g: int, n: int) -> int:
    """Our synchronised start minus the thesis's T_dep (see the module docstring)."""
    if algorithm == "sectors" and n != 4:
        return 0
    return timed_plan(algorithm, g, n).t_sync - thesis_t_dep(algorithm, g, n)
