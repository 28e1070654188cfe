"""``plain`` (the record's JSON conversion, with its inline fast path for large trajectory
lists) against the rule written the slow, obvious way, on random nested values; and
``ResultRecord.to_dict`` against ``dataclasses.asdict`` + that rule (key order included)."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pytest

from swarmex.engine.record import AgentRecord, ResultRecord, plain


def reference(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): reference(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [reference(v) for v in value]
    if isinstance(value, np.ndarray):
        return reference(value.tolist())
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        f = float(value)
        return f if math.isfinite(f) else None
    return value


ATOMS = [0, -7, 2**70, 1.5, -0.0, float("inf"), -float("inf"), float("nan"), 1e308, True, False,
         None, "x", np.int32(4), np.int64(-5), np.uint8(200), np.float32(0.25), np.float64("nan"),
         np.bool_(False)]


def _random_value(rng: np.random.Generator, depth: int = 0) -> Any:
    kind = rng.integers(0, 6 if depth < 4 else 1)
    if kind == 0:
        return ATOMS[rng.integers(len(ATOMS))]
    if kind == 1:
        return [_random_value(rng, depth + 1) for _ in range(rng.integers(0, 5))]
    if kind == 2:
        return tuple(_random_value(rng, depth + 1) for _ in range(rng.integers(0, 4)))
    if kind == 3:
        return {rng.integers(0, 9) if rng.random() < 0.3 else f"k{i}": _random_value(rng, depth + 1)
                for i in range(rng.integers(0, 4))}
    if kind == 4:
        return rng.normal(size=rng.integers(0, 4)) if rng.random() < 0.5 else np.arange(3)
    return [[int(t), float(t) / 3, (t, t + 1)] for t in range(rng.integers(0, 6))]


@pytest.mark.parametrize("seed", range(40))
def test_plain_equals_the_obvious_rule(seed):
    value = _random_value(np.random.default_rng(seed))
    got, want = plain(value), reference(value)
    assert json.dumps(got, allow_nan=False) == json.dumps(want, allow_nan=False)
    assert type(got) is type(want)


@dataclass
class _Point:
    x: int
    y: float


def test_to_dict_equals_asdict_then_plain_in_order():
    rec = ResultRecord(
        mission="m", algorithm="a", params={"p": (1, 2), "np": np.int64(3)}, seed=1,
        world={"w": np.arange(4)}, complete=True, makespan=float("inf"), time_unit="s",
        metrics={"f": np.float32(0.5), "nan": float("nan"), "pt": _Point(1, 2.0)},
        agents=[AgentRecord(id=1, metrics={"k": np.bool_(True)}, trajectory=[[0.0, 1], [1.5, 2]],
                            jobs=[[2.0, 1, "job"]])],
        wall_seconds=0.1, extra={"extra_key": [np.int16(1)]},
    )
    d = asdict(rec)
    extra = d.pop("extra")
    want = reference({"swarmex_version": d.pop("swarmex_version"), **d, **extra})
    got = rec.to_dict()
    assert list(got) == list(want)
    assert json.dumps(got) == json.dumps(want)
