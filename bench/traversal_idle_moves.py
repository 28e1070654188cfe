"""Where a traversal's time goes: moves without a job before and in the end game.

For each (map, nests, seed, algorithm) it runs the mission as
bench/compare_traversal_variants.py does (16 identical agents, 2 s per edge, 9 s per job,
the same nests and seeds) and splits each agent's moves without a job
by phase: "end game" once at most ``--end`` jobs of the whole team are still to start (the
times are the agents' own logs). It prints the makespan, the mean finishing time and the
two counts (docs/traversal-variants.md §7, "Where the rest of
the time goes").

    .venv/bin/python bench/traversal_idle_moves.py --maps random-64-64-20 \\
        warehouse-10-20-10-2-1 room-32-32-4 --algorithms madgta madgta-f
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import _cli

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_traversal_variants import (  # noqa: E402
    NEST_MODES,
    fleet_for,
    load,
    map_name,
    nests_for,
)
from gap_traversal_optimal import check_algorithms, online_policy  # noqa: E402
from swarmex.missions.traversal import run_metrics, run_traversal  # noqa: E402


def idle_moves(run, end: int) -> tuple[float, int, int]:
    """(mean finishing time, moves without a job before the end game, in it), from the
    agents' logged times: a move without a job is an arrival where no job starts, and it is
    in the end game once at most ``end`` jobs are still to start."""
    starts = np.sort([t for agent in run.agents for t, _ in agent.jobs])
    idle = []
    for agent in run.agents:
        arrivals = agent.trajectory[1:]  # the first entry is the start
        # the path holds every arrival, and the start only when a job was done there
        steps = agent.path[len(agent.path) - len(arrivals):]
        idle += [t for (t, _), (_, job) in zip(arrivals, steps, strict=True) if not job]
    left = starts.size - np.searchsorted(starts, np.array(idle), side="right")
    before = int((left > end).sum())
    return float(np.mean([agent.finished_at for agent in run.agents])), before, len(idle) - before


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--maps", nargs="+", type=map_name,
                    default=["random-64-64-20", "warehouse-10-20-10-2-1", "room-32-32-4"])
    ap.add_argument("--algorithms", nargs="+", default=["madgta", "madgta-f"])
    ap.add_argument("--nests", nargs="+", choices=NEST_MODES, default=["shared"])
    ap.add_argument("--seeds", type=_cli.positive_int, default=1)
    ap.add_argument("--agents", type=_cli.positive_int, default=16)
    ap.add_argument("--end", type=_cli.positive_int, default=200,
                    help="jobs left when the end game starts (default 200, madgta-p's)")
    args = ap.parse_args(argv)
    check_algorithms(args.algorithms)
    print("| map | nests | seed | algorithm | makespan | mean finish "
          "| moves w/o job before the end game | in the end game |")
    print("|---|---|---|---|---|---|---|---|")
    for mp in args.maps:
        world = load(mp)
        if world is None:  # load() has said so
            continue
        for mode in args.nests:
            for seed in range(args.seeds):
                nests = nests_for(world, args.agents, mode, seed)
                for alg in args.algorithms:
                    run = run_traversal(world, fleet_for(nests, "same", seed),
                                        online_policy(alg), seed=seed)
                    makespan = run_metrics(run, 1.0)[0]["max_total_time"]
                    mean, before, during = idle_moves(run, args.end)
                    print(f"| {mp} | {mode} | {seed} | {alg} | {makespan:.0f} | {mean:.0f} "
                          f"| {before} | {during} |", flush=True)
    return 0


if __name__ == "__main__":
    _cli.run(main)
