"""The bench scripts' command lines: a wrong argument is one line on stderr and exit status 2.

bench/README.md promises scripts a user runs by hand; before bench/_cli.py, ``--repeats 0``,
``--seeds 0``, ``--runs 0``, ``--seconds -1``, an unknown strategy or revision, ``--only 9``
or a missing ``--load`` file ended in a traceback (or, for ``--seeds 0``, silently ran the
default 10 or 30 seeds), and two scripts ignored every argument. Each case here is refused
before any run, so the whole file costs a process start per case.
"""

from __future__ import annotations

import argparse
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
import _cli  # noqa: E402

BAD = [
    ("bench_roadmap.py", ["--repeats", "0"], "--repeats: must be at least 1, got 0"),
    ("bench_net_loss.py", ["--seeds", "0"], "must be at least 1"),
    ("bench_net_loss.py", ["--loss", "1.5"], "--loss: must be in [0, 1)"),
    ("bench_envs.py", ["--seconds", "-1", "--no-pogema"], "must be a positive number"),
    ("bench_envs.py", ["--only", "nothing", "--no-pogema"], "matches no case"),
    ("bench_startup.py", ["--runs", "0"], "must be at least 1"),
    ("bench_startup.py", ["--src", "/nonexistent"], "no swarmex package there"),
    ("bench_sweep.py", ["--runs", "0"], "must be at least 1"),
    ("bench_traversal_den520d.py", ["--runs", "0"], "must be at least 1"),
    ("traversal_crowd.py", ["--events", "0"], "must be at least 1"),
    ("bench_exploration.py", ["--robots", "0"], "must be at least 1"),
    ("bench_exploration.py", ["--strategy", "nope"], "--strategy must be one of"),
    ("bench_net.py", ["--agents", "x"], "must be an integer, got 'x'"),
    ("bench_net.py", ["--grid", "0x0", "--agents", "2"], "--grid: must be at least 1, got 0"),
    # --mesh was split only after the whole 26 s network bench, then a ValueError traceback
    ("bench_net.py", ["--mesh", "bogus"], "--mesh: expected WxHxROBOTS, got 'bogus'"),
    ("bench_distance_fields.py", ["--bogus"], "unrecognized arguments: --bogus"),
    ("bench_foraging.py", ["--bogus"], "unrecognized arguments: --bogus"),
    ("compare_exploration_strategies.py", ["--seeds", "0"], "must be at least 2"),
    ("compare_exploration_strategies.py", ["--only", "9"], "index 9 out of range"),
    ("compare_exploration_strategies.py", ["--strategies", "nope"], "unknown nope"),
    ("compare_roadmap_rules.py", ["--jobs", "0"], "must be at least 1"),
    ("compare_roadmap_rules.py", ["--seeds", "1"], "at least 2 (a 95 % interval needs two pairs)"),
    ("compare_foraging_patterns.py", ["--per-band", "1"], "must be at least 2"),
    ("foraging_level_comb.py", ["--per-band", "1"], "must be at least 2"),
    ("compare_traversal_variants.py", ["--comm-seeds", "1"], "must be at least 2"),
    ("compare_foraging_patterns.py", ["--ours", "nope"], "--ours: unknown nope"),
    ("compare_foraging_patterns.py", ["--load", "/nonexistent/runs.json"],
     "cannot read /nonexistent/runs.json"),
    ("compare_traversal_variants.py", ["--algorithms", "nope"], "unknown online algorithm"),
    ("compare_traversal_variants.py", ["--algorithms", "madgta", "--reference", "madgta-k"],
     "--reference madgta-k: not one of --algorithms"),
    ("compare_traversal_fingerprints.py", ["--rev", "no-such-revision-xyz", "--seeds", "1"],
     "--rev no-such-revision-xyz"),
    ("gap_traversal_optimal.py", ["--instances", "0"], "must be at least 1"),
    ("gap_traversal_optimal.py", ["--pareto", "0.5"], "must be a number >= 1 (x optimal)"),
    ("gap_traversal_optimal.py", ["--budget", "-1"], "must be a number >= 0"),
    ("profile_traversal.py", ["--case", "empty", "--side", "0"], "must be at least 1"),
    ("gap_traversal_optimal.py", ["--algorithms", "nope"], "unknown online algorithm"),
    ("gap_traversal_optimal.py", ["--algorithms", "madgta-r@nokey"], "algorithm 'madgta-r@nokey'"),
    ("exploration_bound.py", ["--only", "x"], "indices are integers"),
    ("compare_traversal_variants.py", ["--json", "/nonexistent/out.json"],
     "cannot write /nonexistent/out.json: folder /nonexistent does not exist"),
    ("compare_exploration_strategies.py", ["--json", "/nonexistent/out.json"], "cannot write"),
    ("compare_roadmap_rules.py", ["--json", "/nonexistent/out.json"], "cannot write"),
    ("gap_traversal_optimal.py", ["--json", "/nonexistent/out.json"], "cannot write"),
    ("compare_foraging_patterns.py", ["--raw", "/nonexistent/raw.json"], "cannot write"),
    ("compare_foraging_patterns.py", ["--floors", "/tmp"], "it is a folder"),
    ("exploration_fingerprints.py", ["--record", "/nonexistent/fp.json"], "does not exist"),
    ("exploration_fingerprints.py", ["--check", "/nonexistent/fp.json"],
     "cannot read /nonexistent/fp.json"),
    ("profile_traversal.py", ["--case", "empty", "--agents", "0"], "must be at least 1"),
    ("endgame_headroom.py", ["--x", "0"], "must be at least 1"),
    ("traversal_idle_moves.py", ["--end", "0"], "must be at least 1"),
    ("traversal_idle_moves.py", ["--algorithms", "nope"], "unknown online algorithm"),
    ("traversal_idle_moves.py", ["--algorithms", "madgta-f@ils=x"], "option 'ils' must be int"),
    ("traversal_targets_oracle.py", ["--seeds", "1"], "must be at least 2"),
    ("traversal_team_size.py", ["--density", "1"], "--density must be in [0, 1), got 1.0"),
    ("traversal_team_size.py", ["--algorithms", "madgta-f@x=1"], "madgta-f has no option 'x'"),
    ("traversal_targets_oracle.py", ["--maps", "nope"], "no map 'nope' in"),
    # these printed an empty table (or wrote {}) and exited 0
    ("traversal_team_size.py", ["--side", "1"], "more than the 1 free cells of --side 1"),
    ("exploration_fingerprints.py", ["--record", "/tmp/fp-unused.json", "--only", "nosuch"],
     "--only nosuch: no case's name contains it"),
    ("traversal_idle_moves.py", ["--maps", "nope"], "no map 'nope' in"),
    ("endgame_headroom.py", ["--maps", "nope"], "no map 'nope' in"),
    ("compare_traversal_variants.py", ["--quick", "--maps", "nope"], "no map 'nope' in"),
    ("compare_traversal_variants.py", ["--comm-maps", "nope"], "no map 'nope' in"),
    ("compare_traversal_variants.py", ["--runs", "/nonexistent/x.jsonl"],
     "cannot write /nonexistent/x.jsonl: folder /nonexistent does not exist"),
]


@pytest.mark.parametrize(("script", "argv", "says"), BAD, ids=[f"{s}{a}" for s, a, _ in BAD])
def test_a_bad_argument_is_one_line_and_status_2(script: str, argv: list[str], says: str):
    maps = Path(os.environ.get("SWARMEX_MAPS", ROOT.parent / "shared" / "maps"))
    if says.startswith("no map") and not maps.is_dir():
        pytest.skip(f"a map name is checked against the maps folder, and {maps} is absent")
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    proc = subprocess.run([sys.executable, str(BENCH / script), *argv], capture_output=True,
                          text=True, env=env, cwd=ROOT, timeout=120)
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    assert lines[0].startswith(f"{script}: error: ") and says in lines[0], lines[0]
    assert proc.stdout == ""  # refused before any run


def test_argument_types():
    assert _cli.positive_int("3") == 3
    assert _cli.nonneg_int("0") == 0
    assert _cli.probability("0") == 0.0
    assert _cli.int_list("10, 50") == [10, 50]
    assert _cli.nonneg_float("0") == 0.0
    for fn, text in ((_cli.positive_int, "0"), (_cli.positive_int, "1.5"),
                     (_cli.nonneg_int, "-1"), (_cli.positive_float, "nan"),
                     (_cli.positive_float, "inf"), (_cli.positive_float, "0"),
                     (_cli.probability, "1"), (_cli.nonneg_float, "-0.5"),
                     (_cli.int_list, "10,,50")):
        with pytest.raises(argparse.ArgumentTypeError):
            fn(text)


def test_run_turns_input_errors_into_one_line(capsys: pytest.CaptureFixture[str]):
    from swarmex.errors import InputError

    def bad() -> int:
        raise InputError("no such map")

    with pytest.raises(SystemExit) as exc:
        _cli.run(bad)
    assert exc.value.code == 2
    assert capsys.readouterr().err.strip().endswith("error: no such map")
    with pytest.raises(SystemExit) as exc:
        _cli.run(lambda: 3)
    assert exc.value.code == 3


def test_run_says_ctrl_c_in_one_line(capsys: pytest.CaptureFixture[str]):
    def interrupted() -> int:
        raise KeyboardInterrupt

    with pytest.raises(SystemExit) as exc:
        _cli.run(interrupted)
    assert exc.value.code == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "interrupted (Ctrl-C)" in err


def test_paired_count():
    assert _cli.paired_count("2") == 2
    with pytest.raises(argparse.ArgumentTypeError, match="two pairs"):
        _cli.paired_count("1")


def test_pogema_install_failure_is_a_skip(monkeypatch: pytest.MonkeyPatch, tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]):
    """Offline, bench_envs used to die in a CalledProcessError and keep the half-made venv,
    so every later run skipped the install and printed a list's repr as its message."""
    import bench_envs

    monkeypatch.setattr(Path, "home", lambda: tmp_path)
    monkeypatch.setattr(bench_envs.venv, "create", lambda home, with_pip: (home / "bin").mkdir(
        parents=True))
    monkeypatch.setattr(bench_envs.subprocess, "run",
                        lambda *a, **k: subprocess.CompletedProcess(a, 1, "", "no network"))
    assert bench_envs.pogema(0.1, 0.0) is None
    assert not (tmp_path / ".cache" / "swarmex" / "bench-pogema").exists()
    err = capsys.readouterr().err
    assert "POGEMA skipped: pip install pogema==1.4.* failed" in err


def test_ctrl_c_ends_a_pooled_comparison_at_once(tmp_path: Path):
    """``with ProcessPoolExecutor()`` waited on leaving for every queued job: a Ctrl-C went on
    running a quick traversal comparison for 31 s, and hung a foraging one until killed."""
    import signal
    import time

    env = {**os.environ, "PYTHONPATH": str(SRC),
           "SWARMEX_MAPS": str(tmp_path)}  # open 40 x 40 maps under the real names: minutes of runs
    for name in ("empty-16-16", "random-32-32-20", "room-32-32-4"):
        (tmp_path / f"{name}.map").write_text(
            "type octile\nheight 40\nwidth 40\nmap\n" + "\n".join(["." * 40] * 40) + "\n")
    proc = subprocess.Popen(
        [sys.executable, str(BENCH / "compare_traversal_variants.py"), "--quick", "--jobs", "2",
         "--section", "variants"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        env=env, cwd=tmp_path)  # fmt: skip
    try:
        assert proc.stderr is not None
        first = proc.stderr.readline()  # "variants: 270 runs on ...": the pool is at work
        assert first.startswith("variants:"), first
        time.sleep(1.0)
        proc.send_signal(signal.SIGINT)
        start = time.monotonic()
        rest = proc.stderr.read()
        code = proc.wait(timeout=20)
        assert time.monotonic() - start < 5
    finally:
        proc.kill()
    assert code == 130, rest
    assert rest.strip().splitlines()[-1] == "compare_traversal_variants.py: interrupted (Ctrl-C)"
    assert "Traceback" not in rest
