"""The compiled round's priority and collision resolution (fastloop: a cell index, resume
after a bump) give exactly the pure-Python rule's answer (resolve.priority/resolve), checked
on random crowded rounds: robots packed on a small grid, each wishing for a few neighbour
cells and then staying, some of them route followers, several standing in the nest."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.foraging import fastloop
from swarmex.missions.foraging.resolve import priority, resolve, sidesteps


def _crowd(rng: np.random.Generator, g: int, n: int):
    nest = (g // 2, g // 2)
    cells = rng.choice(g * g, size=n, replace=False)
    cur = [(int(c) // g, int(c) % g) for c in cells]
    for a in rng.choice(n, size=min(3, n), replace=False):  # a few robots share the nest
        cur[a] = nest
    opts = []
    for p in cur:
        side = sidesteps(p, g)
        wish = [side[i] for i in rng.permutation(len(side))[: rng.integers(0, 3)]]
        if rng.random() < 0.2:  # an idle robot: stay first, then step aside
            opts.append([p, *side])
        else:
            opts.append([*wish, p])
    following = [bool(rng.random() < 0.3) for _ in range(n)]
    return nest, cur, opts, following


@pytest.mark.parametrize("seed", range(60))
def test_compiled_round_equals_the_python_rule(seed):
    rng = np.random.default_rng(seed)
    g = int(rng.integers(4, 9))
    n = int(rng.integers(2, g * g // 2))
    nest, cur, opts, following = _crowd(rng, g, n)
    order = priority(cur, following, opts)
    expected = resolve(cur, opts, order, nest)  # always an answer: own cell as last resort
    pos = np.asarray(cur, dtype=np.int64)
    wishes = np.zeros((n, fastloop.MAXOPT, 2), dtype=np.int64)
    nopt = np.asarray([len(o) for o in opts], dtype=np.int64)  # may grow by the last resort
    for a, o in enumerate(opts):
        wishes[a, : len(o)] = o
    cells = np.full((g, g), -1, dtype=np.int64)
    got_order = np.empty(n, dtype=np.int64)
    fastloop._order(pos, wishes, got_order, np.asarray(following), cells)
    assert got_order.tolist() == order
    choice = np.zeros(n, dtype=np.int64)
    fastloop._resolve(pos, wishes, nopt, got_order, nest[0], nest[1], choice, cells)
    got = [tuple(int(v) for v in wishes[a, choice[a]]) for a in range(n)]
    assert got == expected
    assert (cells == -1).all()  # the index is left clean for the next round
