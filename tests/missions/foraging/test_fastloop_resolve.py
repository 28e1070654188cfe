"""The compiled priority order and collision resolution (fastloop._order, fastloop._resolve)
against the Python rules they port (resolve.priority, resolve.resolve), on random crowds.

The compiled versions find cells through a grid and roll the pass back to the bumped robot;
the Python ones use dicts. Dense random crowds on a small grid make many swaps and bumps, so
a wrong lookup or rollback shows as a different order or choice. The scratch grid must come
back all -1 (the next round reuses it).
"""

from __future__ import annotations

import numpy as np

from swarmex.missions.foraging.fastloop import MAXOPT, _order, _resolve
from swarmex.missions.foraging.resolve import NEIGH, priority, resolve


def _crowd(rng: np.random.Generator, g: int, n: int):
    cells = rng.choice(g * g, size=n, replace=False)
    cur = [(int(c) // g, int(c) % g) for c in cells]
    opts = []
    for x, y in cur:
        sides = [(x + dx, y + dy) for dx, dy in NEIGH if 0 <= x + dx < g and 0 <= y + dy < g]
        rng.shuffle(sides)
        k = int(rng.integers(1, len(sides) + 1))
        opts.append([*sides[:k], (x, y)])  # staying put is always the last option
    return cur, opts


def test_compiled_order_and_resolution_match_the_python_rules():
    rng = np.random.default_rng(7)
    g = 7
    checked = 0
    for _ in range(300):
        n = int(rng.integers(2, 30))
        cur, opts = _crowd(rng, g, n)
        nest = cur[int(rng.integers(n))]
        order = priority(cur, [False] * n, opts)
        try:
            want = resolve(cur, opts, order, nest)
        except RuntimeError:  # pragma: no cover - a crowd with no way out: not a case
            continue
        cur_a = np.asarray(cur, dtype=np.int64)
        opts_a = np.zeros((n, MAXOPT, 2), dtype=np.int64)
        nopt = np.zeros(n, dtype=np.int64)
        for a, o in enumerate(opts):
            opts_a[a, : len(o)] = o
            nopt[a] = len(o)
        grid = np.full((g, g), -1, dtype=np.int64)
        got_order = np.empty(n, dtype=np.int64)
        _order(cur_a, opts_a, got_order, grid)
        assert got_order.tolist() == order
        choice = np.empty(n, dtype=np.int64)
        _resolve(cur_a, opts_a, nopt, got_order, nest[0], nest[1], choice, grid)
        assert [tuple(opts_a[a, choice[a]]) for a in range(n)] == want
        assert (grid == -1).all()
        checked += 1
    assert checked > 250
