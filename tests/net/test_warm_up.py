"""An agent's warm-up compiles every kernel its mission will call, before it connects.

Why it matters: numba holds the GIL while it compiles, so an agent compiling at its first
decision sends no heartbeat, and the server declares it gone after ``--dead-after`` (2 s).
On a fresh install (a cold cache) the far choice of MADGTA's branch 3 compiled at the first
far decision (~3 s of CPU) and every agent of a hybrid mission "fell silent". The check runs
in a child with an empty numba cache, so kernels this test process already compiled cannot
hide a gap: after ``warm_up()`` (before the agent connects), MADGTA missions of the shapes
the tests and docs fly (walls, an open grid, one shared nest, own nests) must compile
nothing; and after ``warm_policy(name)`` (when the mission data names the algorithm), nor
must missions of every other served algorithm (madgta-r used to compile ~8 s of kernels at
its first end-game decision, madgta-p ~5 s).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"

CHILD = r"""
import json
import numpy as np
from numba.core import event

compiled = []

class Seen(event.Listener):
    def on_start(self, ev):
        compiled.append(str(ev.data.get("dispatcher")))
    def on_end(self, ev):
        pass

event.register("numba:compile", Seen())
from swarmex.missions.traversal.agents import uniform_agents
from swarmex.net.traversal import Mission, run_inprocess, warm_policy, warm_up
from swarmex.worlds import GridWorld

late = {}
walls = np.ones((6, 6), dtype=bool)
for x, y in [(2, 2), (3, 3), (4, 1)]:
    walls[y, x] = False
big = np.ones((16, 16), dtype=bool)  # 256 vertices: madgta-k's sweep before its end game
big[5, 3:12] = False
warm_up()
before = len(compiled)
for free, nests in ((walls, [0, 0, 0]), (np.ones((8, 7), dtype=bool), [0, 0, 0, 0]),
                    (walls, [0, 5, 30]), (big, [0, 0, 0])):
    run_inprocess(Mission(GridWorld(free), uniform_agents(nests, 2.22, 10.0), seed=7))
late["madgta"] = compiled[before:]
# a spec with options is warmed up as itself (its mission data names the spec)
for algorithm in ("madgta+", "madgta-r", "madgta-p", "madgta-p@ils=5,follow=walls",
                  "madgta-k", "madgta-f", "madgta-s", "nearest"):
    warm_policy(algorithm)  # what the agent does when the mission data names it
    before = len(compiled)
    for free in (walls, big):
        run_inprocess(Mission(GridWorld(free), uniform_agents([0, 0, 0], 2.22, 10.0), seed=7,
                              algorithm=algorithm))
    late[algorithm] = compiled[before:]
print(json.dumps(late))
"""


@pytest.mark.timeout(300)
def test_after_the_warm_up_a_mission_compiles_nothing(tmp_path: Path) -> None:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True,
                         text=True, timeout=280, check=True)
    late = json.loads(out.stdout.strip().splitlines()[-1])
    assert all(v == [] for v in late.values()), f"compiled after the warm-up: {late}"
