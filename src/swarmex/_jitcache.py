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
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Mapping
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
