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


class Pools:
    """Pools whose submits may be refused (an OSError, as when the fork server is dying):
    ``refuse(pool number, jobs)`` decides for each submit; the pools made and the jobs each
    accepted submit handed over are recorded."""

    def __init__(self, monkeypatch, refuse) -> None:
        self.made: list = []
        self.handed: list[list] = []
        self.refused: list[int] = []  # the numbers of the pools that refused a submit
        self.refuse = refuse
        self.real = pool._pool
        monkeypatch.setattr(pool, "_pool", self.make)
        monkeypatch.setattr(pool, "REFUSAL_PAUSE", 0.001)

    def make(self, workers, preload):
        executor, stop = self.real(workers, preload)
        self.made.append(executor)
        number = len(self.made)
        submit = executor.submit

        def watch(fn, call, jobs):
            if self.refuse(number, jobs):
                self.refused.append(number)
                raise OSError("handle is closed")
            self.handed.append(list(jobs))
            return submit(fn, call, jobs)

        executor.submit = watch
        return executor, stop


def test_a_refused_pool_after_two_crashes_does_not_stop_the_run(monkeypatch):
    """The crashing job is given up on and every other job runs: one refused pool is not a
    third crash (it used to raise WorkersDied, "before a run was handed to them")."""

    def once_after_the_second_crash(number, jobs):
        crashes = sum(j < 0 for handed in pools.handed for j in handed)
        return crashes == 2 and not pools.refused

    pools = Pools(monkeypatch, once_after_the_second_crash)
    results, finish = collect()
    died: list[int] = []
    jobs = [-1, *range(1, 10)]
    run_local(jobs, exit_on_negative, 1, finish, died=died.append)
    assert died == [-1]
    assert results == {x: 2 * x for x in range(1, 10)}
    assert sum(j < 0 for handed in pools.handed for j in handed) == 2
    assert len(pools.refused) == 1 and len(pools.made) == pools.refused[0] + 1


def test_pools_that_never_start_raise_workers_died(monkeypatch):
    pools = Pools(monkeypatch, lambda number, jobs: True)
    results, finish = collect()
    with pytest.raises(WorkersDied, match="no worker process could be started"):
        run_local([1, 2], operator.neg, 2, finish)
    assert len(pools.made) == pool.MAX_REFUSALS and not results


def test_ready_waits_for_a_pool_that_took_work(monkeypatch):
    # ready() starts a caller's progress thread: after a refused first pool, the next pool
    # (made while the driver still had one thread) must not fork with that thread alive
    pools = Pools(monkeypatch, lambda number, jobs: number == 1)
    at_ready: list[int] = []
    results, finish = collect()
    run_local([1, 2, 3], operator.neg, 2, finish,
              ready=lambda: at_ready.append(len(pools.handed)))
    assert results == {1: -1, 2: -2, 3: -3}
    assert pools.refused == [1] and len(at_ready) == 1 and at_ready[0] > 0
