"""A resumable store of per-run results for long reproduction sweeps.

A full reproduction is thousands of short runs. We want (1) every finished run on disk at
once, so an interrupted sweep loses nothing, (2) one self-contained JSON file that plots and
reports can be rebuilt from without rerunning, and (3) a restart that skips what is done.
Rewriting a multi-megabyte JSON after every 20 ms run would cost more than the runs, so each
result is first appended to a line-oriented journal (``<name>.journal.jsonl``, flushed per
line) and the JSON is rewritten atomically (:func:`swarmex.engine.atomic.write_atomic`) every
few seconds and at the end; opening the store merges both, and a clean :meth:`RunStore.close`
folds the journal in and deletes it. A torn last journal line (a kill mid-write) is ignored.

A gzipped store (``<name>.gz``, how docs/reproduction/ commits its ~10 MB of raw runs) is
the store when no plain ``<name>`` is there: it is read, and written back gzipped, so a rerun
in such a folder resumes from it rather than redoing every run beside it.

Seeds come from :func:`stable_seed`, a hash of the run's identity, so a run's result does not
depend on the order runs are scheduled in or on how many worker processes share them.
"""

from __future__ import annotations

import contextlib
import gzip
import hashlib
import json
import os
import time
from pathlib import Path
from typing import Any

from swarmex.engine.atomic import write_atomic


def stable_seed(*parts: object) -> int:
    """A 32-bit seed from the run's identity; stable across processes and Python versions.

    ``hash()`` is salted per process, so it would give different seeds in different workers.
    """
    text = "|".join(str(p) for p in parts)
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:4], "little")


class RunStore:
    """Runs keyed by a string id, persisted in ``path`` (JSON) plus a journal beside it.

    ``path`` + ``.gz`` stands for ``path`` when only it exists (:attr:`path` then names the
    ``.gz``, which later writes keep gzipped)."""

    def __init__(self, path: Path, header: dict[str, Any], flush_every: float = 5.0) -> None:
        self.path = existing(Path(path))
        self.journal_path = Path(path).with_name(Path(path).stem + ".journal.jsonl")
        self.header = dict(header)
        self.flush_every = flush_every
        self.runs: dict[str, dict[str, Any]] = {}
        self.configs: dict[str, dict[str, Any]] = {}
        #: the file's other fields as it was found (a study's sessions, its plan), else {}
        self.previous: dict[str, Any] = {}
        self._dirty = False
        self._last_flush = time.monotonic()
        self._load()
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._journal = open(self.journal_path, "a", encoding="utf-8")  # noqa: SIM115

    def _load(self) -> None:
        if self.path.exists():
            try:
                data = read_json(self.path)
            except (OSError, EOFError, json.JSONDecodeError):
                data = {}
            self.runs.update(data.get("runs", {}))
            self.configs.update(data.get("configs", {}))
            self.previous = {k: v for k, v in data.items() if k not in ("runs", "configs")}
        if self.journal_path.exists():
            with open(self.journal_path, encoding="utf-8") as fh:
                for line in fh:
                    try:
                        rec = json.loads(line)
                    except json.JSONDecodeError:
                        continue  # torn write from an interrupted run
                    if isinstance(rec, dict) and "id" in rec:
                        self.runs[rec["id"]] = rec
                        self._dirty = True

    def __contains__(self, run_id: str) -> bool:
        return run_id in self.runs

    def get(self, run_id: str) -> dict[str, Any] | None:
        return self.runs.get(run_id)

    def __len__(self) -> int:
        return len(self.runs)

    def add_config(self, key: str, params: dict[str, Any]) -> None:
        """Record what a configuration key means, so the JSON is self-describing."""
        if self.configs.get(key) != params:
            self.configs[key] = params
            self._dirty = True

    def add(self, record: dict[str, Any]) -> None:
        """Store one finished run (its ``id`` field is the key) and journal it immediately."""
        self.runs[record["id"]] = record
        self._journal.write(json.dumps(record, separators=(",", ":")) + "\n")
        self._journal.flush()
        self._dirty = True
        if time.monotonic() - self._last_flush >= self.flush_every:
            self.flush()

    def flush(self) -> None:
        """Rewrite the JSON atomically with everything stored so far."""
        data = {**self.header, "configs": self.configs, "runs": self.runs}
        text = json.dumps(data, separators=(",", ":"), sort_keys=True)
        if self.path.suffix == ".gz":  # mtime 0: the same runs give the same bytes
            write_atomic(self.path, gzip.compress(text.encode("utf-8"), 6, mtime=0))
        else:
            write_atomic(self.path, text)
        self._last_flush = time.monotonic()
        self._dirty = False

    def close(self) -> None:
        """Final flush; the journal is redundant afterwards and is removed."""
        if self._dirty or not self.path.exists():
            self.flush()
        self._journal.close()
        with contextlib.suppress(OSError):
            os.unlink(self.journal_path)

    def __enter__(self) -> RunStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def existing(path: Path) -> Path:
    """``path``, or ``path`` + ``.gz`` when only the gzipped file is there."""
    gz = path.with_name(path.name + ".gz")
    return gz if not path.exists() and gz.exists() else path


def read_json(path: Path) -> Any:
    """A store's JSON (``path``, or gzipped when it ends in ``.gz``)."""
    if path.suffix == ".gz":
        with gzip.open(path, "rt", encoding="utf-8") as fh:
            return json.load(fh)
    return json.loads(path.read_text(encoding="utf-8"))
