"""The decision broker: strict hand-over, results, errors and abandoning a run."""

from __future__ import annotations

import threading

import pytest

from swarmex.envs.broker import Abandoned, DecisionBroker


def counting_run(ask):
    total = 0
    for i in range(5):
        total += ask(("q", i))
    return total


def test_every_request_is_answered_in_order_and_the_result_kept():
    b = DecisionBroker(counting_run)
    seen = []
    req = b.start()
    while req is not None:
        seen.append(req)
        req = b.answer(10 * req[1])
    assert seen == [("q", i) for i in range(5)]
    assert b.finished and b.result == sum(10 * i for i in range(5))
    with pytest.raises(RuntimeError):
        b.answer(0)


def test_only_one_thread_runs_at_a_time():
    running = threading.Semaphore(1)
    log = []

    def run(ask):
        for i in range(50):
            assert running.acquire(blocking=False)  # the caller is not running now
            log.append(i)
            running.release()
            ask(i)
        return len(log)

    b = DecisionBroker(run)
    req = b.start()
    while req is not None:
        assert running.acquire(blocking=False)
        running.release()
        req = b.answer(None)
    assert b.result == 50


def test_an_error_in_the_run_reaches_the_caller():
    def run(ask):
        ask(1)
        raise ValueError("boom")

    b = DecisionBroker(run)
    assert b.start() == 1
    with pytest.raises(ValueError, match="boom"):
        b.answer(0)


def test_close_abandons_a_run_midway_and_the_worker_ends():
    unwound = []

    def run(ask):
        try:
            while True:
                ask("again")
        except Abandoned:
            unwound.append(True)
            raise

    b = DecisionBroker(run)
    assert b.start() == "again"
    b.answer(1)
    b.close()
    assert unwound == [True]
    assert b._thread is not None and not b._thread.is_alive()


def test_a_run_without_decisions_finishes_at_start():
    b = DecisionBroker(lambda ask: 42)
    assert b.start() is None and b.result == 42
