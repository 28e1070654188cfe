"""The worker side of a sweep: run one mission in this process, return a small row.

Why in-process: starting a Python interpreter and importing swarmex costs more than a small run
itself, so a worker is a long-lived process that imported swarmex once and calls the mission
directly through the Mission contract (``Mission.params`` parses and validates exactly as the
command line does, ``Mission.run`` runs and records); no argv and no CLI are involved. The
record is written into the sweep folder with an atomic rename, in the same JSON layout as
``--json``.

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
import traceback
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from swarmex.engine.atomic import write_atomic
from swarmex.errors import InputError
from swarmex.experiments.pool import init_worker, warm_numba


@dataclass(frozen=True)
class Task:
    index: int
    run_id: str
    mission: str  # "traversal"
    values: dict[str, Any]  # the mission's parameters (Mission.params), seed included


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


def run_task(task: Task, runs_dir: str | None) -> Outcome:
    """Run one task; write its record into ``runs_dir`` (or return it when that is None).

    A failing run is an Outcome with ``error`` set, never an exception: one bad configuration
    must not stop a sweep.
    """
    from swarmex.missions.registry import get

    sink = io.StringIO()  # a library that prints (a solver's banner) must not garble the bar
    try:
        with contextlib.redirect_stdout(sink):
            mission = get(task.mission)
            record = mission.run(mission.params(task.values)).record.to_dict()
    except InputError as exc:
        return _failed(task, str(exc))
    except Exception as exc:  # a failing run is data, not a crash
        return _failed(task, f"{type(exc).__name__}: {exc}", traceback.format_exc())
    text = json.dumps(record, indent=1)  # the layout of --json (engine.record.write_record)
    outcome = outcome_from_record(task.index, task.run_id, record)
    if runs_dir is None:
        outcome.record_text = text
    else:
        write_atomic(Path(runs_dir) / f"{task.run_id}.json", text)
    return outcome


class InFolder:
    """``run_task`` (or a stand-in) bound to the sweep's runs folder: the pool's job function
    (a picklable object, since the pool hands it to its workers)."""

    def __init__(self, runner: Callable[[Task, str | None], Outcome], runs_dir: str) -> None:
        self.runner = runner
        self.runs_dir = runs_dir

    def __call__(self, task: Task) -> Outcome:
        return self.runner(task, self.runs_dir)


def warm_up(task: Task) -> None:
    """Do in the driver, once, what every fresh worker would otherwise do before its first run.

    The workers are forked from the driver after this, so they inherit it: the mission's
    modules (imported by a first parse of the task's parameters and a first world), and
    numba's code generation registries, which its first cached kernel loads (a few tenths of
    a second per process). Best effort: a failure here only means the workers warm up
    themselves.
    """
    with contextlib.suppress(Exception):
        from swarmex.missions.registry import get

        mission = get(task.mission)
        mission.prepare(mission.params(task.values))
        import swarmex.engine.record  # noqa: F401
    warm_numba()


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
