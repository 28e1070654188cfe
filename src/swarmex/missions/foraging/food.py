"""Where the food is: the thesis's bands and drawing a food cell (``--food-distance``).

``--food`` and ``--food-distance`` are parsed and checked by
:class:`~swarmex.missions.foraging.params.ForagingParams`; this module draws the cell.

Separation bands (ch. 6) are percentages of the Manhattan distance from the corner ``(0, 0)``
to the nest (``g`` for even ``g``; the released code's ``FoodLocations``): a cell qualifies when
``⌊lo·D/100⌋ ≤ d < ⌊hi·D/100⌋`` (the top band includes ``d = D``). For g = 128 that is
``[0, 25), [25, 51), [51, 76), [76, 102), [102, 128]``. "RANDOM" is any cell. The nest itself is
never a food cell (the food would already be home).
"""

from __future__ import annotations

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.foraging.grid import Cell, nest_of

BANDS = ("0-20", "20-40", "40-60", "60-80", "80-100", "random")


def parse_band(text: str) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in text.replace("%", "").split("-"))
    except ValueError:
        raise InputError(f"--food-distance must be LO-HI in percent, got {text!r}") from None
    if not 0 <= lo < hi <= 100:
        raise InputError(f"--food-distance needs 0 ≤ LO < HI ≤ 100, got {text!r}")
    return lo, hi


def nest_distances(g: int) -> np.ndarray:
    """Every cell's Manhattan distance from the nest, as a ``(g, g)`` array indexed ``[y, x]``."""
    nest = nest_of(g)
    ys, xs = np.mgrid[0:g, 0:g]
    return np.abs(xs - nest[0]) + np.abs(ys - nest[1])


def band_cells(g: int, band: str) -> np.ndarray:
    """All cells ``(x, y)`` of a band (``"random"`` or ``"LO-HI"``), nest excluded."""
    nest = nest_of(g)
    ys, xs = np.mgrid[0:g, 0:g]
    d = nest_distances(g)
    ok = d > 0
    if band != "random":
        lo, hi = parse_band(band)
        D = nest[0] + nest[1]
        ok &= d >= int(lo * D / 100)
        ok &= (d < int(hi * D / 100)) if hi < 100 else (d <= D)
    cells = np.stack([xs[ok], ys[ok]], axis=1)
    if not len(cells):
        raise InputError(f"no cell of the {g}×{g} grid lies in --food-distance {band}")
    return cells


def sample_food(g: int, band: str, rng: np.random.Generator, count: int = 1) -> list[Cell]:
    cells = band_cells(g, band)
    idx = rng.choice(len(cells), size=count, replace=count > len(cells))
    return [(int(cells[i][0]), int(cells[i][1])) for i in idx]


def check_food(food: Cell, g: int, flag: str = "--food") -> Cell:
    """``food`` must be a cell of the g×g grid other than the nest (``flag`` names the option
    in the message: ``--food``, or recall's ``--found``)."""
    x, y = food
    if not (0 <= x < g and 0 <= y < g):
        raise InputError(f"{flag} {x},{y} is outside the {g}×{g} grid")
    if (x, y) == nest_of(g):
        raise InputError(f"{flag} {x},{y} is the nest; the food must be elsewhere")
    return (x, y)
