"""The local process pool that every long experiment runs on: sweeps and the reproductions.

:func:`run_local` runs a list of jobs through a picklable function ``call`` in worker
processes and hands each result to ``finish`` in the driver as it arrives (in completion
order). What it takes care of, once for everybody:

* **Warm workers.** While the driver has a single thread the workers are forked from it, so
  they inherit every import and whatever ``warm`` did (a first world, numba's registries) and
  start in milliseconds. Otherwise (a progress bar is drawing, or the pool is rebuilt after a
  crash) a fork could copy a lock another thread holds, so they come from a fork server that
  imported ``preload`` once; its start-up (about a second) is the price of safety. A caller
  that shows progress starts its bar in ``ready``, which is called once the workers exist.
* **Chunks.** A small run costs a few milliseconds, about what handing it to a worker and its
  result back costs the driver, which then competes with the workers for the cores; jobs
  therefore travel in chunks lasting about ``CHUNK_SECONDS`` (timed in the workers), single
  jobs until the first ones are timed, shrinking towards the end so no worker is left with a
  long tail. A bounded window of chunks is in flight (two per worker).
* **Crashes.** If a worker process dies (a segfault, the OOM killer) the pool breaks and every
  chunk in flight is lost with it. ``recover`` may finish the lost jobs whose result was made
  durable before the crash (a sweep's record file, a study's spool line) and returns the rest;
  those are retried one at a time in a new pool. A job in flight at ``MAX_ATTEMPTS`` deaths is
  handed to ``died`` instead of being retried again (once another job has completed, which
  shows the workers themselves can run). If the pool breaks ``MAX_BREAKS`` times in a row with
  no job completing, the workers cannot run at all: :class:`WorkersDied` is raised and nothing
  is handed to ``died``.
* **Refused starts.** A worker's death can race a submit, which then fails before the chunk
  is sent; with no chunk in flight a new pool is made. Such refusals have their own count,
  not the crashes': a fork server killed by the race (CPython's fork server dies on a
  request whose client vanished) keeps refusing until it has exited and is started again,
  so each new pool waits a little longer (``REFUSAL_PAUSE``, doubled), and only
  ``MAX_REFUSALS`` in a row raise :class:`WorkersDied`. Counted with the crashes, one such
  refusal after a run had killed its worker twice stopped a study that could go on.
* **Stopping.** Workers ignore Ctrl-C: the driver gets it, raises the pool's stop flag, waits
  for the jobs running (their results are not handed over) and re-raises. A worker checks the
  flag before each job, so the rest of its chunk and the chunks already queued for the
  workers (``ProcessPoolExecutor`` moves some into its call queue, where they cannot be
  cancelled) start no run: Ctrl-C waits for one job per worker at most, not for another
  round of long runs. An exception raised by ``call`` in a worker is re-raised in the driver
  the same way.

Results never depend on the pool: a job's result is a function of the job alone (its seed is
part of it), whichever worker ran it, in whatever chunk.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import threading
import time
import warnings
from collections import Counter, deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Generic, TypeVar

from swarmex.engine.interrupts import ctrl_c, is_ctrl_c, note
from swarmex.errors import InputError

J = TypeVar("J")
R = TypeVar("R")

CHUNK_MAX = 16  # jobs per pool task at most
CHUNK_SECONDS = 0.1  # what a pool task should last, about
MAX_BREAKS = 3  # pool breaks in a row, no job completing: the workers cannot run at all
MAX_ATTEMPTS = 2  # a job in flight when a worker process died twice is given up on
MAX_REFUSALS = 6  # new pools in a row that take no chunk: no worker process can start
REFUSAL_PAUSE = 0.05  # seconds before the first new pool after a refused one (then doubled)


#: worker processes (or Ray CPUs) a run of many may ask for: more is a typo, not a machine
MAX_WORKERS = 1024
#: local worker processes per core at most: each holds its own copy of a run (~150 MB), and
#: more than a few per core only share the cores (100,000 asked for met the OOM killer)
PROCESSES_PER_CORE = 4


def check_workers(workers: int | None, flag: str = "--workers") -> None:
    """``workers`` is None or 1..:data:`MAX_WORKERS`; else an InputError naming ``flag``."""
    if workers is not None and not 1 <= workers <= MAX_WORKERS:
        raise InputError(f"{flag} must be between 1 and {MAX_WORKERS}, got {workers}")


def local_processes(workers: int) -> int:
    """The worker processes worth forking on this machine for ``workers`` asked for: at most
    :data:`PROCESSES_PER_CORE` per core."""
    return max(1, min(workers, PROCESSES_PER_CORE * (os.cpu_count() or 1)))


class WorkersDied(InputError):
    """The worker processes died ``MAX_BREAKS`` times in a row before finishing any job, or
    ``MAX_REFUSALS`` new pools in a row could not start one."""


#: in a pool worker: the driver's stop flag (a multiprocessing Event), set when it stops
_STOP: Any = None


# ---------------------------------------------------------------------------- in a worker


def init_worker(driver_pid: int | None = None, stop: Any = None) -> None:
    """Prepare a pool process: ignore Ctrl-C (the driver stops us).

    With ``driver_pid``, a watchdog thread ends this process once the driver is gone: a pool
    worker forked by the fork server is not the driver's child, and if the driver is killed
    (SIGKILL, OOM) nothing else would ever tell it to exit. ``stop`` is the driver's stop
    flag: once it is set, :func:`run_chunk` starts no more jobs.
    """
    global _STOP
    _STOP = stop
    with contextlib.suppress(ValueError):  # not the main thread: nothing to do
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the CLI's handler, if forked
    if driver_pid is not None:
        threading.Thread(target=_watch, args=(driver_pid,), daemon=True).start()


def _watch(driver_pid: int, interval: float = 1.0) -> None:
    while True:
        time.sleep(interval)
        try:
            os.kill(driver_pid, 0)
        except ProcessLookupError:
            os._exit(1)
        except PermissionError:  # alive, owned by someone else (cannot happen for our parent)
            pass


def run_chunk(call: Callable[[J], R], jobs: list[J]) -> list[tuple[R, float]]:
    """Several jobs in one hand-over from the driver: each result with its seconds. Once the
    driver's stop flag is set, the jobs not started are left (the driver is stopping and
    wants no more results)."""
    out = []
    for job in jobs:
        if _STOP is not None and _STOP.is_set():
            break
        t0 = time.perf_counter()
        result = call(job)
        out.append((result, time.perf_counter() - t0))
    return out


def warm_numba() -> None:
    """Load numba's code generation registries (a few tenths of a second per process) by one
    tiny cached kernel call, so that workers forked afterwards start with them. Best effort."""
    with contextlib.suppress(Exception):
        import numpy as np

        from swarmex.planning.distance import distance_field
        from swarmex.worlds.grid import GridWorld

        distance_field(GridWorld(np.ones((1, 2), dtype=bool)).graph, 0)


# ---------------------------------------------------------------------------- the driver


class _Slot(Generic[J]):
    """A job and its place in the list (its identity for the pool's bookkeeping)."""

    __slots__ = ("index", "job")

    def __init__(self, index: int, job: J) -> None:
        self.index = index
        self.job = job


def run_local(
    jobs: Sequence[J],
    call: Callable[[J], R],
    workers: int,
    finish: Callable[[J, R], None],
    *,
    recover: Callable[[list[J]], list[J]] | None = None,
    died: Callable[[J], None] | None = None,
    warm: Callable[[], None] | None = None,
    preload: Sequence[str] = (),
    ready: Callable[[], None] | None = None,
) -> None:
    """Run ``call(job)`` for every job in worker processes; ``finish(job, result)`` each.

    ``call`` must be picklable (a module-level function, or an instance of a module-level
    class). ``recover(lost)`` finishes the lost jobs of a broken pool that it can and returns
    the others; ``died(job)`` records a job that kept killing its worker (without it, such a
    job raises :class:`WorkersDied`); ``warm()`` runs in the driver before the workers are
    forked from it; ``preload`` are the modules a fork server imports; ``ready()`` is called
    once, when the workers exist. See the module docstring for the rest.
    """
    queue: deque[_Slot[J]] = deque(_Slot(i, job) for i, job in enumerate(jobs))
    suspects: deque[_Slot[J]] = deque()
    attempts: dict[int, int] = {}
    dead: list[_Slot[J]] = []  # gave up on, handed to died() once the pool is shown to work
    breaks = 0  # pool breaks since the last completed job
    refused = 0  # new pools in a row that failed before any chunk was handed to them
    window = 2 * workers  # chunks in flight: one running and one queued per worker
    timed = [0.0, 0]  # seconds and count of finished jobs, for the chunk size

    def give_up(slots: list[_Slot[J]]) -> None:
        for slot in slots:
            if died is None:
                raise WorkersDied(
                    f"job {slot.index} killed its worker process {MAX_ATTEMPTS} times:"
                    f" {slot.job!r}"
                )
            died(slot.job)
        slots.clear()

    if queue and warm is not None and _forkable():
        warm()
    pool, stop = _pool(workers, preload)
    flying: dict[Future[list[tuple[R, float]]], list[_Slot[J]]] = {}
    try:
        while queue or suspects or flying:
            careful = suspects or any(s.index in attempts for c in flying.values() for s in c)
            while len(flying) < (1 if careful else window) and (suspects or queue):
                from_suspects = bool(suspects)
                if from_suspects:
                    chunk = [suspects.popleft()]
                else:
                    per_job = timed[0] / timed[1] if timed[1] else None
                    size = chunk_size(per_job, len(queue), workers)
                    chunk = [queue.popleft() for _ in range(min(size, len(queue)))]
                try:
                    with _quiet_fork():  # the first submit forks the workers
                        flying[pool.submit(run_chunk, call, [s.job for s in chunk])] = chunk
                except (BrokenProcessPool, OSError, EOFError) as exc:
                    # a worker died while we were handing out work: the chunk was never
                    # sent, so it goes back where it came from; the futures in flight
                    # report the break below (or, with none in flight, a new pool starts).
                    # OSError: the death can race the submit, which then starts a
                    # replacement worker on the pool's already closed pipe ("handle is
                    # closed", CPython's executor before 3.14; seen in a CI run). EOFError
                    # or OSError: the fork server that race killed is still exiting
                    (suspects if from_suspects else queue).extendleft(reversed(chunk))
                    if not flying:
                        refused += 1
                        if refused >= MAX_REFUSALS:
                            raise WorkersDied(
                                f"no worker process could be started ({refused} new pools"
                                f" in a row failed before a run was handed to them: {exc})"
                            ) from exc
                        pool.shutdown(wait=False, cancel_futures=True)
                        time.sleep(REFUSAL_PAUSE * 2 ** (refused - 1))
                        pool, stop = _pool(workers, preload)
                    break
                refused = 0
            if ready is not None and flying:
                ready()  # the workers are forked by now (not after a refused first pool)
                ready = None
            if not flying:
                continue
            done, _ = wait(list(flying), return_when=FIRST_COMPLETED)
            lost: list[_Slot[J]] = []
            for fut in done:
                chunk = flying.pop(fut)
                try:
                    results = fut.result()
                except BrokenProcessPool:
                    lost += chunk
                    continue
                breaks = 0
                give_up(dead)
                for slot, (result, seconds) in zip(chunk, results, strict=True):
                    attempts.pop(slot.index, None)
                    timed[0] += seconds
                    timed[1] += 1
                    finish(slot.job, result)
            if lost:
                for chunk in flying.values():
                    lost += chunk
                flying.clear()
                pool.shutdown(wait=False, cancel_futures=True)
                if recover is not None:
                    left = Counter(id(job) for job in recover([s.job for s in lost]))
                    lost = [s for s in lost if _take(left, id(s.job))]
                breaks += 1
                if breaks >= MAX_BREAKS:
                    raise WorkersDied(
                        f"the worker processes died {breaks} times in a row before finishing"
                        " a run (from a script, run it under `if __name__ == '__main__':`)"
                    )
                for slot in lost:
                    attempts[slot.index] = attempts.get(slot.index, 0) + 1
                    if attempts[slot.index] >= MAX_ATTEMPTS:
                        dead.append(slot)
                    else:
                        suspects.append(slot)
                pool, stop = _pool(workers, preload)
        give_up(dead)  # the last jobs crashed their workers: hand them over now
    finally:
        # a Ctrl-C while the chunks in flight finish (often a second one: terminals and
        # `timeout` signal the whole group) kills the workers instead of breaking into the
        # executor's own bookkeeping, which then hung at exit or raised "release unlocked lock"
        with sigint_deferred(on_signal=lambda: kill_workers(pool)):
            stop.set()  # no queued job starts now (none is left when all is done)
            try:
                pool.shutdown(wait=True, cancel_futures=True)
            except RuntimeError:  # its locks left half-held by a Ctrl-C inside the executor
                kill_workers(pool)


@contextlib.contextmanager
def sigint_deferred(on_signal: Callable[[], None] | None = None) -> Iterator[None]:
    """Let the block finish through Ctrl-C: a SIGINT meanwhile calls ``on_signal`` and is
    raised as KeyboardInterrupt when the block ends. Only the main thread gets signals, so
    elsewhere (or with Ctrl-C not handled by Python) the block simply runs."""
    before = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or not is_ctrl_c(before):
        yield
        return
    got: list[int] = []

    def on_int(signum: int, frame: Any) -> None:
        got.append(signum)
        if before is ctrl_c:  # the command line's Ctrl-C notes its requests (a caller's
            note()  # own Python handler would never clear the note)
        if on_signal is not None:
            on_signal()

    signal.signal(signal.SIGINT, on_int)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)
    if got:
        raise KeyboardInterrupt


def kill_workers(pool: ProcessPoolExecutor) -> None:
    """End the pool's worker processes now (their chunks' results are not wanted); also the
    bench scripts' Ctrl-C (bench/_cli.process_pool)."""
    for proc in list((getattr(pool, "_processes", None) or {}).values()):
        with contextlib.suppress(Exception):
            proc.kill()


def _take(counts: Counter[int], key: int) -> bool:
    if counts[key] > 0:
        counts[key] -= 1
        return True
    return False


def chunk_size(seconds_per_job: float | None, queued: int, workers: int) -> int:
    """Jobs per pool task: enough to make the hand-over cheap, few enough to stay responsive.

    Chunks last about ``CHUNK_SECONDS`` (the hand-over stays cheap and the bar moves), shrink
    towards the end (a quarter of a fair share) so no worker is left with a long tail, and
    are single jobs until the first results tell how long a job takes.
    """
    if seconds_per_job is None:
        return 1
    by_time = int(CHUNK_SECONDS / max(seconds_per_job, 1e-4))
    return max(1, min(CHUNK_MAX, by_time, queued // (4 * workers)))


def _pool(workers: int, preload: Sequence[str]) -> tuple[ProcessPoolExecutor, Any]:
    """Workers forked from this process when it has one thread, else from a fork server
    that imported ``preload`` (see the module docstring); and their stop flag."""
    ctx: Any
    if _forkable():
        ctx = multiprocessing.get_context("fork")
    else:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(["swarmex.experiments.pool", *preload])
    stop = ctx.Event()
    pool = ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=init_worker,
        initargs=(os.getpid(), stop),
    )
    return pool, stop


def _forkable() -> bool:
    """Whether forking this process is safe: no other Python thread (a progress bar, a
    server) could hold a lock the child inherits.

    The only other threads are then native ones: OpenBLAS's idle server threads (numpy's and
    scipy's), which OpenBLAS quiesces around a fork itself. Python 3.12+ still warns about any
    second OS thread (DeprecationWarning); :func:`_quiet_fork` silences exactly that warning
    where we fork knowingly.
    """
    return "fork" in multiprocessing.get_all_start_methods() and threading.active_count() == 1


@contextlib.contextmanager
def _quiet_fork() -> Iterator[None]:
    with warnings.catch_warnings():
        warnings.filterwarnings(
            "ignore", message=r".*multi-threaded, use of fork\(\)", category=DeprecationWarning
        )
        yield


__all__ = [
    "CHUNK_MAX",
    "CHUNK_SECONDS",
    "MAX_ATTEMPTS",
    "MAX_BREAKS",
    "MAX_REFUSALS",
    "REFUSAL_PAUSE",
    "WorkersDied",
    "chunk_size",
    "init_worker",
    "run_chunk",
    "run_local",
    "sigint_deferred",
    "warm_numba",
]
