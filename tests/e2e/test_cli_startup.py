"""Start-up of the command line (issue 14 item 4): what ``swarmex --help`` imports, the lazy
command index, the compile notice, and the on-disk kernel cache from a fresh process.

These tests look at *what happens* (modules imported, compile events, cache files), not at
wall time, which the machine's load would make flaky; bench/bench_startup.py times it.
"""

from __future__ import annotations

import inspect
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import swarmex
from swarmex import _jitcache
from swarmex.cli import main
from swarmex.cli.app import INDEX, load, load_all

SRC = Path(swarmex.__file__).resolve().parents[1]
# what `swarmex --help` must not import: the heavy libraries and swarmex's kernels and surfaces
HEAVY = ("matplotlib", "numba", "llvmlite", "scipy", "shapely", "networkx", "zmq", "starlette",
         "uvicorn", "pyarrow", "imageio", "PIL")
HEAVY_OURS = ("swarmex.planning", "swarmex.sensing", "swarmex.worlds", "swarmex.viz",
              "swarmex.net", "swarmex.studies", "swarmex.experiments", "swarmex.cli.commands_")


def _python(code: str, env: dict[str, str | None] | None = None, cwd: Path | None = None):
    full = {**os.environ, "PYTHONPATH": str(SRC), **(env or {})}
    full = {k: v for k, v in full.items() if v is not None}  # None: unset
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=full, cwd=cwd, timeout=240)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_help_imports_no_heavy_module():
    """`python -X importtime -m swarmex --help` lists every module the process imported."""
    proc = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "swarmex", "--help"],
        capture_output=True, text=True, timeout=120,
        env={**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "120"},
    )
    assert proc.returncode == 0, proc.stderr
    imported = {line.split("|")[-1].strip() for line in proc.stderr.splitlines()
                if line.startswith("import time:")}
    assert "swarmex.cli" in imported  # the listing is real
    heavy = sorted(m for m in imported if m.split(".")[0] in HEAVY or m.startswith(HEAVY_OURS))
    assert heavy == [], heavy
    listed = {line.strip("│ ").split(" ")[0] for line in proc.stdout.splitlines()}
    for name, entry in INDEX.items():  # and every visible command is listed
        assert (name in listed) != entry.hidden, name


def _imported(argv: list[str], cwd: Path) -> tuple[list[str], str]:
    """Modules a fresh ``python -X importtime -m swarmex ARGV`` imported, in order."""
    proc = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "swarmex", *argv],
        capture_output=True, text=True, timeout=240, cwd=cwd,
        env={**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "120"},
    )
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.startswith("import time:")]
    return [line.split("|")[-1].strip() for line in lines], proc.stdout


def test_demo_imports_no_numba_and_no_surface_it_does_not_use(tmp_path):
    """`swarmex demo` runs its 256-cell map with the kernels interpreted (swarmex._kernels):
    no numba, llvmlite or scipy.linalg; no monitor, network or study code; matplotlib only
    for the picture, after the run (its options and help need none of it). The picture is
    the one this process draws from its own (compiled) run."""
    out = tmp_path / "demo.png"
    order, stdout = _imported(["demo", "--out", str(out)], tmp_path)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "complete" in stdout
    from swarmex.missions.base import FrameList
    from swarmex.missions.registry import get
    from swarmex.missions.traversal.mission import demo_world
    from swarmex.missions.traversal.params import TraversalParams
    from swarmex.viz.traversal import render_traversal

    prepared, frames = demo_world(), FrameList()
    outcome = get("traversal").execute(
        TraversalParams(agents=len(prepared.nests), seed=0), prepared, frames)
    here = render_traversal(outcome.record.to_dict(), outcome.world, tmp_path / "here.png",
                            frames)
    assert here.read_bytes() == out.read_bytes()
    unwanted = ("numba", "llvmlite", "starlette", "uvicorn", "zmq", "pyarrow", "imageio")
    heavy = sorted(m for m in order if m.split(".")[0] in unwanted
                   or m.startswith(("scipy.linalg", "swarmex.viz.monitor", "swarmex.net",
                                    "swarmex.studies", "swarmex.experiments")))
    assert heavy == [], heavy
    assert "swarmex.missions.traversal.policies" in order and "matplotlib" in order
    assert order.index("swarmex.viz.traversal") > order.index("swarmex.missions.traversal.sim")
    helped, _ = _imported(["demo", "--help"], tmp_path)  # loads the mission's Params only
    drawing = {"matplotlib", "numba", "llvmlite", "scipy", "imageio", "PIL", *unwanted}
    assert not [m for m in helped if m.split(".")[0] in drawing]


def test_the_index_says_what_the_commands_say():
    """Each index entry's help and hidden flag are its command's; no command is missing."""
    import typer

    load_all()
    built = typer.main.get_group(swarmex.cli.app).commands
    assert list(built) == list(INDEX)  # the same commands, listed in the same order
    for name, entry in INDEX.items():
        command = load(name)
        first = inspect.cleandoc(command.short_help or command.help or "").split("\n\n")[0]
        assert " ".join(first.split()) == entry.help, name
        assert command.hidden == entry.hidden, name
        assert command.params or getattr(command, "commands", None), name  # the real one


def test_a_command_is_loaded_only_when_used(capsys):
    """The help of one command loads its module (its options come from the Params)."""
    assert main(["demo", "--help"]) == 0
    out = capsys.readouterr().out
    assert "--out" in out and "--seed" in out
    assert main(["nosuch"]) == 2
    assert main(["travers"]) == 2
    assert "Did you mean 'traverse'?" in capsys.readouterr().err


def test_compile_notice_only_when_numba_compiles(capsys):
    """A compile inside the block prints the one line; a cached kernel prints nothing."""
    import numba

    from swarmex.cli import compiling
    from swarmex.cli.app import err_console

    compiling._said = False

    @numba.njit  # a fresh dispatcher: its first call compiles
    def twice(x):
        return 2 * x

    with compiling.compile_notice(err_console):
        assert twice(3) == 6
        assert twice(4) == 8  # already compiled: no second line
    err = capsys.readouterr().err
    assert err.splitlines() == [f"swarmex: {compiling.MESSAGE}"]
    with compiling.compile_notice(err_console):
        assert twice(5) == 10
    assert capsys.readouterr().err == ""


KERNEL_RUN = """
import json, os
import swarmex
from swarmex.planning.distance import _bfs_lattice, distance_field
from swarmex.worlds import empty_grid
d = distance_field(empty_grid(5, 4).graph, 0)
print(json.dumps({"dir": os.environ.get("NUMBA_CACHE_DIR"), "far": float(d.max()),
                  "hits": sum(_bfs_lattice.stats.cache_hits.values()),
                  "misses": sum(_bfs_lattice.stats.cache_misses.values())}))
"""


def _run_kernel(env: dict[str, str | None], cwd: Path) -> dict:
    import json

    return json.loads(_python(KERNEL_RUN, env, cwd).strip().splitlines()[-1])


def test_cache_survives_the_process(tmp_path):
    """A second process loads the kernel from the disk cache instead of compiling it."""
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    first = _run_kernel(env, tmp_path)
    second = _run_kernel(env, tmp_path)
    assert first["far"] == second["far"] == 7.0
    assert first["misses"] == 1 and second == {**first, "hits": 1, "misses": 0}
    assert list((tmp_path / "cache").rglob("distance._bfs_lattice-*.nbi"))


def test_unwritable_install_and_home_fall_back_to_a_temp_cache(tmp_path):
    """A read-only install without a writable home: numba alone would raise "cannot cache
    function" while importing the kernels; swarmex points it at a folder in TMPDIR.

    (The tests may run as root, for whom permission bits mean nothing, so "unwritable" is
    made of files standing where numba wants folders.)"""
    copy = tmp_path / "site" / "swarmex"
    shutil.copytree(SRC / "swarmex", copy, ignore=shutil.ignore_patterns("__pycache__"))
    for folder in [copy, *(p for p in copy.rglob("*") if p.is_dir())]:
        (folder / "__pycache__").write_text("not a folder")
    blocker = tmp_path / "home-is-a-file"
    blocker.write_text("")
    temp = tmp_path / "tmp"
    temp.mkdir()
    env = {"PYTHONPATH": str(copy.parent), "HOME": str(blocker), "XDG_CACHE_HOME": None,
           "TMPDIR": str(temp), "NUMBA_CACHE_DIR": None}
    first = _run_kernel(env, tmp_path)
    assert first["dir"] == str(temp / f"swarmex-numba-cache-{os.getuid()}")
    assert first["far"] == 7.0 and first["misses"] == 1
    assert _run_kernel(env, tmp_path)["hits"] == 1  # and the fallback is a real cache


def test_fallback_rules(tmp_path):
    """The user's NUMBA_CACHE_DIR wins; numba's defaults are kept while one is writable."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    file = tmp_path / "f"
    file.write_text("")
    home_ok = {"HOME": str(tmp_path / "home")}
    home_bad = {"HOME": str(file)}
    choose = _jitcache.fallback_cache_dir
    assert choose({"NUMBA_CACHE_DIR": "/x", **home_bad}, file / "pkg", tmp_path) is None
    assert choose(home_bad, pkg, tmp_path) is None  # in-tree __pycache__ can be made
    assert choose(home_ok, file / "pkg", tmp_path) is None  # ~/.cache/numba can be made
    got = choose(home_bad, file / "pkg", tmp_path)
    assert got is not None and got.parent == tmp_path
    assert choose(home_bad, file / "pkg", file) is None  # nothing writable: numba decides
    assert _jitcache.writable(tmp_path / "a" / "b") and not _jitcache.writable(file / "a")
    assert _jitcache.user_cache_dir({"XDG_CACHE_HOME": str(tmp_path)}) == tmp_path / "numba"
    assert _jitcache.user_cache_dir({"HOME": str(file)}) == file / ".cache" / "numba"


@pytest.mark.parametrize("argv", [["--help"], []])
def test_help_and_no_arguments_exit_0(argv, capsys):
    assert main(argv) == 0


def test_console_entry_leaves_with_its_output_and_status(tmp_path):
    """`python -m swarmex` ends through cli.leave (no interpreter finalisation): everything
    printed arrives, files are complete, the exit status is the command's."""
    env = {**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "400"}  # no wrapped paths
    out = tmp_path / "d.png"
    proc = subprocess.run([sys.executable, "-m", "swarmex", "demo", "--out", str(out)],
                          capture_output=True, text=True, env=env, timeout=240, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.rstrip().endswith(f"wrote {out}")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 1000
    bad = subprocess.run([sys.executable, "-m", "swarmex", "traverse", "--grid", "0x3",
                          "--agents", "1"],
                         capture_output=True, text=True, env=env, timeout=120, cwd=tmp_path)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--grid" in bad.stderr


def test_a_ctrl_c_during_the_exit_clean_ups_leaves_at_once_without_a_traceback(tmp_path):
    """A terminal often sends Ctrl-C twice; the second, landing in an atexit clean-up (a
    pool's, a weakref finaliser), printed "Exception ignored in atexit callback" and a
    traceback after the command's last line (seen as a CI flake of the sweep's Ctrl-C test).
    It now ends the process at once, with the command's status."""
    import signal
    import time

    script = tmp_path / "slow_exit.py"
    script.write_text(
        "import atexit, sys, time\n"
        "from swarmex.cli import leave\n"
        "atexit.register(lambda: time.sleep(20))\n"
        "print('cleaning up', flush=True)\n"
        "leave(130)\n"
    )
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert proc.stdout is not None and proc.stdout.readline() == "cleaning up\n"
        time.sleep(0.5)  # inside the clean-up's sleep
        t0 = time.monotonic()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=10)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and time.monotonic() - t0 < 5
    assert "Traceback" not in err and "Exception ignored" not in err, err
