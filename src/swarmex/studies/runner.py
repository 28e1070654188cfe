"""The one runner of every reproduction: a study's jobs, in worker processes, resumable.

A study describes its runs as jobs (any picklable value: a dict, a dataclass) and one run as
a picklable module-level function ``call(job) -> result``; :func:`run_jobs` does the rest,
the same way for every study:

* **the pool** — the sweeps' local pool (:func:`swarmex.experiments.pool.run_local`): workers
  forked warm from the driver (or from a fork server), small runs in chunks, a crashed worker
  costing only what it had not finished; with ``workers=1`` the runs happen in this process;
* **the store** — every finished run is saved at once in the study's store (a
  :class:`~swarmex.experiments.progress.Journal`, one JSON line per run, or a
  :class:`~swarmex.experiments.runstore.RunStore`), and jobs whose key is already there are
  not run again: an interrupted reproduction resumes where it stopped;
* **the progress bar** — :func:`~swarmex.experiments.progress.runs_progress`, started once
  the workers exist (so they can be forked from a single-threaded driver);
* **the results** — one per job, in the jobs' order, whichever worker ran it and whether it
  ran now or before (jobs with the same key share one run).

How nothing finished is lost: a worker also appends each result to its own spool file
(``.<store name>.spool/<pid>.jsonl`` beside the store) before handing it back. If a worker
dies, the finished runs of its chunk are taken from the spool instead of being run again; if
the driver is stopped (Ctrl-C) or killed, the results still in flight are in the spool and
are folded into the store at the end of this call or at the start of the next one. The
spool is deleted once folded, so a finished reproduction leaves only its store.

A store's results must be JSON (its lines are JSON); jobs without a store (pictures, whose
results hold arrays) are run the same way and simply not kept.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any, Generic, Protocol, TypeVar

from rich.console import Console

from swarmex.engine.interrupts import clear as clear_request
from swarmex.engine.interrupts import raise_if_requested
from swarmex.experiments.pool import local_processes, run_local, warm_numba
from swarmex.experiments.progress import runs_progress

J = TypeVar("J")
R = TypeVar("R")


class Store(Protocol):
    """Where a study keeps its finished runs: each result (a JSON-ready dict) names its key."""

    @property
    def path(self) -> Path: ...

    def get(self, key: Any) -> Any | None: ...

    def add(self, result: Any) -> None: ...


@dataclass
class Runs(Generic[R]):
    """What :func:`run_jobs` did: the results, one per job in job order, and how many runs
    it executed now and how many it found in the store."""

    results: list[R]
    ran: int
    reused: int


def run_jobs(
    jobs: Sequence[J],
    call: Callable[[J], R],
    key: Callable[[J], str],
    *,
    store: Store | None = None,
    workers: int = 1,
    label: str = "runs",
    console: Console | None = None,
    show: bool = True,
    describe: Callable[[J], str] | None = None,
    on_result: Callable[[J, R], None] | None = None,
    warm: Callable[[], None] | None = None,
) -> Runs[R]:
    """Run every job whose key is not in ``store``; return every job's result in job order.

    ``call`` runs one job (in a worker process when ``workers`` > 1: a picklable
    module-level function); ``key(job)`` is the job's identity in the store and must be the
    key its result is stored under. Jobs run in the order given. ``label`` names the progress
    bar (drawn on ``console``, hidden with ``show=False``), ``describe(job)`` adds the last
    finished job to it, and ``on_result(job, result)`` is called in the driver as each run
    finishes. ``warm()`` runs in the driver before the workers are forked from it (numba's
    registries are always loaded). An exception raised by a run stops the reproduction after
    saving every run that finished (see the module docstring).
    """
    unique: dict[str, J] = {}
    for job in jobs:
        unique.setdefault(key(job), job)
    spool = _spool_dir(store) if store is not None else None
    if spool is not None and store is not None:
        _fold(spool, store)  # a previous driver was killed with results in flight
    results: dict[str, Any] = {}
    if store is not None:
        for k in unique:
            found = store.get(k)
            if found is not None:
                results[k] = found
    reused = len(results)
    pending = [(k, job) for k, job in unique.items() if k not in results]
    clear_request()  # a request an earlier, finished call left behind is not this one's
    workers = max(1, min(local_processes(workers), len(pending)))  # no idle forks
    bar = runs_progress(label, console, disable=not show, detail=describe is not None)
    task = bar.add_task("", total=len(unique), completed=reused)
    ran = 0

    def finish(item: tuple[str, J], result: R) -> None:
        nonlocal ran
        k, job = item
        if store is not None:
            store.add(result)
        results[k] = result
        ran += 1
        bar.advance(task)
        if describe is not None:
            bar.update(task, description=describe(job))
        if on_result is not None:
            on_result(job, result)
        raise_if_requested()  # kept; a Ctrl-C a finalizer swallowed stops the rest

    try:
        with _bar_stops(bar):
            if workers == 1:
                bar.start()
                for item in pending:  # finish() asks for a swallowed Ctrl-C
                    finish(item, call(item[1]))
            elif pending:

                def ready() -> None:
                    bar.start()

                def recover(lost: list[tuple[str, J]]) -> list[tuple[str, J]]:
                    spooled = _read_spool(spool) if spool is not None else {}
                    rest = []
                    for item in lost:
                        if item[0] in spooled and item[0] not in results:
                            finish(item, spooled[item[0]])
                        else:
                            rest.append(item)
                    return rest

                def warm_up() -> None:
                    if warm is not None:
                        warm()
                    warm_numba()

                if spool is not None:
                    spool.mkdir(parents=True, exist_ok=True)
                run_local(
                    pending,
                    Spooled(call, None if spool is None else str(spool)),
                    workers,
                    finish,
                    recover=recover,
                    warm=warm_up,
                    preload=["swarmex.studies.runner", getattr(call, "__module__", "swarmex")],
                    ready=ready,
                )
    finally:
        if spool is not None and store is not None:
            _fold(spool, store)  # results that finished while the driver was stopping
    return Runs([results[key(job)] for job in jobs], ran, reused)


@contextlib.contextmanager
def _bar_stops(bar: Any) -> Iterator[None]:
    try:
        yield
    finally:
        if bar.live.is_started:
            bar.stop()


# ---------------------------------------------------------------------------- the spool


class Spooled(Generic[J, R]):
    """The pool's job function: run one ``(key, job)`` and, with a spool folder, append
    ``[key, result]`` to this worker's spool file before handing the result back."""

    def __init__(self, call: Callable[[J], R], spool: str | None) -> None:
        self.call = call
        self.spool = spool

    def __call__(self, item: tuple[str, J]) -> R:
        k, job = item
        result = self.call(job)
        if self.spool is not None:
            fh = _spool_file(self.spool)
            fh.write(json.dumps([k, result]) + "\n")
            fh.flush()
        return result


_SPOOL_FILES: dict[str, IO[str]] = {}  # in a worker: its open spool file per folder


def _spool_file(folder: str) -> IO[str]:
    fh = _SPOOL_FILES.get(folder)
    if fh is None:
        fh = _SPOOL_FILES[folder] = open(  # noqa: SIM115 (kept open for the worker's life)
            os.path.join(folder, f"{os.getpid()}.jsonl"), "a", encoding="utf-8"
        )
    return fh


def _spool_dir(store: Store) -> Path:
    path = Path(store.path)
    return path.with_name(f".{path.name}.spool")


def _read_spool(spool: Path) -> dict[str, Any]:
    """Results by key in every spool file; a torn last line (a killed worker) is skipped."""
    out: dict[str, Any] = {}
    if not spool.is_dir():
        return out
    for path in sorted(spool.glob("*.jsonl")):
        for line in path.read_text(encoding="utf-8").splitlines():
            try:
                k, result = json.loads(line)
            except (ValueError, TypeError):
                continue
            out[k] = result
    return out


def _fold(spool: Path, store: Store) -> None:
    """Move the spooled results the store lacks into it, then delete the spool."""
    if not spool.is_dir():
        return
    for k, result in _read_spool(spool).items():
        if store.get(k) is None:
            store.add(result)
    shutil.rmtree(spool, ignore_errors=True)


__all__ = ["Runs", "Spooled", "Store", "run_jobs"]
