"""``bench/foraging_level_comb.py`` measures a comb that never shears (docs/foraging.md, "A
team that never shears"). What its table rests on: the comb is level in every round and
visits every cell, the level check can fail, and with the route kept the word passes one row
per round."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from swarmex.missions.foraging import timed_plan
from swarmex.missions.foraging.sim import run_mission
from swarmex.missions.foraging.timed import execute

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

from foraging_level_comb import check_level, exact_e, level_plan  # noqa: E402


@pytest.mark.parametrize(("g", "n"), [(32, 4), (64, 8)])
def test_the_level_comb_shares_one_column_every_round_and_visits_every_cell(g, n):
    timed = execute(level_plan(g, n, keep_route=True))
    check_level(timed)  # raises otherwise
    pos = timed.pos[timed.t_sync :]
    rows = np.sort(pos[:, :, 1], axis=1)
    assert (np.diff(rows, axis=1) == 1).all()  # n adjacent rows
    # after the start only the turns revisit cells, n - 1 rounds' worth each, and the sweep
    # passes the nest and the cell the robots left it by (2)
    seen = np.zeros((g, g), dtype=bool)
    start = timed.pos[: timed.t_sync + 1]
    seen[start[:, :, 0], start[:, :, 1]] = True
    steps = (timed.t_end - timed.t_sync) * n
    turns = timed.plan.notes["passes"] - 1
    assert steps - int((~seen).sum()) == (n - 1) * n * turns + 2


def test_the_level_check_fails_on_the_sheared_comb():
    with pytest.raises(AssertionError, match="not level"):
        check_level(timed_plan("comb", 32, 4))


def test_with_the_route_kept_the_word_passes_one_row_per_round():
    g, n = 64, 8
    kept = execute(level_plan(g, n, keep_route=True))
    detour = execute(level_plan(g, n, keep_route=False))
    for food in [(5, 9), (40, 50), (60, 3)]:
        o = run_mission(kept, food, 20, "relay-food", record=False)
        assert all(c is not None for c in o.informed_at)
        assert max(o.informed_at) - o.discovery <= n - 1
        slow = run_mission(detour, food, 20, "relay-food", record=False)
        assert max(slow.informed_at) - slow.discovery > n - 1


def test_exact_e_is_the_mean_first_visit_and_above_the_floor():
    timed = execute(level_plan(32, 4, keep_route=True))
    first = {}
    for t, row in enumerate(timed.pos):
        for x, y in row:
            first.setdefault((int(x), int(y)), t)
    del first[(16, 16)]
    assert exact_e(timed) == pytest.approx(np.mean(list(first.values())))
    assert exact_e(timed) >= (32 * 32 - 1) / (2 * 4)


def test_the_script_prints_the_table_on_two_cells():
    out = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "foraging_level_comb.py"), "--per-band", "2",
         "--floor-search", "2"],
        capture_output=True, text=True, timeout=300, check=True,
    ).stdout  # fmt: skip
    assert "| level comb, route kept |" in out
    assert "| strips |" in out
    assert "at least (g² − 1)/(2n) = 512" in out
