"""``bench/compare_traversal_variants.py --runs``: every finished run is kept in a JSON-lines
file, and a later bench reuses it instead of running it again, so an interrupted bench loses
no finished run and a larger one grows a smaller one. ``--reference`` adds the paired tables
against another algorithm of the same runs."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import swarmex

ROOT = Path(__file__).resolve().parents[2]
SRC = Path(swarmex.__file__).resolve().parents[1]


def _bench(runs: Path, seeds: int, map_path: Path, *extra: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(SRC), "SWARMEX_MAPS": str(map_path.parent)}
    return subprocess.run(
        [sys.executable, str(ROOT / "bench" / "compare_traversal_variants.py"),
         "--section", "variants", "--maps", "empty-16-16", "--agents", "3", "--nests", "dist",
         "--seeds", str(seeds), "--algorithms", "madgta", "madgta+", "nearest",
         "--reference", "nearest", "--runs", str(runs), *extra],
        capture_output=True, text=True, env=env, cwd=ROOT, timeout=300, check=True)


def test_runs_are_kept_as_they_finish_and_reused(tmp_path, real_map):
    runs = tmp_path / "runs.jsonl"
    first = _bench(runs, 2, real_map("empty-16-16.map"))
    assert "0 of 6 runs reused" in first.stderr
    rows = [json.loads(line) for line in runs.read_text().splitlines()]
    assert len(rows) == 6 and {r["algorithm"] for r in rows} == {"madgta", "madgta+", "nearest"}
    assert "madgta+ against nearest" in first.stdout
    # a larger bench: the six runs are reused (their figures, CPU time included, are the
    # saved ones), only the third seed's three run
    second = _bench(runs, 3, real_map("empty-16-16.map"))
    assert "6 of 9 runs reused" in second.stderr
    grown = [json.loads(line) for line in runs.read_text().splitlines()]
    assert len(grown) == 9 and grown[:6] == rows and {r["seed"] for r in grown[6:]} == {2}
    # the same bench again runs nothing and prints the same tables
    again = _bench(runs, 3, real_map("empty-16-16.map"))
    assert "9 of 9 runs reused" in again.stderr and again.stdout == second.stdout
    assert len(runs.read_text().splitlines()) == 9


def test_a_channel_is_part_of_a_run(tmp_path, real_map):
    """``--channel`` runs the variants over one of the comm section's radios: its runs are
    new ones (not the perfect broadcast's, saved in the same file) and say their channel."""
    runs = tmp_path / "runs.jsonl"
    _bench(runs, 2, real_map("empty-16-16.map"))
    lossy = _bench(runs, 2, real_map("empty-16-16.map"), "--channel", "loss 0.3")
    assert "0 of 6 runs reused" in lossy.stderr
    rows = [json.loads(line) for line in runs.read_text().splitlines()]
    assert [r["channel"] for r in rows] == ["perfect"] * 6 + ["loss 0.3"] * 6
    assert any(a["messages"] != b["messages"] for a, b in zip(rows[:6], rows[6:], strict=True))
