"""Output files named on the command line, checked before a run starts.

A typo in ``--json`` or ``--render`` (a wrong suffix, a missing or read-only folder) should
cost one line and exit status 2 at once, not a finished run that cannot be saved. Every
command checks its output options here, so the messages read the same everywhere.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterator
from pathlib import Path

from swarmex.cli.app import err_console, interrupted
from swarmex.cli.compiling import compile_notice
from swarmex.errors import InputError
from swarmex.viz.animation import RENDER_SUFFIXES

__all__ = ["RENDER_SUFFIXES", "check_out_dir", "check_output", "interrupted_keeps", "study"]


def check_out_dir(path: Path, option: str = "--out") -> None:
    """Fail now, not after the first runs, if the output folder ``path`` cannot be made or
    written (it exists as a file, or its first existing parent is not writable)."""
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {path} exists and is not a directory")
    if path.is_dir():
        check_output(path / "runs.jsonl", option)  # the probe: can a file be made in it?
        return
    check_output(path, option)


def check_distinct(*outputs: tuple[Path | None, str]) -> None:
    """Two outputs of one run may not be one file: the later write replaced the earlier one
    (``--json out.png --render out.png`` kept the picture and lost the record silently)."""
    seen: dict[str, str] = {}
    for path, option in outputs:
        if path is None:
            continue
        real = os.path.realpath(path)
        if real in seen:
            raise InputError(f"{seen[real]} and {option} name the same file ({path}); give"
                             " each its own")
        seen[real] = option


def check_output(path: Path | None, option: str, suffixes: tuple[str, ...] = ()) -> None:
    """Fail now, not after the run, if ``path`` cannot be written (or has a bad suffix)."""
    if path is None:
        return
    if suffixes and path.suffix.lower() not in suffixes:
        raise InputError(
            f"{option}: unsupported file type {path.suffix or '(none)'!r} for {path}"
            f" (use {' or '.join(suffixes)})"
        )
    if path.is_dir():
        raise InputError(f"{option}: {path} is a directory")
    if path.exists() and not path.is_file():  # /dev/null, a FIFO: written in place
        if not os.access(path, os.W_OK):
            raise InputError(f"{option}: cannot write {path}: permission denied")
        return
    parent = Path(os.path.realpath(path)).parent if path.is_symlink() else path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent  # the writer creates missing folders below the first existing one
    if not parent.is_dir():
        raise InputError(f"{option}: cannot write {path}: {parent} is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{option}: cannot write {path}: {parent} is not writable")
    # os.access answers yes to root everywhere, and knows nothing of read-only mounts or
    # pseudo file systems (/proc): creating a file there is the only sure test
    probe = parent / f".swarmex-probe-{os.getpid()}-{secrets.token_hex(4)}"
    try:
        os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    except OSError as exc:
        raise InputError(f"{option}: cannot write {path}: {exc.strerror or exc}") from None
    probe.unlink(missing_ok=True)


@contextlib.contextmanager
def interrupted_keeps(store: Path) -> Iterator[None]:
    """Ctrl-C in a resumable study: say where the finished runs are and how to resume, and
    exit 130 (Typer turns a bare KeyboardInterrupt into a silent status 130)."""
    try:
        yield
    except KeyboardInterrupt:
        if _stored_runs(store) == 0:  # stopped before the first run finished
            interrupted("no run had finished, so nothing was kept")
        interrupted(f"finished runs are saved in {store} (run the same command again to resume)")


def _stored_runs(store: Path) -> int | None:
    """How many runs a study's store holds: its journal's lines, or its JSON's ``runs``
    (the traversal study writes its JSON, empty, even when stopped during the first
    compile); None when it cannot tell."""
    from swarmex.experiments.runstore import existing, read_json

    path = existing(store)
    if not path.exists():
        return 0
    try:
        if path.suffix == ".jsonl":
            with path.open(encoding="utf-8") as fh:
                return sum(1 for line in fh if line.strip())
        runs = read_json(path).get("runs")
        return len(runs) if isinstance(runs, dict | list) else None
    except (OSError, ValueError, AttributeError, EOFError):
        return None


@contextlib.contextmanager
def study(store: Path) -> Iterator[None]:
    """What every ``swarmex reproduce`` command runs its study in: Ctrl-C says where the
    finished runs are (:func:`interrupted_keeps`), and a numba compile says so.

    Why the notice: the first reproduction after an install compiles its kernels (8-15 s of
    CPU) before the first run finishes, and without a word it looked hung.
    """
    with interrupted_keeps(store), compile_notice(err_console):
        yield
