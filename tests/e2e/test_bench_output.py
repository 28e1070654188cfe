"""What some bench scripts print, as bench/README.md says: progress on stderr and never in the
tables on stdout, a table for every run set (even one without a variant to pair), and CPU
ratios taken after numba's one-time kernel load, not with it."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import swarmex

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "bench"
SRC = Path(swarmex.__file__).resolve().parents[1]
sys.path.insert(0, str(BENCH))


def _run(script: str, *argv: str, maps: Path | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    if maps is not None:
        env["SWARMEX_MAPS"] = str(maps)
    return subprocess.run([sys.executable, str(BENCH / script), *argv], capture_output=True,
                          text=True, env=env, cwd=ROOT, timeout=300, check=True)


def test_pareto_progress_goes_to_stderr():
    """``--pareto`` printed "instance N done" on stdout, above its table."""
    out = _run("gap_traversal_optimal.py", "--pareto", "1", "1.1", "--instances", "1",
               "--time-limit", "2", "--kind", "identical")
    assert "instance 0 done" in out.stderr
    assert "done" not in out.stdout
    assert out.stdout.splitlines()[0].startswith("| makespan at most |")


def test_no_variant_still_prints_the_means(real_map):
    """``--algorithms madgta nearest`` printed only the CPU table: every mean table was a
    variant's, and nearest is not a variant of madgta."""
    path = real_map("empty-16-16.map")
    out = _run("compare_traversal_variants.py", "--section", "variants", "--maps",
               "empty-16-16", "--agents", "3", "--nests", "dist", "--seeds", "2",
               "--algorithms", "madgta", "nearest", maps=path.parent)
    lines = out.stdout.splitlines()
    assert any("mean over seeds (no variant of madgta to pair)" in line for line in lines)
    header = next(line for line in lines if line.startswith("| map | agents | nests |"))
    row = next(line for line in lines if line.startswith("| empty-16-16 | 3 | dist |"))
    assert "paired" not in header
    assert header.count("|") == row.count("|") == 10  # 3 keys + 2 × (makespan, sum, moves)
    assert "CPU seconds per run" in out.stdout and "against madgta" not in out.stdout


def test_team_size_warms_every_algorithm_up_before_timing(monkeypatch: pytest.MonkeyPatch,
                                                          capsys: pytest.CaptureFixture[str]):
    """Without a warm-up, MADGTA's first timed run paid numba's one-time load and every
    "CPU / MADGTA's" ratio came out too low."""
    import traversal_team_size as bench

    calls: list[tuple[int, str]] = []
    real = bench.run_traversal

    def watched(world, agents, policy, seed=0):
        calls.append((world.width * world.height, policy))
        return real(world, agents, policy, seed=seed)

    monkeypatch.setattr(bench, "run_traversal", watched)
    assert bench.main(["--agents", "2", "--side", "10", "--seeds", "1",
                       "--algorithms", "madgta", "nearest"]) == 0
    assert calls == [(64, "madgta"), (64, "nearest"), (100, "madgta"), (100, "nearest")]
    assert "| 2 | nearest |" in capsys.readouterr().out
