"""``--workers`` of every reproduction is checked before anything runs, and the processes
forked for it are bounded by the machine: ``--workers 100000`` forked until the OOM killer
came (and SIGTERM went unheard for minutes)."""

from __future__ import annotations

import os

import pytest

from swarmex.cli import main
from swarmex.experiments import pool


@pytest.mark.parametrize("study", ["traversal", "foraging", "exploration", "roadmap"])
@pytest.mark.parametrize("workers", [0, 100_000])
def test_a_reproduction_refuses_a_worker_count_no_machine_has(study, workers, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["reproduce", study, "--quick", "--workers", str(workers),
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"swarmex: error: --workers must be between 1 and 1024, got {workers}"
    assert not out.exists()  # nothing ran


def test_local_processes_are_a_few_per_core_at_most(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    assert [pool.local_processes(w) for w in (1, 2, 8, 9, 1024)] == [1, 2, 8, 8, 8]
    monkeypatch.setattr(os, "cpu_count", lambda: None)  # unknown: one core
    assert pool.local_processes(64) == 4


def test_a_run_of_many_jobs_forks_no_more_than_local_processes(monkeypatch):
    from swarmex.studies import runner

    seen = []

    def fake_run_local(items, call, workers, finish, **kw):  # the pool, in this process
        seen.append(workers)
        for job in items:
            finish(job, call(job))

    monkeypatch.setattr(runner, "run_local", fake_run_local)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    done = runner.run_jobs(list(range(-25, 25)), abs, str, workers=1000, show=False)
    assert seen == [8] and done.results == [abs(j) for j in range(-25, 25)]
