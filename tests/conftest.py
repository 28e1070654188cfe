"""Shared fixtures: where the real benchmark maps live, and skipping when they are absent."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

# pytest -n 2: numba's on-disk cache is not safe when two processes write the same kernels at
# once (a cold cache can crash a worker: numba issues #4807, #10128), so each xdist worker keeps
# its own cache, set before any test imports numba, and new for every test session (xdist's
# run id): a folder kept from an earlier session, or from another checkout at the same path,
# once crashed a worker loading a kernel. A user's NUMBA_CACHE_DIR wins.
_WORKER = os.environ.get("PYTEST_XDIST_WORKER")
if _WORKER and "NUMBA_CACHE_DIR" not in os.environ:
    _RUN = os.environ.get("PYTEST_XDIST_TESTRUNUID", "run")[:12]
    _CACHES = Path(tempfile.gettempdir()) / f"swarmex-numba-tests-{os.getuid()}"
    os.environ["NUMBA_CACHE_DIR"] = str(_CACHES / f"{_RUN}-{_WORKER}")
    for _old in _CACHES.glob("*") if _CACHES.is_dir() else ():
        with contextlib.suppress(OSError):  # a day old: no session still running uses it
            if time.time() - _old.stat().st_mtime > 86400:
                shutil.rmtree(_old, ignore_errors=True)


@pytest.fixture
def real_map():
    """Path of a map in SWARMEX_MAPS, or a skip naming what is missing."""

    def get(name: str) -> Path:
        from swarmex.worlds.mapfiles import maps_dir  # after the numba cache is set

        path = maps_dir() / name
        if not path.exists():
            pytest.skip(f"real map {name} not found in {maps_dir()} (set SWARMEX_MAPS)")
        return path

    return get
