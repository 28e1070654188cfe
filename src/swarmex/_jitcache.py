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
``select_top`` compiled into it, silently. :func:`check_kernel_cache` runs once per process,
before swarmex's first kernel is compiled or loaded, and, when the cache is the one beside
the sources, removes swarmex's cached kernels once any source file has changed since they
were written (a stamp of every file's size and time), so they are compiled again from the
current code. A process whose sources changed after it imported swarmex (a notebook, a long
sweep) holds older code than the files: it gets a private cache instead, so it never stores
that code where later processes would load it. Left to numba: a process that changes
sources *after* its first kernel (it may still store old code; the next process to check
drops it unless it checked in between). A pip upgrade rewrites every file, which numba
notices by itself; this is for a source checkout.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import os
import shutil
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
    use_cache_dir(str(chosen))
    return chosen


def use_cache_dir(folder: str) -> None:
    """Make ``folder`` numba's cache for this process and its children."""
    os.environ["NUMBA_CACHE_DIR"] = folder  # read when numba is imported, and by children
    config = sys.modules.get("numba.core.config")
    if config is not None:  # numba was imported first: its configuration is already read
        config.CACHE_DIR = folder  # type: ignore[attr-defined]


#: the stamp of the sources the kernels cached beside them were compiled from
STAMP = "swarmex-kernels.stamp"


def in_tree(env: Mapping[str, str] = os.environ, package: Path = PACKAGE) -> bool:
    """Whether numba caches swarmex's kernels beside its sources (no ``NUMBA_CACHE_DIR``,
    the package's ``__pycache__`` writable): the only cache :func:`check_kernel_cache`
    looks after."""
    return not env.get("NUMBA_CACHE_DIR") and writable(package / "__pycache__")


def source_stamp(package: Path = PACKAGE) -> str:
    """A digest of the size and modification time of every Python file of the package
    (an entry that cannot be read, such as an editor's dangling lock link, is left out)."""
    h = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        try:
            st = path.stat()
        except OSError:
            continue
        h.update(f"{path.relative_to(package)}\0{st.st_size}\0{st.st_mtime_ns}\n".encode())
    return h.hexdigest()


def _stamp_now(package: Path = PACKAGE) -> str | None:
    try:
        return source_stamp(package) if in_tree(os.environ, package) else None
    except OSError:
        return None


#: the sources as this process imported them (``None``: not an in-tree cache)
IMPORTED = _stamp_now()


def drop_stale_kernels(env: Mapping[str, str] = os.environ, package: Path = PACKAGE,
                       stamp: str | None = None) -> int:
    """Remove the kernels numba cached beside the sources of ``package`` if any source
    changed since they were written (``stamp``: the sources now); how many cache files were
    removed (see the module docstring). Nothing is done when numba caches elsewhere. The
    stamp is recorded only once every stale file is gone."""
    if not in_tree(env, package):
        return 0
    cache = package / "__pycache__"
    cache.mkdir(exist_ok=True)
    with _locked(cache / (STAMP + ".lock")):  # test workers start together
        stamp = stamp or source_stamp(package)
        marker = cache / STAMP
        with contextlib.suppress(OSError):
            if marker.read_text() == stamp:
                return 0
        removed = 0
        kept = False
        for pattern in ("__pycache__/*.nbi", "__pycache__/*.nbc"):
            for old in package.rglob(pattern):
                try:
                    old.unlink()
                    removed += 1
                except FileNotFoundError:
                    pass
                except OSError:
                    kept = True
        if not kept:
            with contextlib.suppress(OSError):
                marker.write_text(stamp)
        return removed


def check_kernel_cache(package: Path = PACKAGE) -> str | None:
    """Before swarmex's first kernel is compiled or loaded in this process: drop stale
    cached kernels; or, when a source changed after this process imported swarmex
    (:data:`IMPORTED`; its code in memory is older than the files), give this process a
    private cache, so that it never stores old code under the new files' stamps for later
    processes to load. Returns that private folder, if any. Best effort: a cache it cannot
    clean is left as numba would leave it."""
    try:
        if IMPORTED is None:
            return None
        now = source_stamp(package)
        if now == IMPORTED:
            drop_stale_kernels(os.environ, package, now)
            return None
        private = tempfile.mkdtemp(prefix="swarmex-numba-")
    except OSError:
        return None
    use_cache_dir(private)
    atexit.register(shutil.rmtree, private, ignore_errors=True)
    return private


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    """An exclusive lock on ``path`` across processes where the platform and the file
    system have one (else the block runs unlocked)."""
    try:
        import fcntl
    except ImportError:  # Windows
        yield
        return
    try:
        fh = open(path, "a")  # noqa: SIM115 - held for the block
    except OSError:
        yield
        return
    with fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX)
        except OSError:  # a file system without locks
            yield
            return
        try:
            yield
        finally:
            with contextlib.suppress(OSError):
                fcntl.flock(fh, fcntl.LOCK_UN)
