"""Roadmap speed against the issue's goals: WMA-RRT construction of 800 nodes ≤ 0.2 s, a full
3-agent coverage run with 800 nodes ≤ 2 s.

On the reproduction's Fig. 8 environment (640 × 480, 13 obstacles), 3 agents in the default
lower-left cluster, seeds 0..R-1; medians over the seeds. "Full run" = build the roadmap, run
the behaviour to its end (every branch COMPLETE), sweep the line-of-sight sensor along every
traversed segment on the 256-cell raster, i.e. exactly what ``swarmex roadmap`` computes
before writing the record. Compiled kernels are loaded in a warm-up first. The machine is
shared, so the CPU time of this process is printed beside wall time: CPU is what the code
costs, wall also counts other people's jobs.

    .venv/bin/python bench/bench_roadmap.py [--repeats 5] [--profile]
"""

from __future__ import annotations

import cProfile
import math
import os
import pstats
import time

import numpy as np

import _cli
from swarmex.missions.roadmap import run_roadmap
from swarmex.missions.roadmap.starts import default_starts
from swarmex.planning.prm import build_prm
from swarmex.planning.rrt_wma import build_wma_rrt
from swarmex.studies.roadmap.design import R_BASE, world

BUILD_GOAL = 0.2
RUN_GOAL = 2.0


def timed(fn, repeats: int) -> tuple[float, float, object]:
    walls, cpus, out = [], [], None
    for seed in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        out = fn(seed)
        walls.append(time.perf_counter() - w0)
        cpus.append(time.process_time() - c0)
    return float(np.median(walls)), float(np.median(cpus)), out


def line(name: str, wall: float, cpu: float, goal: float | None, extra: str = "") -> None:
    ratio = f"  wall/goal {wall / goal:5.2f}  cpu/goal {cpu / goal:5.2f}" if goal else ""
    print(f"{name:<46} wall {wall:7.3f} s  cpu {cpu:7.3f} s{ratio}  {extra}")


def main() -> None:
    ap = _cli.Parser()
    ap.add_argument("--repeats", type=_cli.positive_int, default=5)
    ap.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    w = world("fig8")
    starts = default_starts(w, 3)
    # warm-up: numba kernels from their cache, shapely/GEOS first calls
    run_roadmap(w, starts, nodes=50, step=20, sensor_range=math.inf, seed=0)
    run_roadmap(w, starts, planner="prm", nodes=50, step=20, sensor_range=R_BASE, seed=0)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"Fig. 8 environment 640x480, 3 agents, medians over {args.repeats} seeds; "
          f"load average {load:.1f} on {os.cpu_count()} cores; goals: build {BUILD_GOAL} s, "
          f"full run {RUN_GOAL} s (ratio <= 1 meets the goal)")
    for step in (20.0, 40.0):
        wall, cpu, rm = timed(lambda s, st=step: build_wma_rrt(
            w, starts, 800, st, np.random.default_rng(s)), args.repeats)
        line(f"WMA-RRT build, 800 nodes, step {step:g}", wall, cpu, BUILD_GOAL,
             f"({rm.samples} samples)")
    wall, cpu, _ = timed(lambda s: build_prm(w, starts, 800, 20.0, np.random.default_rng(s)),
                         args.repeats)
    line("PRM build, 800 nodes, step 20 (baseline)", wall, cpu, None)
    for step in (20.0, 40.0):
        for rng_r, label in ((R_BASE, "r"), (math.inf, "inf")):
            wall, cpu, run = timed(lambda s, st=step, rr=rng_r: run_roadmap(
                w, starts, nodes=800, step=st, sensor_range=rr, seed=s), args.repeats)
            line(f"coverage run, 800 nodes, step {step:g}, range {label}", wall, cpu, RUN_GOAL,
                 f"({run.steps} steps, coverage {100 * run.raster.coverage():.1f}%)")
    wall, cpu, run = timed(lambda s: run_roadmap(
        w, starts, nodes=800, step=20, sensor_range=R_BASE, seed=s,
        planner="wma-rrt-takeover"), args.repeats)
    line("takeover coverage run, 800 nodes, step 20, r", wall, cpu, RUN_GOAL,
         f"({run.steps} steps)")
    wall, cpu, run = timed(lambda s: run_roadmap(
        w, starts, nodes=800, step=20, sensor_range=R_BASE, seed=s, planner="prm"),
        args.repeats)
    line("PRM coverage run (budget 1600 steps), step 20, r", wall, cpu, None,
         f"({run.roadmap.n_edges} edges)")
    if args.profile:
        prof = cProfile.Profile()
        prof.enable()
        run_roadmap(w, starts, nodes=800, step=20, sensor_range=math.inf, seed=0)
        prof.disable()
        pstats.Stats(prof).sort_stats("tottime").print_stats(12)


if __name__ == "__main__":
    _cli.run(main)
