"""Atomic file writes: a temporary file beside the target, renamed over it when complete.

A reader (a plot, a resumed sweep, another process polling the file) never sees half a file,
and an interrupted write leaves the previous file (or none) rather than a truncated one.
Every atomic write in swarmex goes through here: result records, run stores, sweep tables.

The temporary file is created with :func:`os.open` and mode ``0o666``, so the process umask
applies exactly as it does to a plain ``open(path, "w")``: the renamed file has the mode any
other output of the run has (0644 under the usual umask 022). ``tempfile.mkstemp`` would
create it 0600, and that mode survives the rename.

* :func:`write_atomic` — text or bytes in one call;
* :func:`atomic_open` — a file object for writers that stream (``json.dump``);
* :func:`atomic_path` — a temporary path for writers that want a file name (Parquet, images).

What is already at the path is respected, as a plain ``open(path, "w")`` would:

* a symbolic link stays a link: the file it points to is the one replaced;
* a file that is not a regular file (``/dev/null``, a FIFO, a terminal) is written directly,
  never replaced (renaming over ``/dev/null`` as root made it a plain file);
* a regular file keeps its permission bits (a 0600 record stays 0600).

Directories are created as needed; failing to create the directory or the temporary file is
an :class:`~swarmex.errors.InputError` naming the path (an unwritable ``--json`` or
``--out``), not a traceback. ``fsync=True`` also survives a power cut, at some cost per file.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

from swarmex.errors import InputError


def _temp_beside(path: Path) -> Path:
    """A fresh hidden name in ``path``'s directory (same file system, so rename is atomic)."""
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")


def check_writable(path: Path) -> None:
    """An InputError naming why ``path`` cannot be written, without writing anything: a
    folder by that name (a rename over it fails with IsADirectoryError after the whole
    write), or a file where one of its folders should be (mkdir's bare "File exists" did
    not say which). For a caller that must know before long work (a rerun to draw)."""
    if path.is_dir():
        raise InputError(f"cannot write {path}: it is a folder")
    blocker = next((p for p in path.parents if p.exists() and not p.is_dir()), None)
    if blocker is not None:
        raise InputError(f"cannot write {path}: {blocker} is a file, not a folder")


def _target(path: Path) -> tuple[Path, bool, int | None]:
    """What a write to ``path`` must replace: the link's target for a symbolic link; whether
    that is a special file (written in place); the permission bits of a regular file there."""
    real = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        st = os.stat(real)
    except OSError:
        return real, False, None
    if stat.S_ISREG(st.st_mode):
        return real, False, stat.S_IMODE(st.st_mode)
    return real, not stat.S_ISDIR(st.st_mode), None


#: what a write can meet half-way that no path check can foresee (disk full, a file-size
#: limit, a quota, a read-only remount, a failing disk)
_WRITE_FAILED = frozenset({errno.ENOSPC, errno.EFBIG, errno.EDQUOT, errno.EROFS, errno.EIO})


def _raise_if_write_failed(path: Path, exc: BaseException, kept: bool = True) -> None:
    """Raise the one line for a write that failed half-way (else return, and the caller
    re-raises ``exc``). ``kept``: the write went to a temporary file, so the previous file
    (if any) is as it was."""
    if isinstance(exc, OSError) and exc.errno in _WRITE_FAILED:
        said = " (the previous file, if any, is unchanged)" if kept else ""
        raise InputError(f"cannot write {path}: {exc.strerror or exc}{said}") from None


def _make_parent(path: Path) -> None:
    """Make ``path``'s folder, or say in one line why it cannot be written."""
    check_writable(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror or exc}") from None


@contextlib.contextmanager
def _replace_when_done(tmp: Path, path: Path, keep_mode: int | None) -> Iterator[None]:
    """Around the block that writes ``tmp``: on a clean exit ``tmp`` takes ``keep_mode`` (the
    replaced file's bits, if any) and is renamed over ``path``; on any exception it is
    removed, leaving ``path`` as it was, and a disk-full kind of failure becomes one line.
    Why one place: this commit-or-roll-back is what makes every atomic writer atomic."""
    try:
        yield
        if keep_mode is not None:
            os.chmod(tmp, keep_mode)
        os.replace(tmp, path)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        _raise_if_write_failed(path, exc)
        raise


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; what the block writes there replaces ``path``.

    The writer creates the file itself (with a normal open, hence the umask's mode). If the
    block raises, the temporary file is removed and ``path`` is left as it was.
    """
    path, special, keep_mode = _target(Path(path))
    if special:
        yield path
        return
    _make_parent(path)
    tmp = _temp_beside(path)
    with _replace_when_done(tmp, path, keep_mode):
        yield tmp


@contextlib.contextmanager
def atomic_open(
    path: str | Path, mode: str = "w", encoding: str = "utf-8", fsync: bool = False
) -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path`` for writing (``mode`` "w" or "wb"); on a clean
    exit from the block it is flushed (and fsynced if asked) and renamed over ``path``."""
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_open writes a whole file: mode 'w' or 'wb', not {mode!r}")
    path, special, keep_mode = _target(Path(path))
    if special:
        try:
            fh = open(path, mode, encoding=None if "b" in mode else encoding)  # noqa: SIM115
        except OSError as exc:
            raise InputError(f"cannot write {path}: {exc.strerror or exc}") from None
        try:
            with fh:
                yield fh
        except OSError as exc:
            _raise_if_write_failed(path, exc, kept=False)
            raise
        return
    _make_parent(path)
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    try:
        tmp = _temp_beside(path)
        fd = os.open(tmp, flags, 0o666)  # the umask applies, as for open(path, "w")
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror or exc}") from None
    with (
        _replace_when_done(tmp, path, keep_mode),
        os.fdopen(fd, mode, encoding=None if "b" in mode else encoding) as fh,
    ):
        yield fh
        fh.flush()
        if fsync:
            os.fsync(fh.fileno())


def write_atomic(
    path: str | Path, data: str | bytes, encoding: str = "utf-8", fsync: bool = False
) -> Path:
    """Write ``data`` (text or bytes) to ``path`` atomically; returns the path."""
    mode = "wb" if isinstance(data, bytes | bytearray) else "w"
    with atomic_open(path, mode, encoding=encoding, fsync=fsync) as fh:
        fh.write(data)
    return Path(path)
