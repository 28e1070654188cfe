"""Cached kernels beside the sources are dropped once any source file changed.

numba checks a cached function against its own file only: a kernel that calls a kernel of
another file keeps running the old callee after that file changes (numba issue #1833).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

from swarmex._jitcache import STAMP, drop_stale_kernels


def package(root: Path) -> Path:
    pkg = root / "pkg"
    (pkg / "sub" / "__pycache__").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "b.py").write_text("X = 1\n")
    return pkg


def test_cached_kernels_go_when_a_source_changes_and_stay_otherwise(tmp_path):
    pkg = package(tmp_path)
    cached = pkg / "sub" / "__pycache__"
    for name in ("b.f-1.py311.nbi", "b.f-1.py311.nbc", "b.cpython-311.pyc"):
        (cached / name).write_text("x")
    assert drop_stale_kernels({}, pkg) == 2  # no stamp yet: cached before the check existed
    assert [p.name for p in cached.iterdir()] == ["b.cpython-311.pyc"]
    assert (pkg / "__pycache__" / STAMP).exists()
    (cached / "b.f-1.py311.nbi").write_text("x")
    assert drop_stale_kernels({}, pkg) == 0  # nothing changed: kept
    assert (cached / "b.f-1.py311.nbi").exists()
    (pkg / "sub" / "b.py").write_text("X = 22\n")
    assert drop_stale_kernels({}, pkg) == 1
    assert not (cached / "b.f-1.py311.nbi").exists()


def test_a_cache_elsewhere_is_left_to_numba(tmp_path):
    pkg = package(tmp_path)
    (pkg / "sub" / "__pycache__" / "b.f-1.py311.nbi").write_text("x")
    assert drop_stale_kernels({"NUMBA_CACHE_DIR": str(tmp_path / "nb")}, pkg) == 0
    assert (pkg / "sub" / "__pycache__" / "b.f-1.py311.nbi").exists()


CALLER = """
import numba
from pkg.sub.b import g

@numba.njit(cache=True)
def f():
    return g() + 1
"""


def run_caller(root: Path, drop: bool) -> str:
    code = textwrap.dedent(f"""
        import sys
        from pathlib import Path
        sys.path.insert(0, {str(root)!r})
        from swarmex._jitcache import drop_stale_kernels
        if {drop}:
            drop_stale_kernels({{}}, Path({str(root / "pkg")!r}))
        from pkg.a import f
        print(f())
    """)
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, timeout=120, check=True)
    return out.stdout.strip()


def test_a_changed_callee_in_another_file_is_compiled_again(tmp_path):
    # with numba itself: a kernel loaded from the cache ran its callee's old code
    pkg = package(tmp_path)
    (pkg / "a.py").write_text(CALLER)
    callee = pkg / "sub" / "b.py"
    callee.write_text("import numba\n\n@numba.njit(cache=True)\ndef g():\n    return 1\n")
    assert run_caller(tmp_path, drop=False) == "2"
    callee.write_text("import numba\n\n@numba.njit(cache=True)\ndef g():\n    return 10\n")
    assert run_caller(tmp_path, drop=False) == "2"  # numba's own check: stale
    assert run_caller(tmp_path, drop=True) == "11"


def test_an_unreadable_entry_does_not_break_the_stamp(tmp_path):
    # an editor's lock file (Emacs: a dangling link named .#b.py) matches *.py
    pkg = package(tmp_path)
    (pkg / "sub" / ".#b.py").symlink_to(tmp_path / "user@host.1:1700000000")
    assert drop_stale_kernels({}, pkg) == 0
    (pkg / "sub" / "b.py").write_text("X = 3\n")
    (pkg / "sub" / "__pycache__" / "b.f-1.py311.nbi").write_text("x")
    assert drop_stale_kernels({}, pkg) == 1


def test_a_process_older_than_its_sources_gets_a_private_cache(tmp_path, monkeypatch):
    # imported before a source changed, first kernel after: its code in memory is old, so it
    # must neither vouch for the shared cache (the stamp) nor store into it
    from swarmex import _jitcache

    pkg = package(tmp_path)
    drop_stale_kernels({}, pkg)
    marker = (pkg / "__pycache__" / STAMP).read_text()
    monkeypatch.setattr(_jitcache, "IMPORTED", _jitcache.source_stamp(pkg))
    monkeypatch.setenv("NUMBA_CACHE_DIR", "")  # so that the test's choice is undone after
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    config = sys.modules.get("numba.core.config")
    if config is not None:  # numba already loaded: its own setting is undone too
        monkeypatch.setattr(config, "CACHE_DIR", config.CACHE_DIR)
    kept = pkg / "sub" / "__pycache__" / "b.f-1.py311.nbi"
    kept.write_text("x")
    assert _jitcache.check_kernel_cache(pkg) is None  # sources as imported: shared cache
    assert kept.exists()
    (pkg / "sub" / "b.py").write_text("X = 4\n")  # changed after the import
    private = _jitcache.check_kernel_cache(pkg)
    assert private is not None and os.environ["NUMBA_CACHE_DIR"] == private
    assert (pkg / "__pycache__" / STAMP).read_text() == marker and kept.exists()
