"""Hilbert (thesis §3.3, Algorithms 7–10, Table 2).

Same division, Start-Cells, deployment and codes as ZigZag (:mod:`.zigzag`); the square is
covered by the Hilbert curve the thesis builds recursively: ``route = [START]``, and
``order = log2(size)`` times ``route ← GetRoute(codes, route)`` (each entry ``X`` with code ``c``
becomes ``X`` followed by Table 2's three moves for ``c``) and ``codes ← GetSubCodes(codes)``
(``c ≤ 4 → [c+4, c, c, 9-(c+4)]``, else ``[c-4, c, c, 9-(c-4)]``; Alg. 10's loop bound is read
as ``0 … size-1``). With y pointing down this yields a Hamiltonian path of the square for all
eight codes (checked in the tests).

Supported: ``n`` a power of 4 and ``g/√n`` a power of 2.
"""

from __future__ import annotations

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import DIRS, Cell
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.zigzag import hierarchical_plan, is_power_of_4

TABLE2: dict[int, tuple[str, str, str]] = {
    1: ("E", "N", "W"),
    2: ("W", "N", "E"),
    3: ("S", "E", "N"),
    4: ("S", "W", "N"),
    5: ("N", "E", "S"),
    6: ("N", "W", "S"),
    7: ("E", "S", "W"),
    8: ("W", "S", "E"),
}


def sub_codes(codes: list[int]) -> list[int]:
    out: list[int] = []
    for c in codes:
        b = c + 4 if c <= 4 else c - 4
        out += [b, c, c, 9 - b]
    return out


def hilbert_moves(code: int, order: int) -> list[str]:
    """Alg. 8: the move list (``"St"`` first) of an order-``order`` curve for ``code``."""
    codes = [code]
    route = ["St"]
    for _ in range(order):
        new: list[str] = []
        for x, c in zip(route, codes, strict=True):
            new += [x, *TABLE2[c]]
        route = new
        codes = sub_codes(codes)
    return route


def hilbert_route(start: Cell, code: int, size: int) -> list[Cell]:
    order = size.bit_length() - 1
    x, y = start
    out = [start]
    for m in hilbert_moves(code, order)[1:]:
        dx, dy = DIRS[m]
        x, y = x + dx, y + dy
        out.append((x, y))
    return out


def plan(g: int, n: int) -> Plan:
    if n == 1 or not is_power_of_4(n):
        raise InputError(f"hilbert supports --agents a power of 4 (4, 16, 64, …), not {n}")
    size_ok = g % 2 == 0 and n > 0
    if size_ok:
        k = int(round(n**0.5))
        size = g // k if k and g % k == 0 else 0
        size_ok = size >= 2 and size & (size - 1) == 0
    if not size_ok:
        raise InputError(f"hilbert needs g/√n to be a power of 2 (got g={g}, n={n})")
    return hierarchical_plan("hilbert", g, n, hilbert_route)
