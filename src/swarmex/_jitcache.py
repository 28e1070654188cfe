"""Where numba keeps swarmex's compiled kernels, so ``cache=True`` never breaks an import.

Every kernel is ``@kernel(cache=True)`` (:mod:`swarmex._kernels`, numba's ``njit`` on first
compiled use): the first process compiles (seconds), the next ones load the machine code
from disk. numba looks for a writable place in this order: the
``NUMBA_CACHE_DIR`` the user set, the ``__pycache__`` folder beside the source (an editable
or per-user install), then a per-user folder (``$XDG_CACHE_HOME/numba`` or
``~/.cache/numba``). When none is writable - a read-only system install run by a user
without a home, a container's service account - numba raises ``RuntimeError: cannot cache
function`` while *importing* the kernel module, so every command would end in a traceback.

:func:`ensure_cache_dir` runs when ``swarmex`` is imported (a few ``stat`` calls, no numba
import) and, only in that case, points numba at a private folder in the temporary directory.
If even that is impossible the choice is left to numba. The user's own ``NUMBA_CACHE_DIR``
always wins.

numba checks a cached kernel against its own source file only, not against the kernels it
calls from other files (numba issue #1833): after ``git pull`` or an edit of
``selection.py``, a kernel of ``lattice.py`` loaded from the cache still runs the old
``select_top`` compiled into it, silently. :func:`drop_stale_kernels` runs before numba loads
and, when the cache is the one beside the source, removes swarmex's cached kernels once any
of its source files has changed since they were written (a stamp of every file's size and
time), so they are compiled again from the current code. A pip upgrade rewrites every file,
which numba notices by itself; this is for a source checkout.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import sys
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


def writable(path: Path) -> bool:
    """Whether ``path`` is, or could be created as, a folder this process can write into
    (its nearest existing ancestor is a writable folder)."""
    for candidate in (path, *path.parents):
        if candidate.exists():
            return candidate.is_dir() and os.access(candidate, os.W_OK | os.X_OK)
    return False


def user_cache_dir(env: Mapping[str, str]) -> Path:
    """numba's per-user cache folder (its ``AppDirs("numba").user_cache_dir``, read without
    importing numba; like numba, an empty ``XDG_CACHE_HOME`` means the current folder)."""
    home = env.get("HOME") or os.path.expanduser("~")
    if sys.platform == "darwin":
        return Path(home, "Library", "Caches", "numba")
    if sys.platform == "win32":
        return Path(env.get("LOCALAPPDATA", home), "numba", "Cache")
    base = env["XDG_CACHE_HOME"] if "XDG_CACHE_HOME" in env else os.path.join(home, ".cache")
    return Path(os.path.join(base, "numba"))


def fallback_cache_dir(
    env: Mapping[str, str], package: Path = PACKAGE, temp: Path | None = None
) -> Path | None:
    """The folder numba should use instead of its defaults, or ``None`` when numba's own
    choice works (or nothing better is writable)."""
    if env.get("NUMBA_CACHE_DIR"):
        return None  # the user decided
    if writable(package / "__pycache__") or writable(user_cache_dir(env)):
        return None
    uid = os.getuid() if hasattr(os, "getuid") else 0
    candidate = (temp or Path(tempfile.gettempdir())) / f"swarmex-numba-cache-{uid}"
    return candidate if writable(candidate) else None


def ensure_cache_dir() -> Path | None:
    """Point numba at :func:`fallback_cache_dir` when its defaults are not writable; return
    the folder chosen (``None``: numba's defaults are used)."""
    chosen = fallback_cache_dir(os.environ)
    if chosen is None:
        return None
    os.environ["NUMBA_CACHE_DIR"] = str(chosen)  # read when numba is imported, and by children
    config = sys.modules.get("numba.core.config")
    if config is not None:  # numba was imported first: its configuration is already read
        config.CACHE_DIR = str(chosen)  # type: ignore[attr-defined]
    return chosen


#: the stamp of the sources the kernels cached beside them were compiled from
STAMP = "swarmex-kernels.stamp"


def source_stamp(package: Path = PACKAGE) -> str:
    """A digest of the size and modification time of every Python file of the package."""
    h = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        st = path.stat()
        h.update(f"{path.relative_to(package)}\0{st.st_size}\0{st.st_mtime_ns}\n".encode())
    return h.hexdigest()


def drop_stale_kernels(env: Mapping[str, str] = os.environ, package: Path = PACKAGE) -> int:
    """Remove the kernels numba cached beside the sources if any source changed since; how
    many cache files were removed (see the module docstring). Nothing is done when numba
    caches elsewhere (``NUMBA_CACHE_DIR``, or the folder is not writable)."""
    cache = package / "__pycache__"
    if env.get("NUMBA_CACHE_DIR") or not writable(cache):
        return 0
    cache.mkdir(exist_ok=True)
    with _locked(cache / (STAMP + ".lock")):  # test workers start together
        stamp = source_stamp(package)
        marker = cache / STAMP
        with contextlib.suppress(OSError):
            if marker.read_text() == stamp:
                return 0
        removed = 0
        for pattern in ("__pycache__/*.nbi", "__pycache__/*.nbc"):
            for old in package.rglob(pattern):
                with contextlib.suppress(OSError):
                    old.unlink()
                    removed += 1
        with contextlib.suppress(OSError):
            marker.write_text(stamp)
        return removed


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    """An exclusive lock on ``path`` across processes where the platform has one."""
    try:
        import fcntl
    except ImportError:  # Windows: one process at a time is not enforced
        yield
        return
    try:
        fh = open(path, "a")  # noqa: SIM115 - held for the block
    except OSError:
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)
