"""The worker side of a sweep: run one mission command in this process, return a small row.

Why in-process: starting a Python interpreter and importing swarmex costs more than a small run
itself, so a worker is a long-lived process that imported swarmex once and calls the mission's
command object directly, exactly as ``swarmex run`` does (the command parses, validates and
writes the record; the sweep never re-implements a mission's options). The command's Rich
summary is switched off in workers (it would be rendered and thrown away for every run), and
the record is written to a scratch file on a RAM disk when there is one, then moved into the
sweep folder with an atomic rename.

What goes back to the driver is an :class:`Outcome`: the scalars of the record (complete,
makespan, the totals in ``metrics``), or the error. Trajectories never cross the process
boundary, which is what keeps the driver's memory flat however many runs there are (the Ray
backend is the exception: its workers may be on other machines, so they hand the record text
back and the driver writes it).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import signal
import tempfile
import threading
import time
import traceback
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from swarmex.errors import InputError


@dataclass(frozen=True)
class Task:
    index: int
    run_id: str
    command: str  # "traverse"
    argv: list[str]  # the command's options, without --json


@dataclass
class Outcome:
    index: int
    run_id: str
    ok: bool
    complete: bool | None = None
    makespan: float | None = None
    time_unit: str | None = None
    wall_seconds: float | None = None
    metrics: dict[str, Any] = field(default_factory=dict)
    error: str | None = None
    detail: str | None = None  # a traceback, for errors that are bugs rather than bad input
    record_text: str | None = None  # only when the driver must write the record itself

    def to_json(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("record_text")
        return d

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> Outcome:
        names = cls.__dataclass_fields__
        return cls(**{k: v for k, v in d.items() if k in names})


_COMMANDS: dict[str, Any] = {}
_SCRATCH: Path | None = None


def init_worker(driver_pid: int | None = None) -> None:
    """Prepare a pool process: ignore Ctrl-C (the driver stops us), silence the CLI's output.

    With ``driver_pid``, a watchdog thread ends this process once the driver is gone: a pool
    worker forked by the fork server is not the driver's child, and if the driver is killed
    (SIGKILL, OOM) nothing else would ever tell it to exit.
    """
    with contextlib.suppress(ValueError):  # not the main thread: nothing to do
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the CLI's handler, if forked
    _silence()  # for the life of the process
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


@contextlib.contextmanager
def quiet_cli() -> Iterator[None]:
    """Make the commands' Rich consoles skip their output (rendering it is most of the cost).

    Restored on exit, so the serial backend can use it around each run inside the CLI's own
    process and still print its summary afterwards.
    """
    saved = _silence()
    try:
        yield
    finally:
        for c, old in saved:
            if old is None:
                del c.print
            else:
                c.print = old  # type: ignore[method-assign]


def _silence() -> list[tuple[Any, Any]]:
    """Replace the shared consoles' ``print``; returns what was there, to restore it."""
    from swarmex.cli.app import console, err_console

    saved = [(c, c.__dict__.get("print")) for c in (console, err_console)]
    for c, _ in saved:
        c.print = _silent  # type: ignore[method-assign]
    return saved


def _silent(*_args: Any, **_kwargs: Any) -> None:
    return None


def _command(name: str) -> Any:
    """The Click command of ``swarmex NAME``, built once per process (Typer is slow at it)."""
    if name not in _COMMANDS:
        import typer

        from swarmex.cli import app

        group = typer.main.get_command(app)
        _COMMANDS.update(group.commands)
    if name not in _COMMANDS:
        raise InputError(f"this installation has no 'swarmex {name}' command")
    return _COMMANDS[name]


def _scratch() -> Path:
    """This process's scratch file (named by pid: a forked worker must not share its parent's)."""
    global _SCRATCH
    if _SCRATCH is None or not _SCRATCH.name.endswith(f"-{os.getpid()}.json"):
        shm = Path("/dev/shm")
        base = shm if shm.is_dir() and os.access(shm, os.W_OK) else Path(tempfile.gettempdir())
        _SCRATCH = base / f"swarmex-sweep-{os.getpid()}.json"
    return _SCRATCH


def run_task(task: Task, runs_dir: str | None) -> Outcome:
    """Run one task; write its record into ``runs_dir`` (or return it when that is None).

    A failing run is an Outcome with ``error`` set, never an exception: one bad configuration
    must not stop a sweep.
    """
    scratch = _scratch()
    scratch.unlink(missing_ok=True)
    try:
        code = _invoke(task)
        if code:
            return _failed(task, f"swarmex {task.command} exited with status {code}")
        text = scratch.read_text(encoding="utf-8")
    except InputError as exc:
        return _failed(task, str(exc))
    except Exception as exc:  # a failing run is data, not a crash
        if hasattr(exc, "format_message"):  # Click's usage errors: bad input, not a bug
            return _failed(task, exc.format_message())
        return _failed(task, f"{type(exc).__name__}: {exc}", traceback.format_exc())
    finally:
        scratch.unlink(missing_ok=True)
    record = json.loads(text)
    outcome = outcome_from_record(task.index, task.run_id, record)
    if runs_dir is None:
        outcome.record_text = text
    else:
        write_text_atomic(Path(runs_dir) / f"{task.run_id}.json", text)
    return outcome


def run_chunk(
    runner: Callable[[Task, str | None], Outcome], tasks: list[Task], runs_dir: str | None
) -> list[Outcome]:
    """Several tasks in one hand-over from the driver (see ``sweep._chunk_size``)."""
    return [runner(task, runs_dir) for task in tasks]


def warm_up(task: Task) -> None:
    """Do in the driver, once, what every fresh worker would otherwise do before its first run.

    The workers are forked from the driver after this, so they inherit it: the Click command
    built from Typer's app, a first parse of the task's options (Click's first call imports
    much of what it uses), and numba's code generation registries, which its first cached
    kernel loads (a few tenths of a second per process). Best effort: a failure here only
    means the workers warm up themselves.
    """
    with contextlib.suppress(Exception):
        command = _command(task.command)
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            command.make_context(f"swarmex {task.command}", [*task.argv, "--json", os.devnull])
    with contextlib.suppress(Exception):
        import numpy as np

        from swarmex.planning.distance import distance_field
        from swarmex.worlds.grid import GridWorld

        distance_field(GridWorld(np.ones((1, 2), dtype=bool)).graph, 0)


def _invoke(task: Task) -> int:
    argv = [*task.argv, "--json", str(_scratch())]
    sink = io.StringIO()
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            result = _command(task.command).main(
                args=argv, prog_name=f"swarmex {task.command}", standalone_mode=False
            )
    except SystemExit as exc:  # typer.Exit and friends
        return exc.code if isinstance(exc.code, int) else 1
    code = getattr(result, "exit_code", 0)
    return code if isinstance(code, int) else 0


def _failed(task: Task, message: str, detail: str | None = None) -> Outcome:
    return Outcome(task.index, task.run_id, ok=False, error=message.strip(), detail=detail)


def outcome_from_record(index: int, run_id: str, record: dict[str, Any]) -> Outcome:
    """The row-sized part of a result record: termination, makespan and scalar totals."""
    return Outcome(
        index,
        run_id,
        ok=True,
        complete=bool(record.get("complete")),
        makespan=_number(record.get("makespan")),
        time_unit=record.get("time_unit"),
        wall_seconds=_number(record.get("wall_seconds")),
        metrics=flat_scalars(record.get("metrics") or {}),
    )


def _number(v: Any) -> float | None:
    return None if v is None else float(v)


def flat_scalars(metrics: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """Scalar metrics, nested tables flattened with dots; lists are left out (not a column)."""
    out: dict[str, Any] = {}
    for key, value in metrics.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(flat_scalars(value, name + "."))
        elif value is None or isinstance(value, str | int | float | bool):
            out[name] = value
    return out


def write_text_atomic(path: Path, text: str) -> None:
    """Temp file + rename: a reader (or a resumed sweep) never sees half a record.

    No fsync: a record survives the crash of any process, which is what resuming needs; only
    a power cut could lose the last few, and those runs are simply run again.
    """
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


class RayWorker:
    """A long-lived Ray actor body: imports swarmex once, then runs chunks of tasks.

    Plain class here (decorated with ``ray.remote`` by the driver) so this module never
    imports Ray. It returns the record texts, since a cluster node may not share the sweep
    folder with the driver. Tasks come in small chunks because one actor call costs a few
    round trips through Ray's scheduler, as much as a small run on a busy machine.
    """

    def __init__(self) -> None:
        init_worker()

    def run(self, tasks: list[Task]) -> list[Outcome]:
        return [run_task(task, None) for task in tasks]
