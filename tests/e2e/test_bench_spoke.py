"""``bench/foraging_spoke.py`` measures a team kept on one ray from the nest (docs/foraging.md,
"A team on one ray"). What its table rests on: the bands partition the grid into equal parts,
the routes are walks that visit every cell, the team turns together, and the spread measure
can tell a spoke from a team that is not one."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from swarmex.missions.foraging import timed_plan
from swarmex.missions.foraging.timed import execute

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

from foraging_spoke import instant_word_q, line_of, spoke_plan, spread, sweeps  # noqa: E402


@pytest.mark.parametrize(("g", "n"), [(32, 4), (64, 8)])
def test_the_bands_split_the_grid_into_equal_parts(g, n):
    bands = sweeps(g, n)
    cells = [c for band in bands for c in band]
    nest = (g // 2, g // 2)
    assert len(cells) == len(set(cells)) == g * g - 1 and nest not in cells
    assert max(len(b) for b in bands) - min(len(b) for b in bands) <= 6
    # band i lies outside band i - 1 on every line (by ring, the Chebyshev distance)
    for inner, outer in zip(bands, bands[1:], strict=False):
        last = {}
        for x, y in inner:
            line, ring = line_of(x - nest[0], y - nest[1])
            last[line] = max(last.get(line, 0), ring)
        for x, y in outer:
            line, ring = line_of(x - nest[0], y - nest[1])
            assert ring > last.get(line, 0)


@pytest.mark.parametrize(("g", "n"), [(32, 4), (64, 8)])
def test_the_team_visits_every_cell_and_turns_together(g, n):
    timed = execute(spoke_plan(g, n, keep_route=False))
    seen = np.zeros((g, g), dtype=bool)
    seen[timed.pos[:, :, 0], timed.pos[:, :, 1]] = True
    assert seen.all()
    assert spread(timed) < 30  # degrees from the team's mean direction, median over rounds


def test_the_spread_tells_a_spoke_from_a_team_round_the_nest():
    assert spread(timed_plan("sectors", 64, 8)) > 120  # one robot per sector


def test_the_script_prints_the_table_on_two_cells():
    out = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "foraging_spoke.py"), "--per-band", "2",
         "--floor-search", "2"],
        capture_output=True, text=True, timeout=300, check=True,
    ).stdout  # fmt: skip
    assert "| spoke, seed detour |" in out and "| strips |" in out
    assert "Q, word instant" in out
    assert "at least (g² − 1)/(2n) = 512" in out


def test_the_instant_word_oracle_is_the_run_when_there_is_no_one_to_tell():
    # one robot: the finder is the whole team, so the oracle's Q is the real run's
    from swarmex.missions.foraging.sim import run_mission

    timed = timed_plan("strips", 16, 1)
    for food in [(3, 4), (12, 2), (8, 15)]:
        run = run_mission(timed, food, 5, "relay-food", record=False)
        assert instant_word_q(timed, food, units=5) == run.makespan - run.discovery
