"""Bit-exact fingerprints of the traversal runs the scale work (issue 14, item 1) speeds up.

Recorded with the code *before* that work (main at f0cdbff), like
``test_regression_fingerprint.py``: empty grids (where the distances are lattice distances
until a wall is found, which the scale work exploits), heterogeneous teams on them, the
``nearest`` baseline, and den520d.map (walls found cell by cell: repaired fields). The full
16-agent den520d run of ``bench/bench_traversal_den520d.py`` is pinned too; it takes a few
seconds, so it runs only when ``SWARMEX_SLOW_TESTS=1`` (its first 40,000 events always run).

The den520d values were re-taken on 25 Nov 2026 when the fingerprint stopped hashing the map
file's folder (the record's ``world.source`` is reduced to the file name): the old values
matched the current code with the map in /work/shared/maps, and a clone elsewhere failed.

Regenerate (only for a deliberate change of behaviour, said so in the commit) with
``PYTHONPATH=src python tests/missions/traversal/test_scale_fingerprint.py``.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from swarmex.missions.traversal import AgentSpec, run_traversal, uniform_agents
from swarmex.missions.traversal.metrics import run_fingerprint as fingerprint
from swarmex.missions.traversal.sim import TraversalRun
from swarmex.worlds import GridWorld, empty_grid, load_movingai

MAPS = Path(os.environ.get("SWARMEX_MAPS", Path(__file__).resolve().parents[3].parent
                           / "shared" / "maps"))
SLOW = os.environ.get("SWARMEX_SLOW_TESTS") == "1"


def _empty(w: int, h: int, agents: int, seed: int = 0, nests: int = 1,
           max_events: int | None = None, **kw) -> TraversalRun:
    """The CLI's defaults (2.22 s per edge, 10 s per job); ``nests`` spread over the grid."""
    world = empty_grid(w, h)
    rng = np.random.default_rng(seed)
    where = [0] if nests == 1 else [int(v) for v in rng.choice(w * h, nests, replace=False)]
    specs = uniform_agents([where[i % len(where)] for i in range(agents)], 2.22, 10.0)
    return run_traversal(world, specs, seed=seed, max_events=max_events, **kw)


def _hetero(size: int, seed: int) -> TraversalRun:
    """Three speed / job-time classes, two nests: the per-class paths of the policy."""
    world = empty_grid(size, size)
    specs = [
        AgentSpec(0, 1.0, 1.0), AgentSpec(0, 1.0, 1.0), AgentSpec(size * size - 1, 1.7, 0.5),
        AgentSpec(size * size - 1, 1.7, 0.5), AgentSpec(0, 0.6, 2.5), AgentSpec(size - 1, 1.3),
    ]
    return run_traversal(world, specs, seed=seed, start_interval=0.3)


def _mostly_empty(seed: int) -> TraversalRun:
    """An open grid with a few walls that are found late (the switch from lattice
    distances to the field cache mid-run)."""
    free = np.ones((40, 40), dtype=bool)
    free[20, 5:35] = False
    free[5:15, 30] = False
    world = GridWorld(free, source="open 40x40 with two walls")
    specs = uniform_agents([0, 0, 0, 1599, 1599], 1.0, 1.0)
    return run_traversal(world, specs, seed=seed)


def _den520d(agents: int, max_events: int | None = None) -> TraversalRun:
    path = MAPS / "den520d.map"
    if not path.exists():
        pytest.skip(f"den520d.map not found in {MAPS} (set SWARMEX_MAPS)")
    world = load_movingai(path)
    free = np.flatnonzero(~world.blocked)
    specs = uniform_agents([int(free[free.size // 2])] * agents, 1.0, 1.0)
    return run_traversal(world, specs, seed=0, max_events=max_events)


CASES: dict[str, Callable[[], TraversalRun]] = {
    "empty64-8a": lambda: _empty(64, 64, 8),
    "empty80x30-12a-3nests-sync": lambda: _empty(80, 30, 12, seed=2, nests=3,
                                                 start_interval=0.0),
    "empty48-hetero": lambda: _hetero(48, 1),
    "empty40-nearest": lambda: _empty(40, 40, 5, seed=3, algorithm="nearest"),
    "empty256-64a-20k-events": lambda: _empty(256, 256, 64, seed=4, max_events=20_000),
    "open40-late-walls": lambda: _mostly_empty(5),
    "den520d-16a-40k-events": lambda: _den520d(16, max_events=40_000),
}
SLOW_CASES: dict[str, Callable[[], TraversalRun]] = {
    "den520d-16a": lambda: _den520d(16),
    "empty128-8a": lambda: _empty(128, 128, 8),
    "empty256-8a": lambda: _empty(256, 256, 8),
    "empty1024-64a-30k-events": lambda: _empty(1024, 1024, 64, seed=5, nests=4,
                                               max_events=30_000),
}

EXPECTED: dict[str, str] = {
    "empty64-8a": "fbd112ec794b91669fd8c7200b85b9d9d8bb6a536093bfb6d9b4a4d85d6a56be",
    "empty80x30-12a-3nests-sync":
        "03120bf931c06e5cb6fb364107c0d0e70d34a0f8ec039f2d19fc90352d4cbced",
    "empty48-hetero": "44d189b5bd088041d97f810171554f89d40164554ecaf0de6c3a2360b771b7fc",
    "empty40-nearest": "c1871c3204c2111bfa3e965bf1f1a5072f045c48664605d1466ec9659604bf0a",
    "empty256-64a-20k-events": "93b420047502776dacaae43720bfb04dbf835fc727e582249b8490fea21852a0",
    "open40-late-walls": "c738d2b92b6b10b4bd18a5b7531f7b4c0a60956eca363d1ed737399ae90c24a6",
    "den520d-16a-40k-events": "4590ecdbafe66759b10e385c00f5e95ba62ae740bfa609e01c72e4f437ed8240",
    "den520d-16a": "62658b7f8252ea727c649a1080113daae4b864ab626b543cfa0da2c34435f7aa",
    "empty128-8a": "9c8fec0752a10c2c4b185a71580044e43796ccf0a6a093a88eae9505b54feda2",
    "empty256-8a": "c4e0421318e82975e9608552c064384c21c21bd5e7d2a617942da0e837e9402f",
    "empty1024-64a-30k-events":
        "226831e248c4ad3371f696d3469fd8f35799c2c7546ba7c793816bb75991e4ba",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_scale_fingerprint_unchanged(name: str) -> None:
    assert fingerprint(CASES[name]()) == EXPECTED[name]


@pytest.mark.skipif(not SLOW, reason="set SWARMEX_SLOW_TESTS=1 for the full runs")
@pytest.mark.parametrize("name", sorted(SLOW_CASES))
def test_scale_fingerprint_unchanged_full_runs(name: str) -> None:
    assert fingerprint(SLOW_CASES[name]()) == EXPECTED[name]


if __name__ == "__main__":  # regenerate EXPECTED
    for key, case in {**CASES, **SLOW_CASES}.items():
        print(f'    "{key}": "{fingerprint(case())}",', flush=True)
