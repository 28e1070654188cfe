"""comm.adjacent_pairs, written for speed, gives the pairs (in the same order) of the plain
rule it replaced."""

import numpy as np

from swarmex.missions.foraging.comm import adjacent_pairs


def reference(pos, who):
    at = {}
    for a in who:
        at.setdefault(pos[a], []).append(a)
    out = []
    for c, here in at.items():
        out.extend((a, b) for i, a in enumerate(here) for b in here[i + 1 :])
        for dx, dy in ((1, 0), (0, 1)):
            for b in at.get((c[0] + dx, c[1] + dy), ()):
                out.extend((a, b) for a in here)
    return out


def test_adjacent_pairs_are_the_plain_rules():
    rng = np.random.default_rng(5)
    for n, g in [(2, 2), (6, 3), (16, 5), (16, 32), (40, 6)]:
        for _ in range(200):
            pos = [tuple(int(v) for v in c) for c in rng.integers(0, g, size=(n, 2))]
            who = sorted(rng.choice(n, size=rng.integers(0, n + 1), replace=False).tolist())
            assert adjacent_pairs(pos, who) == reference(pos, who)
