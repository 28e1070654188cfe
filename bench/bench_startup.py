"""Start-up of the command line (issue 14 item 4), hyperfine-style: each command is run as a
fresh process several times and the wall and CPU (user + system, from ``wait4``) of each
run are kept; the table shows the median and the best.

Rows:

* ``python -c pass`` and ``import typer + rich`` - the floor, measured in the same run;
* ``swarmex --help`` (goal <= 0.3 s), with the ratio to the goal;
* ``swarmex demo``, second process: the kernels come from numba's disk cache
  (goal <= 1 s), with the ratio to the goal;
* ``swarmex demo``, first process: a fresh ``NUMBA_CACHE_DIR``, so every kernel compiles
  (once; the number of "compiling kernels" lines on stderr is shown, it must be 1).

Wall time suffers from other jobs on a shared machine; CPU time much less, so both are shown.

    PYTHONPATH=src .venv/bin/python bench/bench_startup.py [--runs 7] [--no-cold] [--src DIR]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
GOALS = {"swarmex --help": 0.3, "swarmex demo (warm cache)": 1.0}


def run_once(argv: list[str], env: dict[str, str], cwd: str) -> tuple[float, float, str]:
    """Wall seconds, CPU seconds (user + system of the child) and stderr of one run."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            cwd=cwd, text=True)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read() if proc.stderr else ""
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        raise SystemExit(f"{' '.join(argv)} exited {code}: {err.strip()[-300:]}")
    return wall, usage.ru_utime + usage.ru_stime, err


def measure(name: str, argv: list[str], runs: int, env: dict[str, str], cwd: str) -> dict:
    run_once(argv, env, cwd)  # warm-up: the OS file cache, numba's kernel cache
    samples = [run_once(argv, env, cwd) for _ in range(runs)]
    walls, cpus = [s[0] for s in samples], [s[1] for s in samples]
    return {"name": name, "wall": statistics.median(walls), "wall_min": min(walls),
            "cpu": statistics.median(cpus), "cpu_min": min(cpus), "runs": runs}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7, help="timed runs per command")
    ap.add_argument("--no-cold", action="store_true", help="skip the cold-cache demo")
    ap.add_argument("--src", type=Path, default=SRC,
                    help="the source tree to time (e.g. another checkout's src, to compare)")
    args = ap.parse_args()
    env = {**os.environ, "PYTHONPATH": str(args.src.resolve()), "COLUMNS": "100"}
    py = sys.executable
    with tempfile.TemporaryDirectory() as tmp:
        rows = [
            measure("python -c pass", [py, "-c", "pass"], args.runs, env, tmp),
            measure("import typer + rich", [py, "-c", "import typer.rich_utils"], args.runs,
                    env, tmp),
            measure("swarmex --help", [py, "-m", "swarmex", "--help"], args.runs, env, tmp),
            measure("swarmex demo (warm cache)", [py, "-m", "swarmex", "demo"], args.runs,
                    env, tmp),
        ]
        cold = None
        if not args.no_cold:
            cold_env = {**env, "NUMBA_CACHE_DIR": str(Path(tmp) / "numba-cache")}
            wall, cpu, err = run_once([py, "-m", "swarmex", "demo"], cold_env, tmp)
            lines = [line for line in err.splitlines() if "compiling kernels" in line]
            cold = (wall, cpu, len(lines))
    load = os.getloadavg()[0]
    print(f"start-up of {args.src}, {args.runs} runs each after one warm-up; load average "
          f"{load:.1f} on {os.cpu_count()} cores")
    print(f"{'command':28} {'wall med':>9} {'wall min':>9} {'cpu med':>8} {'cpu min':>8}"
          f" {'goal':>6} {'ratio':>6}")
    for r in rows:
        goal = GOALS.get(r["name"])
        ratio = f"{r['wall_min'] / goal:6.2f}" if goal else ""
        print(f"{r['name']:28} {r['wall']:9.3f} {r['wall_min']:9.3f} {r['cpu']:8.3f}"
              f" {r['cpu_min']:8.3f} {goal or '':>6} {ratio}")
    if cold is not None:
        print(f"{'swarmex demo (cold cache)':28} {cold[0]:9.3f} {'':9} {cold[1]:8.3f} {'':8}"
              f"  ({cold[2]} 'compiling kernels' line(s) on stderr)")
    print("ratio = best wall / goal (<= 1 meets it)")


if __name__ == "__main__":
    main()
