"""The process pool's recovery from pools that fail before a run is handed to them.

A worker's death can race a submit; the failed submit then kills CPython's fork server (it
dies on a request whose client vanished), and until it has exited every new pool fails to
start. Those refusals must neither crash the run nor add to the count of worker crashes.
"""

from __future__ import annotations

import multiprocessing.forkserver
import operator
import os
import socket
from collections.abc import Callable
from typing import Any

import pytest

from swarmex.experiments import pool
from swarmex.experiments.pool import WorkersDied, run_local


def exit_on_negative(x: int) -> int:
    """A job; a negative one kills its worker process, every time."""
    if x < 0:
        os._exit(3)
    return 2 * x


def collect() -> tuple[dict, Callable[[Any, Any], None]]:
    results: dict = {}
    return results, results.__setitem__


def test_a_fork_server_killed_by_a_vanished_client_is_started_again(monkeypatch):
    monkeypatch.setattr(pool, "_forkable", lambda: False)  # as while a progress bar draws
    results, finish = collect()
    run_local([1, 2, 3], operator.neg, 2, finish)  # the fork server runs
    server = multiprocessing.forkserver._forkserver
    assert server._forkserver_pid is not None
    with socket.socket(socket.AF_UNIX) as client:  # a request whose client vanishes:
        client.connect(server._forkserver_address)  # the fork server dies of it
    results.clear()
    run_local(list(range(8)), operator.neg, 2, finish)
    assert results == {x: -x for x in range(8)}


def test_a_refused_pool_after_two_crashes_does_not_stop_the_run(monkeypatch):
    """The crashing job is given up on and every other job runs: one refused pool is not a
    third crash (it used to raise WorkersDied, "before a run was handed to them")."""
    made = []
    handed: list[int] = []  # the crashing job's hand-overs
    refused: list[int] = []
    real = pool._pool

    def refuses_once_after_the_second_crash(workers, preload):
        executor, stop = real(workers, preload)
        made.append(executor)
        submit = executor.submit
        refuse = len(handed) == 2 and not refused

        def watch(fn, call, jobs):
            if refuse and not refused:
                refused.append(len(made))
                raise OSError("handle is closed")
            handed.extend(j for j in jobs if j < 0)
            return submit(fn, call, jobs)

        executor.submit = watch
        return executor, stop

    monkeypatch.setattr(pool, "_pool", refuses_once_after_the_second_crash)
    results, finish = collect()
    died: list[int] = []
    jobs = [-1, *range(1, 10)]
    run_local(jobs, exit_on_negative, 1, finish, died=died.append)
    assert died == [-1]
    assert results == {x: 2 * x for x in range(1, 10)}
    assert handed == [-1, -1] and refused and len(made) == refused[0] + 1


def test_pools_that_never_start_raise_workers_died(monkeypatch):
    made = []
    real = pool._pool

    def refusing(workers, preload):
        executor, stop = real(workers, preload)
        made.append(executor)

        def refuse(*args, **kwargs):
            raise OSError("handle is closed")

        executor.submit = refuse
        return executor, stop

    monkeypatch.setattr(pool, "_pool", refusing)
    monkeypatch.setattr(pool, "REFUSAL_PAUSE", 0.001)
    results, finish = collect()
    with pytest.raises(WorkersDied, match="no worker process could be started"):
        run_local([1, 2], operator.neg, 2, finish)
    assert len(made) == pool.MAX_REFUSALS and not results
