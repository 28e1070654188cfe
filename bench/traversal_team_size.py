"""How the traversal methods' makespan and CPU grow with the team, on one generated map.

The comparisons of docs/traversal-variants.md use 16 agents. A user with a larger swarm
wants to know whether a method still pays and what it costs: madgta-k's partition and
madgta-f's end-game plan work over every agent's route. For each team size this runs every
algorithm on the same random map (``--side`` cells square, ``--density`` walls, generator
seed 1) from the same random nests (seeded by the team size), one process, and prints the
makespan against MADGTA's and the CPU seconds with their ratio to MADGTA's run in the same
process (seeds 0 .. ``--seeds`` − 1; the ratio of the summed CPU), and the messages and
kilobytes sent per run (madgta-s's plan messages grow with the team).

Before the table every algorithm runs once on a tiny walled map (8 × 8, 3 agents; about a
second in all), untimed: numba compiles or loads its kernels there. Without it, the first
timed run of the first algorithm (MADGTA, the ratios' denominator) paid numba's one-time load
(0.4 s against 0.03 s for a warm run on the 24 × 24 map), which inflated MADGTA's CPU and
deflated every "CPU / MADGTA's" ratio.

    .venv/bin/python bench/traversal_team_size.py                       # ~8 min
    .venv/bin/python bench/traversal_team_size.py --agents 16 --side 48 --seeds 1
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import _cli

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gap_traversal_optimal import check_algorithms, online_policy  # noqa: E402
from swarmex.missions.traversal import run_metrics, run_traversal, uniform_agents  # noqa: E402
from swarmex.worlds import random_obstacles  # noqa: E402


def warm_up(algorithms: list[str]) -> None:
    """Run every algorithm once on a tiny walled map, so numba's one-time load of the kernels
    (compiling them, or reading them from its disk cache) is paid outside the timed runs, as
    bench_traversal_den520d.py and profile_traversal.py do."""
    warm = random_obstacles(8, 8, 0.2, seed=0)
    nests = [int(v) for v in np.flatnonzero(~warm.blocked)[:3]]
    for alg in algorithms:
        run_traversal(warm, uniform_agents(nests, 2.0, 9.0), online_policy(alg), seed=0)


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--side", type=_cli.positive_int, default=96)
    ap.add_argument("--density", type=float, default=0.2)
    ap.add_argument("--agents", type=_cli.positive_int, nargs="+", default=[16, 32, 64])
    ap.add_argument("--seeds", type=_cli.positive_int, default=2)
    ap.add_argument("--algorithms", nargs="+",
                    default=["madgta", "madgta-k@tip_per_agent=60", "madgta-f"])
    args = ap.parse_args(argv)
    if not 0.0 <= args.density < 1.0:
        ap.error(f"--density must be in [0, 1), got {args.density}")
    algorithms = list(dict.fromkeys(["madgta", *args.algorithms]))
    check_algorithms(algorithms)
    world = random_obstacles(args.side, args.side, args.density, seed=1)
    free = np.nonzero(~world.blocked)[0]
    if max(args.agents) > free.size:  # every team skipped printed an empty table, exit 0
        ap.error(f"--agents {max(args.agents)}: more than the {free.size} free cells of"
                 f" --side {args.side}")
    warm_up(algorithms)
    print(f"{args.side}x{args.side}, {args.density:.0%} walls, {free.size} free cells; "
          f"seeds 0-{args.seeds - 1}")
    print("| agents | algorithm | mean makespan | against MADGTA | CPU s per run "
          "| CPU / MADGTA's | messages per run | kB per run |")
    print("|---|---|---|---|---|---|---|---|")
    for m in args.agents:
        if m > free.size:
            print(f"skipping {m} agents: more than the {free.size} free cells", file=sys.stderr)
            continue
        rng = np.random.default_rng([m, 17])
        agents = uniform_agents([int(v) for v in rng.choice(free, m, replace=False)], 2.0, 9.0)
        makespan: dict[str, list[float]] = {}
        cpu: dict[str, float] = {}
        for alg in algorithms:
            makespan[alg], cpu[alg], sent, size = [], 0.0, 0, 0
            for seed in range(args.seeds):
                t = time.process_time()
                run = run_traversal(world, agents, online_policy(alg), seed=seed)
                cpu[alg] += time.process_time() - t
                makespan[alg].append(run_metrics(run, 1.0)[0]["max_total_time"])
                sent, size = sent + run.messages, size + run.message_bytes
            rel = np.array(makespan[alg]) / np.array(makespan["madgta"]) - 1.0
            print(f"| {m} | {alg} | {np.mean(makespan[alg]):.1f} | {100 * rel.mean():+.2f} % "
                  f"| {cpu[alg] / args.seeds:.2f} | {cpu[alg] / cpu['madgta']:.1f}x "
                  f"| {sent / args.seeds:.0f} | {size / args.seeds / 1000:.0f} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    _cli.run(main)
