"""The study runner: results in job order, resume, worker crashes, interruptions."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from swarmex.experiments.pool import WorkersDied
from swarmex.experiments.progress import Journal
from swarmex.experiments.runstore import RunStore
from swarmex.studies.runner import run_jobs

LOG = "SWARMEX_TEST_RUNNER_LOG"  # a file every run appends its key to (one write per run)


def square(job: dict) -> dict:
    """A tiny deterministic job; logs that it ran."""
    log = job.get("log") or os.environ.get(LOG)
    if log:
        with open(log, "a", encoding="utf-8") as fh:
            fh.write(f"{job['k']}\n")
    if job.get("crash") and not Path(job["crash"]).exists():
        Path(job["crash"]).touch()  # crash once: the retry runs normally
        os._exit(3)
    if job.get("always_crash"):
        os._exit(3)
    if job.get("sleep"):
        time.sleep(job["sleep"])
    return {"key": job["k"], "x": job["x"], "y": job["x"] ** 2}


def key(job: dict) -> str:
    return job["k"]


_LOG: list[str] = []  # the current test's log file, carried in each job (a pool worker from
# a fork server started by an earlier test does not see a later test's environment)


def jobs(n: int, **extra) -> list[dict]:
    carry = {"log": _LOG[-1]} if _LOG else {}
    return [{"k": f"j{i}", "x": i, **carry, **extra} for i in range(n)]


def ran(log: Path) -> list[str]:
    return log.read_text().split() if log.exists() else []


@pytest.fixture
def log(tmp_path, monkeypatch) -> Path:
    path = tmp_path / "ran.log"
    monkeypatch.setenv(LOG, str(path))
    _LOG.append(str(path))
    yield path
    _LOG.pop()


def test_results_come_in_job_order_and_equal_the_serial_ones(tmp_path, log):
    js = jobs(40)
    js.insert(5, dict(js[30]))  # the same key twice: one run, its result in both places
    serial = run_jobs(js, square, key, workers=1, show=False)
    pooled = run_jobs(js, square, key, workers=2, show=False)
    assert pooled.results == serial.results
    assert [r["key"] for r in pooled.results] == [j["k"] for j in js]
    assert (pooled.ran, pooled.reused) == (40, 0)
    assert sorted(ran(log)) == sorted(2 * [j["k"] for j in jobs(40)])


def test_a_rerun_resumes_from_the_journal(tmp_path, log):
    path = tmp_path / "runs.jsonl"
    with Journal(path) as journal:
        first = run_jobs(jobs(10), square, key, store=journal, workers=2, show=False)
    assert first.ran == 10 and len(path.read_text().splitlines()) == 10
    log.unlink()
    more = jobs(14)
    with Journal(path) as journal:
        second = run_jobs(more, square, key, store=journal, workers=2, show=False)
    assert (second.ran, second.reused) == (4, 10)
    assert sorted(ran(log)) == ["j10", "j11", "j12", "j13"]
    assert second.results == run_jobs(more, square, key, show=False).results
    assert len(path.read_text().splitlines()) == 14
    assert not list(tmp_path.glob(".*spool*")), "the spool is gone once folded"


def test_a_run_store_is_a_store_too(tmp_path):
    store = RunStore(tmp_path / "runs.json", {"study": "t"})
    js = [{"k": f"r{i}", "x": i} for i in range(5)]

    def with_id(job: dict) -> dict:
        return {**square(job), "id": job["k"]}

    run_jobs(js, with_id, key, store=store, show=False)
    store.close()
    data = json.loads((tmp_path / "runs.json").read_text())
    assert sorted(data["runs"]) == [f"r{i}" for i in range(5)]
    again = RunStore(tmp_path / "runs.json", {"study": "t"})
    assert run_jobs(js, with_id, key, store=again, show=False).ran == 0


def test_a_worker_crash_loses_only_unfinished_runs(tmp_path, log):
    """Small runs travel in chunks; the runs of a chunk finished before its worker died are
    taken from the worker's spool, not run again."""
    js = jobs(80)
    js[40]["crash"] = str(tmp_path / "crashed-once")
    with Journal(tmp_path / "runs.jsonl") as journal:
        out = run_jobs(js, square, key, store=journal, workers=2, show=False)
    assert [r["y"] for r in out.results] == [i * i for i in range(80)]
    assert (tmp_path / "crashed-once").exists()
    counts = {k: ran(log).count(k) for k in set(ran(log))}
    assert counts.pop("j40") == 2  # the crashing run, and its retry
    assert len(counts) == 79
    # no finished run was run again; the other worker (stopped with the broken pool) may
    # have been in the middle of one run, which is run again
    assert sum(c - 1 for c in counts.values()) <= 1
    assert len(Journal(tmp_path / "runs.jsonl").rows()) == 80


def test_a_run_that_always_kills_its_worker_stops_the_study_keeping_the_rest(tmp_path, log):
    js = jobs(12)
    js[6]["always_crash"] = True
    path = tmp_path / "runs.jsonl"
    with Journal(path) as journal, pytest.raises(WorkersDied, match="killed its worker"):
        run_jobs(js, square, key, store=journal, workers=2, show=False)
    kept = Journal(path).rows()
    # what finished before the stop is kept (how much depends on the timing of the two
    # workers on a loaded machine, so only the crashing run's absence is certain)
    assert "j6" not in kept
    assert set(kept) <= {f"j{i}" for i in range(12)}
    assert not list(tmp_path.glob(".*spool*"))


def test_an_interrupted_run_keeps_what_finished_and_resumes(tmp_path, log):
    path = tmp_path / "runs.jsonl"
    seen = []

    def stop(job: dict, result: dict) -> None:
        seen.append(job["k"])
        if len(seen) == 5:
            raise KeyboardInterrupt

    js = jobs(30, sleep=0.01)
    with Journal(path) as journal, pytest.raises(KeyboardInterrupt):
        run_jobs(js, square, key, store=journal, workers=2, show=False, on_result=stop)
    kept = set(Journal(path).rows())
    assert set(seen) <= kept and len(kept) < 30  # runs in flight at the stop are kept too
    log.unlink()
    with Journal(path) as journal:
        out = run_jobs(js, square, key, store=journal, workers=2, show=False)
    assert out.reused == len(kept) and out.ran == 30 - len(kept)
    assert set(ran(log)) == {j["k"] for j in js} - kept
    assert [r["y"] for r in out.results] == [i * i for i in range(30)]


SCRIPT = """
import sys
from swarmex.experiments.progress import Journal
from swarmex.studies.runner import run_jobs
sys.path.insert(0, {tests!r})
from studies.test_runner import jobs, key, square

if __name__ == "__main__":
    with Journal({path!r}) as journal:
        run_jobs(jobs(60, sleep=0.05), square, key, store=journal, workers=2, show=False)
"""


def _sigint_default() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL])
def test_a_stopped_driver_loses_no_finished_run(tmp_path, log, sig):
    """Ctrl-C or SIGKILL a driver mid-run: the rerun runs only what never finished (a killed
    driver's last results are folded in from the workers' spool)."""
    path = tmp_path / "runs.jsonl"
    script = tmp_path / "drive.py"
    tests = str(Path(__file__).resolve().parents[1])
    script.write_text(SCRIPT.format(tests=tests, path=str(path)))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    # a background job of a non-interactive shell (a CI script run with "&") inherits
    # SIGINT ignored, and Python then never raises KeyboardInterrupt: the child gets Ctrl-C's
    # default back, as a terminal's process would have it
    proc = subprocess.Popen([sys.executable, str(script)], env=env, stderr=subprocess.PIPE,
                            preexec_fn=_sigint_default)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None:
            if path.exists() and len(path.read_text().splitlines()) >= 6:
                break
            time.sleep(0.01)
        proc.send_signal(sig)
    finally:
        proc.wait(timeout=20)
    before = ran(log)
    assert 6 <= len(set(before)) < 60, "the driver should have been stopped part way"
    log.unlink()
    with Journal(path) as journal:
        out = run_jobs(jobs(60, sleep=0.05), square, key, store=journal, workers=2, show=False)
    twice = set(ran(log)) & set(before)
    # Ctrl-C: the driver waits for the runs in flight and keeps them; SIGKILL: a run a
    # worker had started and not finished (at most one per worker) is run again
    assert len(twice) <= (0 if sig == signal.SIGINT else 2), sorted(twice)
    assert [r["y"] for r in out.results] == [i * i for i in range(60)]
    assert out.reused + out.ran == 60
    assert not list(tmp_path.glob(".*spool*"))



def test_the_bar_is_silent_when_not_drawn_on_a_terminal(tmp_path, log, capsys):
    """In a pipe or a log the bar prints nothing: Rich used to print its last state on
    standard output when it stopped (``swarmex reproduce foraging --quick | cat`` began with a
    truncated bar); on a terminal it is drawn on standard error."""
    from io import StringIO

    from rich.console import Console

    from swarmex.experiments.progress import runs_progress

    done = run_jobs(jobs(3), square, key, workers=1, label="quiet", describe=key)
    assert len(done.results) == 3
    out, err = capsys.readouterr()
    assert (out, err) == ("", "")
    assert runs_progress("x").console.stderr
    term = StringIO()
    bar = runs_progress("drawn", Console(file=term, force_terminal=True, width=80))
    bar.add_task("", total=1, completed=1)
    bar.start()
    bar.stop()
    assert "drawn" in term.getvalue()
