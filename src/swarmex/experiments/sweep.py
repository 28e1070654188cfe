"""Sweeps: every run of a spec's product, in parallel, resumable, into one Parquet table.

The sweep folder (``--out DIR``) holds::

    DIR/runs/<run id>.json         the result record of each finished run (DESIGN.md schema)
    DIR/runs/<run id>.error.json   what a failed run said (its mission, params, error, traceback)
    DIR/journal.jsonl              one line per finished run: its row-sized outcome
    DIR/results.parquet            one row per finished run of the spec, in product order

A run counts as finished when its record (or error file) exists and is not damaged (a file
left empty or cut short is removed with a warning and its run runs again); both are written
with an atomic rename the moment the run ends, so Ctrl-C, a killed driver or a crashed
worker loses no finished run, and running the same command again resumes: it runs only what
is missing (and, with ``retry_failed``, the failures). The journal spares a resumed sweep
from re-reading every record for its row; a record without a journal line (the driver died
between the two) is read back instead. ``results.parquet`` is rebuilt from the outcomes at
the end of every call, interrupted or not.

Backends, all giving the same records and table for the same spec (each run is seeded by its
own ``--seed``; nothing depends on which worker ran it or when):

* ``serial`` — in this process; the reference, and a debugging aid;
* ``local`` — the local process pool of :mod:`swarmex.experiments.pool` (shared with the
  reproductions): forked from the warmed-up driver while it has a single thread (else from a
  fork server that imported swarmex once); small runs go to the workers in chunks, so the
  driver's share of the cores stays small;
* ``ray`` — long-lived Ray actors, locally (``ray.init()``) or on a cluster by address.

The driver keeps only outcomes (a few scalars per run) and a bounded window of tasks in
flight, so its memory does not grow with the records' size.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from swarmex.engine.atomic import atomic_path, write_atomic
from swarmex.engine.interrupts import clear as clear_request
from swarmex.engine.interrupts import raise_if_requested
from swarmex.errors import InputError, require
from swarmex.experiments.pool import (
    MAX_ATTEMPTS,
    check_workers,
    local_processes,
    run_local,
    sigint_deferred,
)
from swarmex.experiments.progress import Journal, read_journal
from swarmex.experiments.scenario import OptionShape
from swarmex.experiments.sweep_spec import RunSpec, SweepSpec
from swarmex.experiments.sweep_worker import (
    InFolder,
    Outcome,
    Task,
    outcome_from_record,
    run_task,
    warm_up,
)

BACKENDS = ("local", "ray", "serial")
RESULTS = "results.parquet"
JOURNAL = "journal.jsonl"
METADATA_KEY = b"swarmex.sweep"
RAY_CHUNK = 8  # runs per Ray actor call at most

OnOutcome = Callable[[Outcome], None]


@dataclass
class SweepResult:
    out_dir: Path
    total: int  # runs in the spec
    skipped: int  # already finished before this call
    ran: int  # finished during this call
    failed: int  # failed runs among all finished ones
    table: Path
    interrupted: bool = False


# ---------------------------------------------------------------------------- the folder


class SweepStore:
    """The sweep folder: records, error files, the journal and the table (see module doc)."""

    def __init__(self, out_dir: str | Path, warn: Callable[[str], None] | None = None) -> None:
        self.dir = Path(out_dir)
        self.warn = warn if warn is not None else _warn
        self.runs_dir = self.dir / "runs"
        try:
            self.runs_dir.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"--out: cannot create {self.runs_dir}: {exc.strerror}") from None
        if not os.access(self.runs_dir, os.W_OK):
            raise InputError(f"--out: {self.runs_dir} is not writable")
        self._journal = Journal(self.dir / JOURNAL, key="run_id")

    def record_path(self, run_id: str) -> Path:
        return self.runs_dir / f"{run_id}.json"

    def error_path(self, run_id: str) -> Path:
        return self.runs_dir / f"{run_id}.error.json"

    def finished(self, runs: list[RunSpec], retry_failed: bool = False) -> dict[str, Outcome]:
        """Outcomes of the runs already done (from the journal, else from their files).

        A record or error file that cannot be read (0 bytes or cut short: the renames are not
        fsynced, so a power loss can leave one) does not count: it is removed with a warning
        naming it, and its run is run again. (A record the journal knows is only checked for
        being empty, so that resuming does not read every record.)"""
        journal = self._read_journal()
        done: dict[str, Outcome] = {}
        for run in runs:
            known: Outcome | None = journal.get(run.run_id)
            size = _size(self.record_path(run.run_id))
            if size is not None:
                if known is None or not known.ok or size == 0:
                    known = self._from_record(run)
            elif self.error_path(run.run_id).exists():
                if retry_failed:
                    self.error_path(run.run_id).unlink()
                    continue
                if known is None or known.ok:
                    known = self._from_error(run)
            else:
                continue
            if known is None:  # unreadable: run it again
                continue
            known.index = run.index
            done[run.run_id] = known
        return done

    def _read_journal(self) -> dict[str, Outcome]:
        """Outcomes by run id; a line cut short by a crash is skipped (its run is re-read
        from its record, or run again)."""
        out: dict[str, Outcome] = {}
        for run_id, row in read_journal(self._journal.path, key="run_id").items():
            try:
                out[run_id] = Outcome.from_json(row)
            except TypeError:  # a row missing fields: treat it like a torn line
                continue
        return out

    def _from_record(self, run: RunSpec) -> Outcome | None:
        data = self._read(self.record_path(run.run_id))
        return None if data is None else outcome_from_record(run.index, run.run_id, data)

    def _from_error(self, run: RunSpec) -> Outcome | None:
        data = self._read(self.error_path(run.run_id))
        return None if data is None else Outcome(run.index, run.run_id, ok=False,
                                                 error=data.get("error"))

    def _read(self, path: Path) -> dict[str, Any] | None:
        """A record or error file as JSON; None (and the file removed, with a warning) when
        it is damaged, so that its run counts as not finished and runs again."""
        try:
            text = path.read_text(encoding="utf-8")
            data = json.loads(text) if text.strip() else None
            why = "empty" if data is None else "not a JSON object"
        except OSError as exc:  # unreadable now (permissions, a network file system): the
            # record may be whole, so it is not removed; the sweep stops and says which
            raise InputError(f"{path}: cannot read this finished run's file"
                             f" ({exc.strerror or type(exc).__name__})") from None
        except ValueError as exc:  # cut short, or not JSON (UnicodeDecodeError included)
            data, why = None, f"not JSON: {exc}"
        if isinstance(data, dict):
            return data
        self.warn(f"{path}: unreadable ({why}); its run is run again")
        with contextlib.suppress(OSError):  # the new run's atomic rename replaces it anyway
            path.unlink()
        return None

    def save(self, outcome: Outcome, run: RunSpec, task: Task) -> None:
        """Make a finished run durable: its record or error file, then its journal line."""
        if outcome.record_text is not None:
            write_atomic(self.record_path(run.run_id), outcome.record_text)
            outcome.record_text = None  # the driver keeps scalars only
        if outcome.ok:
            self.error_path(run.run_id).unlink(missing_ok=True)
        else:
            info = {
                "run": run.run_id,
                "mission": task.mission,
                "params": run.params,
                "seed": run.seed,
                "error": outcome.error,
                "traceback": outcome.detail,
            }
            write_atomic(self.error_path(run.run_id), json.dumps(info, indent=1))
            outcome.detail = None
        self._journal.add(outcome.to_json())

    def close(self) -> None:
        self._journal.close()


def _size(path: Path) -> int | None:
    try:
        return path.stat().st_size
    except FileNotFoundError:
        return None


def _warn(text: str) -> None:
    import warnings

    warnings.warn(text, UserWarning, stacklevel=2)


# ---------------------------------------------------------------------------- the table


def build_table(spec: SweepSpec, runs: list[RunSpec], outcomes: dict[str, Outcome]):
    """One row per finished run in product order: params, seed, outcome, metrics, error."""
    import pyarrow as pa

    rows = [(run, outcomes[run.run_id]) for run in runs if run.run_id in outcomes]
    params = spec.param_names
    columns: dict[str, Any] = {"run": pa.array([r.run_id for r, _ in rows], pa.string())}
    for name in params:
        columns[name] = _column([r.params[name] for r, _ in rows])
    columns["seed"] = pa.array([r.seed for r, _ in rows], pa.int64())
    columns["complete"] = pa.array([o.complete for _, o in rows], pa.bool_())
    columns["makespan"] = pa.array([o.makespan for _, o in rows], pa.float64())
    columns["time_unit"] = pa.array([o.time_unit for _, o in rows], pa.string())
    metric_names: list[str] = []
    for _, o in rows:  # first-seen order: stable for a given spec
        metric_names += [k for k in o.metrics if k not in metric_names]
    entries, tables = count_entries(spec.mission)
    metric_names += [k for k in entries if k not in metric_names]  # the same columns always
    metric_columns = []
    for key in metric_names:
        taken = key in columns or key in ("wall_seconds", "error")
        name = f"metrics.{key}" if taken else key
        counted = key.startswith(tables)  # every declared entry is in a table
        columns[name] = _column([_metric(o, key, counted) for _, o in rows])
        metric_columns.append(name)
    columns["wall_seconds"] = pa.array([o.wall_seconds for _, o in rows], pa.float64())
    columns["error"] = pa.array([o.error for _, o in rows], pa.string())
    meta = {
        "mission": spec.mission,
        "command": spec.command,
        "spec": str(spec.path),
        "params": params,
        "axes": [k for k, v in spec.axes.items() if len(v) > 1],
        "metrics": ["makespan", "complete", *metric_columns],
        "runs": len(runs),
    }
    table = pa.table(columns)
    return table.replace_schema_metadata({METADATA_KEY: json.dumps(meta).encode()})


def count_entries(mission: str) -> tuple[list[str], tuple[str, ...]]:
    """The sweep columns of the mission's tables of counts (``MetricInfo.counts``): their
    declared entries (``messages_by_kind.RERR.messages``), and the tables' prefixes
    (``messages_by_kind.``) for entries not declared in advance. A record leaves out an entry
    that counted nothing, so such a column is 0 for every successful run without it."""
    from swarmex.missions.registry import get

    try:
        declared = get(mission).team_metrics()
    except InputError:  # a plugin mission no longer installed: no table is known
        return [], ()
    tables = {name: info for name, info in declared.items() if info.counts}
    entries = [f"{name}.{key}" for name, info in tables.items() for key in info.keys]
    return entries, tuple(f"{name}." for name in tables)


def _metric(outcome: Outcome, key: str, counted: bool) -> Any:
    """A run's value of a metric column: 0 for an entry of a table of counts that a finished
    run's record left out (it counted nothing); None when the run failed or the metric is
    not a count (an unfinished run's time is unknown, not 0)."""
    if key in outcome.metrics:
        return outcome.metrics[key]
    return 0 if counted and outcome.ok else None


def _column(values: list[Any]):
    """An Arrow column of one type: bools, ints, floats, else text (as the CLI spells it)."""
    import pyarrow as pa

    from swarmex.experiments.scenario import as_text

    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return pa.array(values, pa.bool_())
    numeric = all(isinstance(v, int | float) and not isinstance(v, bool) for v in present)
    if present and numeric:
        if all(isinstance(v, int) for v in present):
            return pa.array(values, pa.int64())
        return pa.array([None if v is None else float(v) for v in values], pa.float64())
    return pa.array([None if v is None else as_text(v) for v in values], pa.string())


def write_table(table, path: Path) -> Path:
    import pyarrow.parquet as pq

    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)
    return path


def read_results(out_dir: str | Path):
    """The sweep table of DIR and its metadata (params, axes, metrics)."""
    import pyarrow.parquet as pq

    path = Path(out_dir)
    if path.is_dir():
        path = path / RESULTS
    if not path.exists():
        raise InputError(f"no sweep results at {path} (run swarmex sweep first)")
    try:
        table = pq.read_table(path)
    except Exception as exc:  # pyarrow raises several types for a damaged file
        raise InputError(f"{path}: not a readable Parquet file: {exc}") from None
    return table, table_meta(table)


def table_meta(table: Any) -> dict[str, Any]:
    """A sweep table's metadata (mission, params, axes, metrics), from its schema.

    A table whose schema lost it (written back through pandas, or rebuilt by another tool)
    still has :func:`build_table`'s layout: the parameters are the columns between ``run``
    and ``seed``, and the axes those of them with more than one value. Without this the
    comparisons and the pooling note saw no axis at all ("it varies: none")."""
    raw = (table.schema.metadata or {}).get(METADATA_KEY)
    meta: dict[str, Any] = json.loads(raw) if raw else {}
    names = list(table.column_names)
    if "axes" not in meta and "run" in names and "seed" in names:
        params = names[names.index("run") + 1 : names.index("seed")]
        meta.setdefault("params", params)
        meta["axes"] = [p for p in params if len(table.column(p).unique()) > 1]
    return meta


# ---------------------------------------------------------------------------- running


def check_values(spec: SweepSpec, runs: list[dict[str, Any]]) -> None:
    """Parse every distinct value of every parameter with its option's parser, before any
    run: a value the option refuses (``agents = "three"``, a negative ``loss``) would fail
    every run it is in the same way, one error row and file each, after the sweep started.
    Rules that tie parameters together (``Params.check``) and the world's checks stay per
    run: a bad combination of good values is a failed row, as docs/sweeps.md says."""
    from swarmex.missions.registry import get

    opts = get(spec.mission).params_type.options()
    seen: set[tuple[str, str]] = set()
    for values in runs:
        for name, value in values.items():
            info = opts.get(name)
            key = (name, repr(value))
            if info is None or value is None or key in seen:
                continue
            seen.add(key)
            try:
                info.parse(value, info.flag)
            except InputError as exc:
                raise InputError(f"{spec.path}: {exc}") from None


def check_backend(
    backend: str, workers: int | None, ray_address: str | None = None, *, python: bool = False
) -> None:
    """The backend options, checked before anything runs; errors name the command line's
    options, or with ``python`` the keywords of :func:`swarmex.sweep`."""

    def opt(name: str, value: str | None = None) -> str:
        if python:
            return name.replace("-", "_") + ("" if value is None else f"={value!r}")
        return f"--{name}" + ("" if value is None else f" {value}")

    if backend not in BACKENDS:
        raise InputError(f"{opt('backend')} must be one of {', '.join(BACKENDS)}, got {backend!r}")
    check_workers(workers, opt("workers"))
    # an option the backend ignores was silently dropped: say so instead
    if workers is not None and backend == "serial":
        either = "backend='local' or 'ray'" if python else "--backend local or ray"
        raise InputError(f"{opt('workers')} is for {either} (serial runs in this process)")
    if ray_address is not None and backend != "ray":
        raise InputError(f"{opt('ray-address')} is for {opt('backend', 'ray')}, not {backend}")


def run_sweep(
    spec: SweepSpec,
    shapes: dict[str, OptionShape],
    out_dir: str | Path,
    backend: str = "local",
    workers: int | None = None,
    ray_address: str | None = None,
    retry_failed: bool = False,
    on_start: Callable[[int, int], None] | None = None,
    on_outcome: OnOutcome | None = None,
    on_warning: Callable[[str], None] | None = None,
) -> SweepResult:
    """Run every unfinished run of ``spec`` and write DIR/results.parquet.

    ``shapes`` are the mission's option shapes (:func:`~swarmex.experiments.scenario.
    mission_shapes`); every run's parameters are built and checked before anything runs, so a
    misspelt option fails at once.
    ``on_start(total, already_finished)`` and ``on_outcome(outcome)`` drive a progress display;
    an exception raised by ``on_outcome`` (Ctrl-C) stops the sweep after saving what finished.
    ``on_warning(text)`` says a one-line warning (a damaged record, run again); by default a
    UserWarning.
    """
    check_backend(backend, workers, ray_address)
    if backend == "ray":
        _import_ray()  # fail now, with one line, not after the progress bar appears
        ray_address = ray_address or os.environ.get("RAY_ADDRESS") or None
        if ray_address in ("auto", "local"):  # Ray's own words for "find it" / "start one"
            ray_address = None
        if ray_address:
            _check_reachable(ray_address)
    runs = spec.runs()
    by_id = {r.run_id: r for r in runs}
    tasks = {r.run_id: Task(r.index, r.run_id, spec.mission, spec.values(r, shapes)) for r in runs}
    check_values(spec, [t.values for t in tasks.values()])
    store = SweepStore(out_dir, on_warning)
    clear_request()  # a request an earlier, finished call left behind is not this one's
    outcomes = store.finished(runs, retry_failed)
    skipped = len(outcomes)
    pending = [tasks[r.run_id] for r in runs if r.run_id not in outcomes]
    started = False

    def start() -> None:  # the local backend calls it once its workers are forked
        nonlocal started
        if not started and on_start is not None:
            on_start(len(runs), skipped)
        started = True

    if not pending or backend != "local":
        start()

    def finish(outcome: Outcome) -> None:
        store.save(outcome, by_id[outcome.run_id], tasks[outcome.run_id])
        outcomes[outcome.run_id] = outcome
        if on_outcome is not None:
            on_outcome(outcome)
        raise_if_requested()  # saved; a Ctrl-C a finalizer swallowed stops the rest

    interrupted = False
    try:
        if pending:
            if backend == "serial":
                _serial(pending, store.runs_dir, finish)
            elif backend == "local":
                _local(
                    pending,
                    min(local_processes(workers or os.cpu_count() or 1), len(pending)),
                    spec.mission,
                    store.runs_dir,
                    finish,
                    ready=start,
                )
            else:
                _ray(pending, workers, ray_address, finish)
    except KeyboardInterrupt:
        interrupted = True
        raise
    finally:
        with sigint_deferred():  # a second Ctrl-C must not cost the table of what finished
            store.close()
            if interrupted:  # records the workers wrote whose outcomes never reached us
                for run_id, outcome in store.finished(runs).items():
                    outcomes.setdefault(run_id, outcome)
            table = write_table(build_table(spec, runs, outcomes), store.dir / RESULTS)
    failed = sum(1 for o in outcomes.values() if not o.ok)
    return SweepResult(
        store.dir, len(runs), skipped, len(outcomes) - skipped, failed, table, interrupted
    )


def _serial(tasks: Iterable[Task], runs_dir: Path, finish: OnOutcome) -> None:
    for task in tasks:  # finish() asks for a swallowed Ctrl-C between runs
        outcome = run_task(task, str(runs_dir))
        finish(outcome)


def _local(
    tasks: list[Task],
    workers: int,
    mission: str,
    runs_dir: Path,
    finish: OnOutcome,
    runner: Callable[[Task, str | None], Outcome] = run_task,
    ready: Callable[[], None] | None = None,
) -> None:
    """The local pool (:func:`~swarmex.experiments.pool.run_local`) over the tasks.

    Workers write each record into ``runs_dir`` themselves, so a worker that dies loses only
    the runs it had not finished: the records of its chunk written before the crash are read
    back (``_keep_recorded``). A task that keeps killing its worker is recorded as failed.
    (``runner`` is the worker function; tests pass one that crashes. ``ready`` is called once
    the workers exist, so a progress bar's thread starts after the fork.)
    """
    run_local(
        tasks,
        InFolder(runner, str(runs_dir)),
        workers,
        lambda _task, outcome: finish(outcome),
        recover=lambda lost: _keep_recorded(lost, runs_dir, finish),
        died=lambda task: finish(_died(task)),
        warm=lambda: warm_up(tasks[0]),
        preload=[
            "swarmex.cli",
            "swarmex.experiments.sweep_worker",
            "swarmex.engine.record",
            "swarmex.worlds",
            f"swarmex.missions.{mission}",
        ],
        ready=ready,
    )


def _keep_recorded(lost: list[Task], runs_dir: Path, finish: OnOutcome) -> list[Task]:
    """Finish the lost tasks whose record a worker wrote before its pool broke; return the rest."""
    rest = []
    for task in lost:
        path = Path(runs_dir) / f"{task.run_id}.json"
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            rest.append(task)
            continue
        finish(outcome_from_record(task.index, task.run_id, record))
    return rest


def _died(task: Task) -> Outcome:
    return Outcome(
        task.index,
        task.run_id,
        ok=False,
        error=f"the worker process died while running it ({MAX_ATTEMPTS} attempts)",
    )


def _import_ray() -> Any:
    require("ray", "ray", "--backend ray")
    import ray

    return ray


def _check_reachable(address: str, timeout: float = 5.0) -> None:
    """Fail in one line when nothing listens at a Ray address (``ray.init`` would retry for
    minutes, printing warnings, before giving up)."""
    import socket

    text = address.removeprefix("ray://")
    host, _, port = text.rpartition(":")
    if not host or not port.isdigit():
        raise InputError(f"--ray-address must be HOST:PORT, got {address!r}")
    try:
        with socket.create_connection((host, int(port)), timeout=timeout):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InputError(
            f"--ray-address {address}: no Ray cluster answers there ({reason})"
        ) from None


def _ray(tasks: list[Task], workers: int | None, address: str | None, finish: OnOutcome) -> None:
    """Long-lived Ray actors, two chunks of tasks in flight each; records come back as text.

    Chunks shrink towards the end (at most a quarter of a fair share per actor) so the last
    actors do not wait for one long chunk. If an actor dies, the runs of its chunk are
    recorded as failed (``--retry-failed`` runs them again) and a new actor replaces it.
    """
    ray = _import_ray()
    from swarmex.experiments.sweep_worker import RayWorker

    started = not ray.is_initialized()
    if started:
        kwargs: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False}
        if address:
            kwargs["address"] = address
        elif workers:
            kwargs["num_cpus"] = workers
        try:
            ray.init(**kwargs)
        except (ConnectionError, ValueError, RuntimeError) as exc:
            where = f"a Ray cluster at {address}" if address else "a local Ray"
            reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise InputError(f"--backend ray: cannot start or join {where}: {reason}") from None
    try:
        n = workers or max(1, int(ray.cluster_resources().get("CPU", 1)))
        actor_cls = ray.remote(num_cpus=1)(RayWorker)
        actors = [actor_cls.remote() for _ in range(n)]
        queue = deque(tasks)
        flying: dict[Any, tuple[Any, list[Task]]] = {}
        replaced: dict[int, Any] = {}
        idle = deque(actors * 2)  # two slots per actor: one running, one queued
        while queue or flying:
            while idle and queue:
                size = max(1, min(RAY_CHUNK, len(queue) // (4 * n)))
                chunk = [queue.popleft() for _ in range(min(size, len(queue)))]
                actor = idle.popleft()
                flying[actor.run.remote(chunk)] = (actor, chunk)
            done, _ = ray.wait(list(flying), num_returns=1)
            for ref in done:
                actor, chunk = flying.pop(ref)
                try:
                    outcomes = ray.get(ref)
                except ray.exceptions.RayError as exc:  # the actor died: record, replace it
                    outcomes = [
                        Outcome(t.index, t.run_id, ok=False, error=f"ray: {exc}") for t in chunk
                    ]
                    dead, actor = actor, replaced.get(id(actor))
                    if actor is None:  # one replacement per dead actor, in all its slots
                        actor = replaced[id(dead)] = actor_cls.remote()
                        idle = deque(actor if a is dead else a for a in idle)
                idle.append(actor)
                for outcome in outcomes:
                    finish(outcome)
    finally:
        if started:
            ray.shutdown()
