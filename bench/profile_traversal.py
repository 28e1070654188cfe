"""Where a traversal run's CPU time goes: cProfile on CPU time (not wall time).

The machine is shared, so the profiler's clock is ``time.process_time``: other jobs' load
does not show up as time spent in a function. Runs one warm-up on a small walled map first
(numba compiles or loads its kernels there), then profiles the chosen case and prints the
run's CPU time, its fingerprint and the functions with the largest own time.

    PYTHONPATH=src .venv/bin/python bench/profile_traversal.py                # den520d, 16 agents
    PYTHONPATH=src .venv/bin/python bench/profile_traversal.py --case empty --side 512 --agents 32

Run it with another tree's ``src`` on ``PYTHONPATH`` to profile that code the same way.
"""

from __future__ import annotations

import cProfile
import pstats
import time

import numpy as np

import _cli
from swarmex.missions.traversal import run_traversal, uniform_agents
from swarmex.missions.traversal.metrics import run_fingerprint
from swarmex.worlds import empty_grid, load_movingai, random_obstacles

maps_dir = _cli.maps_dir  # $SWARMEX_MAPS, default ../shared/maps


def main() -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", choices=("den520d", "empty"), default="den520d")
    ap.add_argument("--side", type=_cli.positive_int, default=512,
                    help="empty grid side (--case empty)")
    ap.add_argument("--agents", type=_cli.positive_int, default=16)
    ap.add_argument("--top", type=_cli.positive_int, default=15, help="functions to list")
    args = ap.parse_args()
    warm = random_obstacles(24, 24, 0.2, seed=0)
    run_traversal(warm, uniform_agents([int(np.flatnonzero(~warm.blocked)[0])] * 3, 1.0, 1.0))
    if args.case == "den520d":
        path = maps_dir() / "den520d.map"
        if not path.exists():
            print(f"SKIP: {path} not found (set SWARMEX_MAPS)")
            return 0
        world = load_movingai(path)
        free = np.flatnonzero(~world.blocked)
        specs = uniform_agents([int(free[free.size // 2])] * args.agents, 1.0, 1.0)
        seed = 0
    else:
        world = empty_grid(args.side, args.side)
        rng = np.random.default_rng(5)
        nests = [int(v) for v in rng.choice(world.graph.n_nodes, 4, replace=False)]
        specs = uniform_agents([nests[i % 4] for i in range(args.agents)], 2.22, 10.0)
        seed = 5
    prof = cProfile.Profile(time.process_time)
    c0 = time.process_time()
    prof.enable()
    run = run_traversal(world, specs, seed=seed)
    prof.disable()
    print(f"{args.case}: CPU {time.process_time() - c0:.2f} s (profiled), fingerprint "
          f"{run_fingerprint(run)[:16]}")
    pstats.Stats(prof).sort_stats("tottime").print_stats(args.top)
    return 0


if __name__ == "__main__":
    _cli.run(main)
