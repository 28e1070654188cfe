"""The result record of DESIGN.md: one JSON object per run, written atomically.

Every mission command builds a :class:`ResultRecord` and writes it with
:func:`write_record`; sweeps, plots and reproduction reports read the same schema back.
Numbers are plain Python floats/ints so the JSON is identical across numpy versions, and
``wall_seconds`` is the only field allowed to differ between two runs of the same seed.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from swarmex import __version__
from swarmex.engine.atomic import atomic_open
from swarmex.errors import InputError


def plain(value: Any) -> Any:
    """Numpy scalars/arrays and tuples → JSON-ready Python values (non-finite → None)."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        f = float(value)
        return f if math.isfinite(f) else None
    return value


@dataclass
class AgentRecord:
    id: int
    metrics: dict[str, Any] = field(default_factory=dict)
    trajectory: list[list[float]] = field(default_factory=list)
    jobs: list[list[float]] = field(default_factory=list)


@dataclass
class ResultRecord:
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

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        extra = d.pop("extra")
        out = {"swarmex_version": d.pop("swarmex_version"), **d}
        out.update(extra)
        return plain(out)


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


def write_json_atomic(data: Any, path: str | Path) -> Path:
    """Write JSON atomically (:mod:`swarmex.engine.atomic`: temp file beside ``path``, fsync,
    rename), with the mode a plain ``open`` would give it.

    A reader never sees a half-written file, and an interrupted run leaves the previous file
    (or none) rather than a truncated one.
    """
    with atomic_open(path, fsync=True) as fh:
        json.dump(plain(data), fh, indent=1)
    return Path(path)


def write_record(record: ResultRecord, path: str | Path) -> Path:
    return write_json_atomic(record.to_dict(), path)


def read_record(path: str | Path) -> dict[str, Any]:
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"record not found: {path}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path} is not a JSON record: {exc.msg} at line {exc.lineno}") from None
