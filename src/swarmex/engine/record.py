"""The result record of DESIGN.md: one JSON object per run, written atomically.

Every mission command builds a :class:`ResultRecord` and writes it with
:func:`write_record`; sweeps, plots and reproduction reports read the same schema back.
Numbers are plain Python floats/ints so the JSON is identical across numpy versions, and
``wall_seconds`` is the only field allowed to differ between two runs of the same seed.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, is_dataclass
from html import escape
from pathlib import Path
from typing import Any, cast

import numpy as np

from swarmex import __version__
from swarmex.engine.atomic import atomic_open
from swarmex.errors import InputError


def plain(value: Any) -> Any:
    """Numpy scalars/arrays and tuples → JSON-ready Python values (non-finite → None);
    dataclasses → dicts.

    A large run's record holds millions of trajectory rows, so the common case (a list of
    lists of ints and floats) is walked in one loop per list with the type tests inline,
    not one call per number: a 64-agent traversal of a 1024² grid, 16 s → a few."""
    t = type(value)
    if t is int or t is str or t is bool or value is None:
        return value
    if t is float:
        return value if value - value == 0.0 else None  # inf - inf and nan are nan
    if t is list or t is tuple:
        return _plain_seq(value)
    return _plain_other(value)


def _plain_seq(seq: list[Any] | tuple[Any, ...]) -> list[Any]:
    out: list[Any] = []
    append = out.append
    for v in seq:
        t = type(v)
        if t is int or t is str or t is bool or v is None:
            append(v)
        elif t is float:
            append(v if v - v == 0.0 else None)
        elif t is list or t is tuple:
            append(_plain_seq(v))
        else:
            append(_plain_other(v))
    return out


def _plain_other(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return _plain_seq(value)
    if isinstance(value, np.ndarray):
        return _plain_seq(value.tolist())
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        f = float(value)
        return f if math.isfinite(f) else None
    if is_dataclass(value) and not isinstance(value, type):
        return plain(asdict(value))
    return value


#: How many team metrics a record's one-line repr names (the rest are counted).
MAX_SHOWN = 6


def _short(value: Any) -> str:
    """A number as a REPL line shows it: 4 significant digits for floats."""
    if isinstance(value, float) and not isinstance(value, bool):
        return f"{value:.4g}"
    return str(value)


def _cell(value: Any) -> str:
    """A metric as one table cell: a table metric's entries ``key=value`` (the first
    :data:`MAX_SHOWN`), a list by its length, anything else as :func:`_short` shows it."""
    if isinstance(value, dict):
        items = [f"{k}={_short(v)}" for k, v in list(value.items())[:MAX_SHOWN]]
        return ", ".join(items) + (", …" if len(value) > MAX_SHOWN else "")
    if isinstance(value, list):
        return f"[{len(value)} values]"
    return _short(value)


@dataclass(frozen=True)
class MetricInfo:
    """What one team metric of a record means (a mission's ``metrics`` declaration).

    Why declared: a sweep can then check a ``--metric`` name before hours of runs (a typo
    used to surface only in the summary), and ``swarmex.describe`` and docs/api.md list every
    metric from the one place that a test holds equal to what the runs write. ``numeric`` is
    False for a metric that is a list or a table per run (it has no mean over seeds).
    ``keys`` are the entries a table can hold, each a sweep column ``NAME.KEY`` (nested
    tables joined with dots), so a misspelt entry is caught before the runs too; empty when
    they are not known in advance (or the metric is a list). ``counts`` marks a table of
    counts, whose record leaves out an entry that counted nothing (no RERR sent, no replan
    for that reason): a sweep's column of such an entry is then 0, not a missing value, so
    means, CIs, plots and pairs count that run.
    """

    meaning: str
    numeric: bool = True
    keys: tuple[str, ...] = ()
    counts: bool = False


@dataclass
class AgentRecord:
    """One agent of a run: its id, its own metrics (the mission's names, e.g. traversal's
    ``nodes_done``, ``total_time``), its ``trajectory`` as ``[t, x, y]`` rows and its
    ``jobs`` as ``[t, x, y]`` rows (both empty in a ``trace=False`` run)."""

    id: int
    metrics: dict[str, Any] = field(default_factory=dict)
    trajectory: list[list[float]] = field(default_factory=list)
    jobs: list[list[float]] = field(default_factory=list)

    def __repr__(self) -> str:  # the trace can hold millions of rows: count them instead
        return (f"AgentRecord(id={self.id}, metrics={self.metrics!r},"
                f" trajectory=<{len(self.trajectory)} rows>, jobs=<{len(self.jobs)} rows>)")


def _check_path(path: Any, where: str) -> None:
    """A file name, or one line saying what was given (None was a TypeError from ``open``)."""
    if not isinstance(path, str | os.PathLike):
        raise InputError(f"{where}: the path must be a file name (a str or path), got {path!r}")


@dataclass
class ResultRecord:
    """The result of one run (DESIGN.md's record), what ``swarmex.run`` returns and
    ``--json`` writes.

    ``mission`` and ``algorithm`` name what ran; ``params`` every parameter as the run used
    it (after defaults and derived values, e.g. each agent's nest); ``seed``; ``world`` the
    world's kind, source, size and free cells; ``complete`` whether the mission finished
    (False when stopped early by :class:`~swarmex.missions.base.StopRun` or a limit);
    ``makespan`` in ``time_unit`` (``"s"`` or ``"step"``); ``metrics`` the team totals;
    ``agents`` one :class:`AgentRecord` each; ``wall_seconds`` the run's wall time, the one
    field that differs between two runs of the same seed; ``extra`` mission-specific
    top-level keys. :meth:`to_dict` is the JSON, :meth:`from_dict` reads it back; records
    pickle, so they cross process boundaries.
    """

    mission: str
    algorithm: str
    params: dict[str, Any]
    seed: int
    world: dict[str, Any]
    complete: bool
    makespan: float
    time_unit: str
    metrics: dict[str, Any]
    agents: list[AgentRecord]
    wall_seconds: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)
    swarmex_version: str = __version__

    def __repr__(self) -> str:
        """One line a REPL can show: what ran and how it ended, the team metrics by name.
        Why not the dataclass's: it printed every trajectory row (5 kB for 2 agents on 8x8,
        hundreds of MB for a 1024² run, which froze a notebook that displayed the record)."""
        state = "complete" if self.complete else "incomplete"
        numbers = [f"{k}={_short(v)}" for k, v in self.metrics.items()
                   if isinstance(v, int | float) and not isinstance(v, bool)][:MAX_SHOWN]
        more = len(self.metrics) - len(numbers)
        if more > 0:
            tail = f", … {more} more" if numbers else f"{more} not numbers"
        else:
            tail = "" if numbers else "none"  # all shown: "b=2.5none" was printed
        shown = ", ".join(numbers) + tail
        return (f"<ResultRecord {self.mission} {self.algorithm}, seed {self.seed}: {state},"
                f" {self._headline()}; metrics {shown}>")

    def _headline(self) -> str:
        """"makespan 69 steps, 2 agents": the unit and the count read as words, the same in
        the repr and the notebook view."""
        unit = "steps" if self.time_unit == "step" else self.time_unit
        count = len(self.agents)
        return f"makespan {_short(self.makespan)} {unit}, {count} agent{'s' * (count != 1)}"

    def _repr_html_(self) -> str:
        """A notebook's view: the run in a heading, every team metric in a table (a table
        metric, e.g. exploration's ``unicasts``, as its entries; a list as its length)."""
        state = "complete" if self.complete else "incomplete"
        rows = "".join(
            f"<tr><td><code>{escape(str(k))}</code></td><td>{escape(_cell(v))}</td></tr>"
            for k, v in self.metrics.items()
        )
        return (f"<b>{escape(self.mission)} {escape(self.algorithm)}</b>, seed {self.seed}:"
                f" {state}, {escape(self._headline())}<table>{rows}</table>")

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON-ready values: the version first, then the fields in order,
        then ``extra``'s keys. Built field by field rather than by ``dataclasses.asdict``,
        whose deep copy of every trajectory row :func:`plain` would copy again."""
        out: dict[str, Any] = {"swarmex_version": self.swarmex_version}
        for f in fields(self):
            if f.name in ("extra", "swarmex_version"):
                continue
            if f.name == "agents":
                out["agents"] = [
                    {"id": a.id, "metrics": a.metrics, "trajectory": a.trajectory, "jobs": a.jobs}
                    for a in self.agents
                ]
            else:
                out[f.name] = getattr(self, f.name)
        out.update(self.extra)
        return cast(dict[str, Any], plain(out))

    @classmethod
    def read(cls, path: str | Path) -> ResultRecord:
        """The record of a file ``--json``, a sweep or :meth:`write` wrote (an InputError
        names a missing or malformed one, and the file)."""
        _check_path(path, "ResultRecord.read")
        data = read_record(path)
        try:
            return cls.from_dict(data)
        except InputError as exc:  # among several files, which one is what matters
            raise InputError(f"{path}: {exc}") from None

    def write(self, path: str | Path) -> Path:
        """Write the record's JSON to ``path`` atomically (what ``--json`` writes)."""
        _check_path(path, "ResultRecord.write")
        return write_record(self, path)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ResultRecord:
        """The record back from its JSON (:meth:`to_dict`, or a file ``--json`` wrote):
        ``ResultRecord.from_dict(rec.to_dict()).to_dict() == rec.to_dict()``.

        Why: a record written by the command line or a sweep is the input of later analysis
        in Python, which wants ``record.metrics`` and ``record.agents[i].trajectory`` rather
        than nested dict lookups. Keys that are not fields go back to ``extra``, in order, so
        writing the record again gives the same JSON. A missing field or a malformed agent is
        an :class:`~swarmex.errors.InputError` naming it.
        """
        if not isinstance(data, Mapping):
            raise InputError(f"a record is a JSON object, got {type(data).__name__}")
        names = [f.name for f in fields(cls) if f.name != "extra"]
        optional = {"wall_seconds", "swarmex_version"}
        missing = [n for n in names if n not in data and n not in optional]
        if missing and "error" in data and "traceback" in data:  # a sweep's runs/ID.error.json
            raise InputError(
                f"not a record but a failed sweep run's error file (it failed with:"
                f" {str(data['error']).splitlines()[0] if data['error'] else '?'}); run it"
                " again with swarmex sweep SPEC --retry-failed"
            )
        if missing:
            raise InputError(f"not a swarmex record: no {', '.join(map(repr, missing))}")
        if not isinstance(data["agents"], list):
            raise InputError("record: 'agents' must be a list of agent objects")
        for key in ("params", "world", "metrics"):  # read as tables later: say it here
            if not isinstance(data[key], Mapping):
                raise InputError(f"record: {key!r} must be a JSON object, got"
                                 f" {type(data[key]).__name__}")
        for key in ("mission", "algorithm"):
            if not isinstance(data[key], str):
                raise InputError(f"record: {key!r} must be a string, got {data[key]!r}")
        agents = []
        for i, a in enumerate(data["agents"]):
            if not isinstance(a, Mapping) or "id" not in a:
                raise InputError(f"record: agents[{i}] is not an agent object with an 'id'")
            if not isinstance(a.get("metrics") or {}, Mapping) or not all(
                isinstance(a.get(k) or [], list) for k in ("trajectory", "jobs")
            ):
                raise InputError(f"record: agents[{i}] needs an object 'metrics' and lists"
                                 " 'trajectory' and 'jobs'")
            agents.append(AgentRecord(
                id=a["id"], metrics=dict(a.get("metrics") or {}),
                trajectory=list(a.get("trajectory") or []), jobs=list(a.get("jobs") or []),
            ))
        given = {n: data[n] for n in names if n in data and n != "agents"}
        extra = {k: v for k, v in data.items() if k not in names}
        return cls(**given, agents=agents, extra=extra)


def without_trace(record: ResultRecord, derived: tuple[str, ...] = ()) -> ResultRecord:
    """The record with its per-step trace left out (``trace=False`` of the Mission contract):
    each agent's ``trajectory`` and ``jobs`` emptied, and the per-agent metrics named in
    ``derived`` (those only the trace gives) set to None. Team metrics are untouched."""
    for agent in record.agents:
        agent.trajectory = []
        agent.jobs = []
        for key in derived:
            if key in agent.metrics:
                agent.metrics[key] = None
    return record


def message_total(record: Mapping[str, Any]) -> int | None:
    """A record's own count of messages sent, under the name its mission uses, if any (the
    live views' end totals)."""
    metrics = record.get("metrics") or {}
    for key in ("messages", "messages_sent"):
        if isinstance(metrics.get(key), int):
            return int(metrics[key])
    return None


def write_json_atomic(data: Any, path: str | Path) -> Path:
    """Write JSON atomically (:mod:`swarmex.engine.atomic`: temp file beside ``path``, fsync,
    rename), with the mode a plain ``open`` would give it.

    A reader never sees a half-written file, and an interrupted run leaves the previous file
    (or none) rather than a truncated one.
    """
    return _write_plain_json(plain(data), path)


def _write_plain_json(data: Any, path: str | Path) -> Path:
    # one dumps and one write: json.dump with an indent encodes in Python chunk by chunk,
    # 2-3x slower on a large record (the text is the same)
    text = json.dumps(data, indent=1)
    with atomic_open(path, fsync=True) as fh:
        fh.write(text)
    return Path(path)


def write_record(record: ResultRecord, path: str | Path) -> Path:
    return _write_plain_json(record.to_dict(), path)


def read_record(path: str | Path) -> dict[str, Any]:
    """A record file's JSON as a dict (``ResultRecord.from_dict`` makes it a record again);
    a missing or malformed file is an InputError naming it."""
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"record not found: {path}") from None
    except IsADirectoryError:
        raise InputError(f"{path} is a folder, not a record file") from None
    except OSError as exc:  # unreadable: permissions, a device
        raise InputError(f"cannot read the record {path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path} is not a JSON record: not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path} is not a JSON record: {exc.msg} at line {exc.lineno}") from None
