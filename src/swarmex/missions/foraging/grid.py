"""Grid conventions and path helpers shared by every foraging pattern.

Conventions (thesis ch. 3): cells are ``(x, y)`` with ``(0, 0)`` the top-left corner, so
*North* is ``y - 1``. The nest is the centre cell ``(g // 2, g // 2)``; for even ``g`` there
is no true centre and we use the released simulator's ``(g/2, g/2)``, which is why the West
and North borders are one step farther from the nest than the East and South ones.
Distances are Manhattan.

Routes are lists of cells in which consecutive cells are 4-neighbours. Patterns build their
exploration orders as lists of "cells to visit" and :func:`join` turns them into a walkable
route by inserting shortest L-shaped connections; that is how the thesis's "move between
non-contiguous in-range cells" and the spiral's "move along the boundary" are realised.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

Cell = tuple[int, int]

DIRS: dict[str, Cell] = {"N": (0, -1), "S": (0, 1), "E": (1, 0), "W": (-1, 0)}


def nest_of(g: int) -> Cell:
    return (g // 2, g // 2)


def manhattan(a: Cell, b: Cell) -> int:
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def inside(c: Cell, g: int) -> bool:
    return 0 <= c[0] < g and 0 <= c[1] < g


def walk(start: Cell, moves: Iterable[tuple[str, int]]) -> list[Cell]:
    """Cells visited by run-length moves such as ``[("N", 3), ("E", 1)]`` (start excluded)."""
    x, y = start
    out: list[Cell] = []
    for d, k in moves:
        dx, dy = DIRS[d]
        for _ in range(k):
            x += dx
            y += dy
            out.append((x, y))
    return out


def lpath(a: Cell, b: Cell, x_first: bool = True) -> list[Cell]:
    """A shortest path from ``a`` to ``b`` (``a`` excluded, ``b`` included), one axis first."""
    x, y = a
    out: list[Cell] = []
    sx = 1 if b[0] > x else -1
    sy = 1 if b[1] > y else -1

    def xs() -> None:
        nonlocal x
        while x != b[0]:
            x += sx
            out.append((x, y))

    def ys() -> None:
        nonlocal y
        while y != b[1]:
            y += sy
            out.append((x, y))

    if x_first:
        xs()
        ys()
    else:
        ys()
        xs()
    return out


def join(cells: Sequence[Cell], start: Cell | None = None) -> list[Cell]:
    """Concatenate cells into a walkable route, bridging gaps with shortest paths.

    The bridge goes first along the axis of the larger gap: in the patterns that gap is the
    "along the current level" direction, so the agent finishes its level before it steps
    to the next one, as Alg. 12 prescribes.
    """
    route: list[Cell] = [start] if start is not None else []
    for c in cells:
        if not route:
            route.append(c)
            continue
        last = route[-1]
        if c == last:
            continue
        if manhattan(last, c) == 1:
            route.append(c)
        else:
            x_first = abs(c[0] - last[0]) >= abs(c[1] - last[1])
            route.extend(lpath(last, c, x_first))
    return route


def is_walk(route: Sequence[Cell]) -> bool:
    return all(manhattan(a, b) == 1 for a, b in zip(route, route[1:], strict=False))


def smooth(cells: Sequence[Cell], window: int = 3) -> list[Cell]:
    """Locally reorder a visiting order so consecutive cells are adjacent where possible.

    Sort keys (angle, ring) leave ties and parity flips at quadrant boundaries; pulling an
    adjacent cell from the next ``window`` entries forward removes most of those detours
    without changing the overall sweep.
    """
    out = list(cells)
    for i in range(len(out) - 1):
        if manhattan(out[i], out[i + 1]) == 1:
            continue
        for j in range(i + 2, min(i + 1 + window, len(out))):
            if manhattan(out[i], out[j]) == 1:
                out.insert(i + 1, out.pop(j))
                break
    return out
