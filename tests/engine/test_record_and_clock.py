"""The result record is atomic and plain JSON; the clock breaks ties by schedule order."""

from __future__ import annotations

import json

import numpy as np
import pytest

from swarmex.engine import AgentRecord, EventQueue, ResultRecord, read_record, write_record
from swarmex.errors import InputError


def _record() -> ResultRecord:
    return ResultRecord(
        mission="traversal",
        algorithm="madgta",
        params={"agents": np.int64(3)},
        seed=1,
        world={"kind": "grid", "source": "x", "width": 2, "height": 2, "free_cells": 4},
        complete=True,
        makespan=np.float64(3.5),
        time_unit="s",
        metrics={"bad": float("inf")},
        agents=[AgentRecord(1, {"m": 1}, [[0.0, 0, 0]], [])],
    )


def test_record_schema_and_atomic_write(tmp_path):
    path = write_record(_record(), tmp_path / "sub" / "r.json")
    data = json.loads(path.read_text())
    for key in ("swarmex_version", "mission", "algorithm", "params", "seed", "world",
                "complete", "makespan", "time_unit", "metrics", "agents", "wall_seconds"):
        assert key in data
    assert data["params"]["agents"] == 3 and data["metrics"]["bad"] is None
    assert not [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]
    assert read_record(path)["makespan"] == 3.5


def test_failed_write_keeps_previous_file(tmp_path, monkeypatch):
    path = write_record(_record(), tmp_path / "r.json")
    before = path.read_text()

    import contextlib

    from swarmex.engine import record as record_module

    real_open = record_module.atomic_open

    @contextlib.contextmanager
    def half_written(target, *a, **k):  # the disk fills up in the middle of the file
        with real_open(target, *a, **k) as fh:
            fh.write('{"half": ')
            raise RuntimeError("disk full")
            yield fh

    monkeypatch.setattr(record_module, "atomic_open", half_written)
    with pytest.raises(RuntimeError):
        write_record(_record(), path)
    assert path.read_text() == before
    assert len(list(tmp_path.iterdir())) == 1


def test_read_record_errors(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_record(tmp_path / "none.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    with pytest.raises(InputError, match="not a JSON record"):
        read_record(bad)


def test_event_ties_follow_schedule_order():
    q = EventQueue()
    q.schedule(2.0, "b")
    q.schedule(1.0, "a")
    q.schedule(2.0, "c")
    assert [q.pop().kind for _ in range(3)] == ["a", "b", "c"]
    with pytest.raises(ValueError):
        q.schedule(1.0, "past")
