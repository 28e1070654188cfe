"""``bench/traversal_targets_oracle.py``: the rivals'-targets oracle of
docs/traversal-variants.md §5 runs on a real map and prints its table; its oracle reserves
the rivals' current targets and nothing else (a run where no agent ever travels is MADGTA's,
decision for decision)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import swarmex
from swarmex.missions.traversal import run_traversal, uniform_agents
from swarmex.worlds import empty_grid, random_obstacles

ROOT = Path(__file__).resolve().parents[2]
SRC = Path(swarmex.__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))


def test_the_bench_prints_its_table(real_map):
    path = real_map("empty-16-16.map")
    env = {**os.environ, "PYTHONPATH": str(SRC), "SWARMEX_MAPS": str(path.parent)}
    out = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "traversal_targets_oracle.py"),
         "--maps", "empty-16-16", "--seeds", "2"],
        capture_output=True, text=True, env=env, cwd=ROOT, timeout=300, check=True)
    assert "12 runs on empty-16-16" in out.stderr
    rows = [line for line in out.stdout.splitlines() if line.startswith("| empty-16-16 | 4 |")]
    assert len(rows) == 1 and rows[0].count("%") == 4
    # the pooled row is "all" whatever maps are given; no group row repeats a map's row
    pooled = [line for line in out.stdout.splitlines() if line.startswith("| all | 4 |")]
    assert pooled == [rows[0].replace("| empty-16-16 |", "| all |", 1)]
    assert "the small maps" not in out.stdout


def test_the_oracle_keeps_two_travellers_off_one_target():
    from traversal_targets_oracle import TargetsOracle

    current: dict[int, int] = {}  # each agent's branch-3 target, from its own decisions

    class Watching(TargetsOracle):
        shared = 0

        def decide(self, belief, rng):
            current.pop(belief.me, None)  # deciding again ends its last target
            decision = super().decide(belief, rng)
            if decision.branch == 3:
                rivals = {v for a, v in current.items() if a != belief.me}
                Watching.shared += decision.target in rivals
                current[belief.me] = int(decision.target)
            return decision

    world = random_obstacles(16, 16, 0.2, seed=3)
    free = np.nonzero(~world.blocked)[0]
    agents = uniform_agents([int(free[0])] * 8, 2.0, 9.0)
    oracle = Watching()
    run = run_traversal(world, agents, oracle, seed=3)
    assert run.complete and Watching.shared == 0
    # one agent never has a rival: the oracle is MADGTA, move for move
    alone = uniform_agents([0], 2.0, 9.0)
    grid = empty_grid(6, 6)
    assert run_traversal(grid, alone, TargetsOracle(), seed=1).path_strings() == \
        run_traversal(grid, alone, "madgta", seed=1).path_strings()
