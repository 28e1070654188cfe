"""Policy wrappers for tests: it never writes the belief, and the same belief gives the same
decision (a deep copy of the belief and the same generator state, decided by a fresh policy
of the same class); :func:`spying` also sees the belief only through a read-only proxy that
logs what it reads."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

KEYS = ("status", "reserved", "loc", "next_loc", "free_at", "reservation")


def checking(base: type, limit: int) -> Any:
    """An instance of ``base`` (a traversal policy class) that checks its first ``limit``
    decisions for determinism, and every decision for writes to the belief."""

    class Checking(base):  # type: ignore[misc, valid-type]
        def __init__(self) -> None:
            super().__init__()
            self.checked = 0

        def decide(self, belief: Any, rng: np.random.Generator) -> Any:
            snapshot = {k: np.copy(getattr(belief, k)) for k in KEYS}
            state = copy.deepcopy(rng.bit_generator.state)
            decision = super().decide(belief, rng)
            for k, before in snapshot.items():
                assert np.array_equal(getattr(belief, k), before), f"policy changed belief.{k}"
            if self.checked < limit:
                again = np.random.default_rng()
                again.bit_generator.state = state
                assert base.decide(base(), copy.deepcopy(belief), again) == decision
                self.checked += 1
            return decision

    return Checking()


# what a traversal policy may read: the attributes of its own belief
BELIEF_API = {
    "me", "here", "graph", "known", "status", "reserved", "loc", "next_loc", "free_at",
    "now", "time_per_unit", "job_time", "km_mask", "km_at", "in_km", "rivals",
}


class ReadOnlyBelief:
    """Forwards reads to a belief and logs their names; refuses every write."""

    def __init__(self, inner: Any, seen: set[str]) -> None:
        object.__setattr__(self, "_inner", inner)
        object.__setattr__(self, "_seen", seen)

    def __getattr__(self, name: str) -> Any:
        self._seen.add(name)
        return getattr(self._inner, name)

    def __setattr__(self, name: str, value: Any) -> None:
        raise AssertionError(f"policy wrote belief.{name}")


def spying(base: type, limit: int) -> Any:
    """An instance of ``base`` (a traversal policy class) that decides on a
    :class:`ReadOnlyBelief` (the names it read gather in ``.seen``), checks every decision for
    writes to the belief, and its first ``limit`` decisions for determinism (``base``'s own
    decide on a deep copy of the belief with the same generator state; ``.checked`` counts
    them)."""

    class Spying(base):  # type: ignore[misc, valid-type]
        def __init__(self) -> None:
            super().__init__()
            self.seen: set[str] = set()
            self.checked = 0

        def decide(self, belief: Any, rng: np.random.Generator) -> Any:
            snapshot = {k: np.copy(getattr(belief, k)) for k in KEYS}
            state = copy.deepcopy(rng.bit_generator.state)
            decision = super().decide(ReadOnlyBelief(belief, self.seen), rng)
            for k, before in snapshot.items():
                assert np.array_equal(getattr(belief, k), before), f"policy changed belief.{k}"
            if self.checked < limit:  # same belief, same draws => same answer, from a copy
                again = np.random.default_rng()
                again.bit_generator.state = state
                assert base.decide(self, copy.deepcopy(belief), again) == decision
                self.checked += 1
            return decision

    return Spying()


def jit_and_python_agree(code: str, cwd: Any) -> None:
    """Run ``code`` (it prints one JSON line last) compiled and with numba's JIT disabled,
    in fresh interpreters, and require the same output."""
    import json
    import os
    import subprocess
    import sys
    import textwrap
    from pathlib import Path

    import swarmex

    src = Path(swarmex.__file__).resolve().parents[1]
    out = {}
    for name, env in (("jit", {}), ("python", {"NUMBA_DISABLE_JIT": "1"})):
        proc = subprocess.run(
            [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
            timeout=240, cwd=cwd, env={**os.environ, "PYTHONPATH": str(src), **env},
        )
        assert proc.returncode == 0, proc.stderr
        out[name] = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["jit"] == out["python"]
