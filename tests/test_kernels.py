"""swarmex._kernels: kernels load numba on first compiled use, run interpreted in small
one-shot runs, and give the same results both ways.

Interpreted runs are checked in fresh processes (this one has numba loaded, and then kernels
always run compiled); the compiled side runs here, so every comparison crosses the two
routes. The golden records are the broader check: ``NUMBA_DISABLE_JIT=1`` (every kernel
interpreted) reproduces all of them.
"""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import swarmex
from swarmex import _kernels
from swarmex.planning import distance, hop_shift

SRC = Path(swarmex.__file__).resolve().parents[1]
KERNEL_MODULES = (
    "swarmex.planning.distance", "swarmex.planning.hop_shift", "swarmex.planning.hop_repair",
    "swarmex.planning.fieldcache", "swarmex.sensing.visibility",
    "swarmex.sensing.laser", "swarmex.sensing.frontiers", "swarmex.sensing.occupancy",
    "swarmex.missions.traversal.policies", "swarmex.missions.traversal.lattice",
    "swarmex.missions.traversal.rollout", "swarmex.missions.traversal.rollout_sim",
    "swarmex.missions.traversal.teamplan",
    "swarmex.missions.traversal.partition",
    "swarmex.missions.foraging.fastloop", "swarmex.missions.exploration.paths",
)


def _python(code: str, tmp_path: Path, **env: str) -> str:
    proc = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
        timeout=240, cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": f"{SRC}{os.pathsep}{tmp_path}", **env},
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout + proc.stderr


def test_importing_kernel_modules_loads_no_numba(tmp_path):
    code = f"""
    import importlib, sys
    for name in {KERNEL_MODULES!r}:
        importlib.import_module(name)
    print(sorted(m for m in sys.modules if m.split(".")[0] in ("numba", "llvmlite")
                 or m.startswith("scipy.linalg")))
    """
    assert _python(code, tmp_path).strip() == "[]"


DEMO = """
import json, sys
import swarmex
from swarmex._kernels import interpreted_while_cold, interpreting
from swarmex.missions.base import FrameList
from swarmex.missions.registry import get
from swarmex.missions.traversal.mission import demo_world
from swarmex.missions.traversal.params import TraversalParams

def run(seed):
    prepared = demo_world()
    params = TraversalParams(agents=len(prepared.nests), seed=seed)
    rec = get("traversal").execute(params, prepared, FrameList()).record.to_dict()
    rec.pop("wall_seconds")
    return rec
"""


@pytest.mark.parametrize("seed", [0, 5])
def test_demo_interpreted_equals_compiled(seed, tmp_path):
    """The demo's whole run with every kernel interpreted (and MADGTA's numpy route) gives
    the record of the compiled run; numba is never imported for it."""
    code = DEMO + f"""
with interpreted_while_cold():
    assert interpreting()
    rec = run({seed})
print(json.dumps({{"numba": "numba" in sys.modules, "rec": rec}}))
"""
    got = json.loads(_python(code, tmp_path).strip().splitlines()[-1])
    assert got["numba"] is False
    ns: dict = {}
    exec(DEMO, ns)
    import numba  # noqa: F401  (compiled here, whatever ran before)

    with _kernels.interpreted_while_cold():
        assert not _kernels.interpreting()  # numba is loaded: kernels run compiled
        compiled = json.loads(json.dumps(ns["run"](seed)))
    assert got["rec"] == compiled
    assert compiled["complete"] and compiled["metrics"]["nodes_missed"] == 0


MODULE = '''
import numpy as np
from swarmex._kernels import kernel

@kernel(cache=False, inline="always")
def twice(x):
    return 2 * x

@kernel(cache=False)
def plus_one(x):
    return x + 1

@kernel(cache=False, nogil=True)
def total(a):
    s = 0
    for v in a:
        s += plus_one(twice(v))
    return s
'''


def test_compiled_kernel_calls_kernels_and_shows_the_compile_notice(tmp_path):
    """A kernel compiled by numba calls other kernels (one inlined) through their Kernel
    objects; the compile notice, entered before numba was imported, still speaks."""
    (tmp_path / "kmod.py").write_text(MODULE)
    code = """
    import sys
    import numpy as np
    from rich.console import Console
    from swarmex.cli.compiling import MESSAGE, compile_notice
    import kmod
    assert "numba" not in sys.modules
    with compile_notice(Console(stderr=True)):
        got = kmod.total(np.arange(5))
    print("total", got, type(kmod.total.dispatcher).__name__, "numba" in sys.modules)
    """
    out = _python(code, tmp_path)
    assert "total 25 CPUDispatcher True" in out  # sum(2v + 1) for v in 0..4
    assert out.count("compiling kernels, first run only") == 1


def test_interpreted_only_while_cold(tmp_path):
    """Inside the block kernels run their Python until numba is imported; outside it a call
    loads numba, runs the waiting callbacks once, and from then on everything is compiled."""
    (tmp_path / "kmod.py").write_text(MODULE)
    code = """
    import sys
    import numpy as np
    from swarmex import _kernels
    import kmod
    calls = []
    _kernels.when_loaded(lambda: calls.append("loaded"))
    withdrawn = _kernels.when_loaded(lambda: calls.append("withdrawn"))
    withdrawn()
    with _kernels.interpreted_while_cold():
        a = kmod.total(np.arange(4))
        print("inside", a, _kernels.interpreting(), "numba" in sys.modules, calls)
    with _kernels.interpreted_while_cold(enabled=False):
        assert not _kernels.interpreting()
    b = kmod.total(np.arange(4))
    print("outside", b, "numba" in sys.modules, calls)
    with _kernels.interpreted_while_cold():
        print("after", _kernels.interpreting())
    _kernels.when_loaded(lambda: calls.append("late"))
    print(calls)
    """
    out = _python(code, tmp_path).splitlines()
    assert out[0] == "inside 16 True False []"
    assert out[1] == "outside 16 True ['loaded']"
    assert out[2] == "after False"
    assert out[3] == "['loaded', 'late']"  # a late callback runs at once


def test_cone_share_is_the_free_share_of_the_half_plane():
    """A shift's cone-size guess: the share of free vertices nearer (in lattice steps) to
    the new source than to the old one, checked against that definition per vertex."""
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(300):
        width = int(rng.integers(1, 30))
        height = int(rng.integers(1, 30))
        n = width * height
        free = rng.random(n) < rng.random()
        col_free, row_free = distance.free_counts(free, width)
        b = int(rng.integers(0, n))
        y, x = divmod(b, width)
        for dy, dx in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            if 0 <= y + dy < height and 0 <= x + dx < width:
                a = (y + dy) * width + x + dx
                vy, vx = np.divmod(np.flatnonzero(free), width)
                nearer = np.abs(vy - y - dy) + np.abs(vx - x - dx) < np.abs(vy - y) + np.abs(vx - x)
                want = nearer.sum() / free.sum() if free.any() else 0.0
                assert hop_shift._cone_share(width, a, b, col_free, row_free) == want
                checked += 1
    assert checked > 500


def _kernel(module: str, name: str) -> _kernels.Kernel:
    (k,) = [k for k in _kernels.kernels() if (k.__module__, k.__name__) == (module, name)]
    return k


def test_kernel_surface():
    """Kernels show their state and reach the dispatcher's attributes; once loaded, the
    names binding them in swarmex's modules are the dispatcher itself (no extra frame per
    call), and pickles made either way load back; a twin can only be given to a kernel."""
    from swarmex.planning import fieldcache

    k = _kernel("swarmex.planning.distance", "_bfs_hops_lattice")
    assert "planning.distance._bfs_hops_lattice" in repr(k)
    assert k.options == {"cache": True, "nogil": True}
    assert hasattr(k, "stats")  # the dispatcher's, loaded on demand
    assert distance._bfs_hops_lattice is k.dispatcher
    assert fieldcache._bfs_hops_lattice is k.dispatcher  # a `from ... import` binding too
    assert pickle.loads(pickle.dumps(k)) is k.dispatcher  # by reference: the module's name
    assert k.__wrapped__ is k.py_func and k.__doc__ == k.py_func.__doc__
    with pytest.raises(TypeError):
        _kernels.twin(len)(len)


def test_small_traverse_runs_interpreted_with_the_golden_records(tmp_path):
    """Every traversal golden scenario (all <= 400 vertices) through `swarmex traverse` in a
    fresh process: the kernels run interpreted, numba is never imported, and every record's
    digest is the golden one."""
    repo = SRC.parent
    code = f"""
    import json, os, sys
    sys.path.insert(0, {str(repo)!r})
    os.chdir({str(repo)!r})
    from tests.golden.make_golden import digest, run_cli
    from tests.golden.scenarios import SCENARIOS
    got = {{name: digest(run_cli(command, argv))
           for name, mission, command, argv in SCENARIOS if mission == "traversal"}}
    print(json.dumps({{"numba": "numba" in sys.modules, "got": got}}))
    """
    out = json.loads(_python(code, tmp_path).strip().splitlines()[-1])
    golden = json.loads((repo / "tests" / "golden" / "records.json").read_text())
    assert out["numba"] is False
    assert len(out["got"]) >= 7
    assert out["got"] == {name: golden[name]["sha256"] for name in out["got"]}


FORAGING = """
import hashlib, json, sys
from swarmex._kernels import interpreted_while_cold, interpreting
from swarmex.missions.foraging.sim import run_mission
from swarmex.missions.foraging.timed import timed_plan

RUNS = [("zigzag", 16, 16, (2, 13), "relay-path", "seed"),
        ("spiral", 12, 8, (11, 0), "end-to-end", "seed"),
        ("sectors", 16, 16, (3, 12), "relay-food", "seed"),
        ("hilbert", 16, 16, (12, 3), "relay-food", "omniscient")]

def runs():
    out = []
    for pattern, g, n, food, transport, rule in RUNS:
        o = run_mission(timed_plan(pattern, g, n), food, 8, transport, comm=rule)
        out.append([o.makespan, o.jobs, o.informed_at, o.comm_done, o.handovers,
                    hashlib.sha256(o.positions.tobytes()).hexdigest()])
    return json.loads(json.dumps(out))
"""


def test_foraging_kernels_interpreted_equal_compiled(tmp_path):
    """Plain foraging runs (the timetable, the compiled communication phase and transport
    tail) with every kernel interpreted, in a fresh process, give the compiled runs."""
    code = FORAGING + """
with interpreted_while_cold():
    assert interpreting()
    got = runs()
print(json.dumps({"numba": "numba" in sys.modules, "got": got}))
"""
    out = json.loads(_python(code, tmp_path).strip().splitlines()[-1])
    assert out["numba"] is False
    ns: dict = {}
    exec(FORAGING, ns)
    import numba  # noqa: F401  (compiled here, whatever ran before)

    assert out["got"] == ns["runs"]()
