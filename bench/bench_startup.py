"""Start-up of the command line (issue 14 item 4), hyperfine-style: each command is run as a
fresh process several times and the wall and CPU (user + system, from ``wait4``) of each
run are kept; the table shows the median and the best, the best wall as a ratio to the
goal and to ``python -c pass`` measured in the same run.

Rows:

* ``python -c pass`` and ``import typer + rich`` - the floor;
* ``swarmex --help`` (goal <= 0.3 s);
* ``swarmex demo``, second process (goal <= 1 s): its 256-cell run has the kernels
  interpreted (swarmex._kernels), so numba is not even imported;
* ``swarmex traverse --grid 16x16 --agents 4`` (256 vertices, interpreted too, no picture)
  and ``--grid 32x32`` (1,024 vertices: above the interpreted limit, so the kernels are
  compiled, loaded from numba's disk cache - the fixed cost the demo no longer pays);
* cold rows (unless ``--no-cold``): a fresh ``NUMBA_CACHE_DIR``. The demo compiles nothing;
  ``traverse --grid 32x32`` compiles its kernels once and says so in one "compiling
  kernels" line.

The children run without ``PYTHONDONTWRITEBYTECODE`` (the warm-up writes the ``.pyc`` files
an installed package has; without them every run would compile swarmex's sources, 0.1-0.2 s).
Wall time suffers from other jobs on a shared machine; CPU time much less, so both are shown.

    PYTHONPATH=src .venv/bin/python bench/bench_startup.py [--runs 7] [--no-cold] [--src DIR]
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import _cli

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
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=_cli.positive_int, default=7, help="timed runs per command")
    ap.add_argument("--no-cold", action="store_true", help="skip the cold-cache demo")
    ap.add_argument("--src", type=Path, default=SRC,
                    help="the source tree to time (e.g. another checkout's src, to compare)")
    args = ap.parse_args()
    if not (args.src / "swarmex" / "__init__.py").is_file():
        # else the children import whatever swarmex is installed and time the wrong tree
        ap.error(f"--src {args.src}: no swarmex package there (give a checkout's src folder)")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(PYTHONPATH=str(args.src.resolve()), COLUMNS="100")
    py = sys.executable
    swarmex = [py, "-m", "swarmex"]
    traverse = [*swarmex, "traverse", "--agents", "4", "--grid"]
    with tempfile.TemporaryDirectory() as tmp:
        rows = [
            measure("python -c pass", [py, "-c", "pass"], args.runs, env, tmp),
            measure("import typer + rich", [py, "-c", "import typer.rich_utils"], args.runs,
                    env, tmp),
            measure("swarmex --help", [*swarmex, "--help"], args.runs, env, tmp),
            measure("swarmex demo (warm cache)", [*swarmex, "demo"], args.runs, env, tmp),
            measure("traverse 16x16", [*traverse, "16x16"], args.runs, env, tmp),
            measure("traverse 32x32 (warm cache)", [*traverse, "32x32"], args.runs, env, tmp),
        ]
        cold = []
        if not args.no_cold:
            for name, argv in (("swarmex demo (cold cache)", [*swarmex, "demo"]),
                               ("traverse 32x32 (cold cache)", [*traverse, "32x32"])):
                cache = Path(tmp) / f"numba-cache-{len(cold)}"
                wall, cpu, err = run_once(argv, {**env, "NUMBA_CACHE_DIR": str(cache)}, tmp)
                lines = [line for line in err.splitlines() if "compiling kernels" in line]
                cold.append((name, wall, cpu, len(lines)))
    load = os.getloadavg()[0]
    floor = rows[0]["wall_min"]
    print(f"start-up of {args.src}, {args.runs} runs each after one warm-up; load average "
          f"{load:.1f} on {os.cpu_count()} cores")
    print(f"{'command':28} {'wall med':>9} {'wall min':>9} {'cpu med':>8} {'cpu min':>8}"
          f" {'goal':>6} {'/goal':>6} {'/pass':>6}")
    for r in rows:
        goal = GOALS.get(r["name"])
        ratio = f"{r['wall_min'] / goal:6.2f}" if goal else ""
        print(f"{r['name']:28} {r['wall']:9.3f} {r['wall_min']:9.3f} {r['cpu']:8.3f}"
              f" {r['cpu_min']:8.3f} {goal or '':>6} {ratio:>6} {r['wall_min'] / floor:6.1f}")
    for name, wall, cpu, lines in cold:
        print(f"{name:28} {wall:9.3f} {'':9} {cpu:8.3f} {'':8}"
              f"  ({lines} 'compiling kernels' line(s) on stderr)")
    print("/goal = best wall / goal (<= 1 meets it); /pass = best wall / `python -c pass`")


if __name__ == "__main__":
    _cli.run(main)
