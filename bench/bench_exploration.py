"""Exploration speed: the thesis's world, full exploration, against the issue's 15 s target.

20 × 20 m at 5 cm (400 × 400 cells), 10 robots, 2 m laser, 10 m radio, the thesis's
greedy-exclusion strategy, seed 0. Prints the simulated steps, wall and CPU seconds, the
ratio wall / 15 s (≤ 1 meets the target), and where the CPU time went. The machine is
shared, so the CPU time of this process is printed too: it is what the code costs, while
wall time also counts other people's jobs.

    .venv/bin/python bench/bench_exploration.py [--robots 10] [--strategy NAME] [--profile]
"""

from __future__ import annotations

import cProfile
import os
import pstats
import time

import _cli
from swarmex.missions.exploration import ExplorationParams, run_exploration
from swarmex.worlds.metric import empty_metric

TARGET_SECONDS = 15.0


def main() -> None:
    ap = _cli.Parser()
    ap.add_argument("--robots", type=_cli.positive_int, default=10)
    ap.add_argument("--strategy", default="greedy-exclusion")
    ap.add_argument("--seed", type=_cli.nonneg_int, default=0)
    ap.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    grid = empty_metric(20, 20, 0.05)
    params = ExplorationParams(
        robots=args.robots, laser_range=2.0, comm_range=10.0, strategy=args.strategy,
        seed=args.seed,
    )
    # warm-up: load the compiled kernels (numba cache) outside the timed run
    run_exploration(empty_metric(1, 1, 0.05), ExplorationParams(robots=1, laser_range=0.3))
    prof = cProfile.Profile() if args.profile else None
    w0, c0 = time.perf_counter(), time.process_time()
    if prof:
        prof.enable()
    run = run_exploration(grid, params)
    if prof:
        prof.disable()
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"world 400x400 cells (20x20 m at 5 cm), {args.robots} robots, laser 2 m, comm 10 m, "
          f"{args.strategy}, seed {args.seed}")
    print(f"complete={run.complete} steps={run.makespan} "
          f"explored={run.explored_fraction():.4f}")
    print(f"wall {wall:.2f} s   cpu {cpu:.2f} s   load average {load:.1f} on {os.cpu_count()} "
          f"cores")
    print(f"target {TARGET_SECONDS:.0f} s: wall ratio {wall / TARGET_SECONDS:.2f}, "
          f"cpu ratio {cpu / TARGET_SECONDS:.2f} (<= 1 meets the target)")
    print(f"per simulated step: {1000 * cpu / max(run.makespan, 1):.1f} ms cpu")
    if prof:
        pstats.Stats(prof).sort_stats("tottime").print_stats(15)


if __name__ == "__main__":
    _cli.run(main)
