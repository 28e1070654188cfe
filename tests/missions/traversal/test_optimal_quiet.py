"""``algorithm="optimal"`` prints nothing: HiGHS's banner, written by its first instance in a
process straight to file descriptor 1, used to land in a library user's stdout and before
``swarmex traverse --algorithm optimal``'s summary."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

SRC = str(Path(__file__).resolve().parents[3] / "src")


def test_optimal_run_writes_nothing_to_stdout() -> None:
    code = ("import swarmex; r = swarmex.run('traversal', grid='3x3', agents=2,"
            " algorithm='optimal'); print('done', r.complete)")
    env = {**os.environ, "PYTHONPATH": SRC}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=env)
    assert out.stdout == "done True\n"
    assert "HiGHS" not in out.stderr
