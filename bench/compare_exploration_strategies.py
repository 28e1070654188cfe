"""Compare the exploration goal strategies on the study's scenarios, paired by seed (issue 17).

Scenarios are the exploration study's (swarmex.studies.exploration.design.SCENARIOS: open world
with a long and a short radio, room-32-32-4, warehouse-10-20-10-2-1, ost003d); every strategy
runs from the same starts with the same seeds. The measure is the makespan (steps until the
last robot finished; every run here maps all reachable free space, which the table checks).
For each scenario and strategy: mean ± sd, and the mean paired difference against the
thesis's ``greedy-exclusion`` (same seed) with its Student-t 95 % interval — an interval below
zero is a significant gain, above zero a significant loss.

Maps are read from ``SWARMEX_MAPS`` (default ``../shared/maps``); an absent map is skipped.

    .venv/bin/python bench/compare_exploration_strategies.py               # 10 seeds
    .venv/bin/python bench/compare_exploration_strategies.py --seeds 20 --only 1
    .venv/bin/python bench/compare_exploration_strategies.py --quick       # 3 seeds
"""

from __future__ import annotations

import json
import sys
import time
from typing import Any

import numpy as np

import _cli
from swarmex.engine.stats import summarize
from swarmex.missions.exploration.strategies import STRATEGIES
from swarmex.studies.exploration.design import SCENARIOS, STRATEGY_ORDER, maps_dir
from swarmex.studies.exploration.runs import run_job

BASE = "greedy-exclusion"


def one(job: dict[str, Any]) -> tuple[str, str, int, int, bool]:
    out = run_job(job)
    return job["scenario"], job["strategy"], job["seed"], out["makespan"], out["complete"]


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=_cli.paired_count, default=None,
                    help="seeds per cell (10; --quick 3)")
    ap.add_argument("--first-seed", type=_cli.nonneg_int, default=0,
                    help="seeds run from here (20 with --seeds 20: the held-out seeds 20-39)")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", help="comma-separated scenario indices (0-based)")
    ap.add_argument("--strategies", default=",".join(STRATEGY_ORDER))
    ap.add_argument("--jobs", type=_cli.positive_int, default=2)
    ap.add_argument("--json", type=_cli.out_file, help="write every run's makespan here")
    args = ap.parse_args(argv)
    seeds = args.seeds or (3 if args.quick else 10)
    seed_list = range(args.first_seed, args.first_seed + seeds)
    scenarios = SCENARIOS
    if args.only:
        scenarios = [SCENARIOS[i] for i in _cli.indices(args.only, len(SCENARIOS))]
    strategies = args.strategies.split(",")
    unknown = [st for st in strategies if st not in STRATEGIES]
    if unknown:  # before the pool: the base strategy's runs would come first
        ap.error(f"--strategies: unknown {', '.join(unknown)}; choose from {', '.join(STRATEGIES)}")
    if BASE not in strategies:
        strategies.insert(0, BASE)
    jobs = []
    for name, world, n, laser, comm in scenarios:
        if "map" in world and not (maps_dir() / world["map"]).exists():
            print(f"skipped {name}: {maps_dir() / world['map']} not found", file=sys.stderr)
            continue
        jobs += [{"kind": "strategy", "scenario": name, "world": world, "robots": n,
                  "laser": laser, "comm": comm, "strategy": st, "seed": s}
                 for st in strategies for s in seed_list]
    res: dict[str, dict[str, dict[int, tuple[int, bool]]]] = {}
    t0 = time.perf_counter()
    with _cli.process_pool(args.jobs) as pool:
        for i, (sc, st, seed, mk, ok) in enumerate(pool.map(one, jobs), 1):
            res.setdefault(sc, {}).setdefault(st, {})[seed] = (mk, ok)
            if sys.stderr.isatty():  # a progress line, not a log of carriage returns
                print(f"\r{i}/{len(jobs)} runs, {time.perf_counter() - t0:.0f} s", end="",
                      file=sys.stderr, flush=True)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    print(f"makespan in steps, mean ± sd over seeds {seed_list.start}-{seed_list.stop - 1}; "
          f"Δ = strategy − {BASE} on the same seed (mean [95 % CI])\n")
    print("| scenario | " + " | ".join(strategies) + " |")
    print("|---|" + "---:|" * len(strategies))
    for sc, by in res.items():
        base = np.array([by[BASE][s][0] for s in seed_list], dtype=float)
        cells = []
        for st in strategies:
            v = np.array([by[st][s][0] for s in seed_list], dtype=float)
            done = all(by[st][s][1] for s in seed_list)
            cell = f"{v.mean():.0f} ± {v.std(ddof=1) if seeds > 1 else 0:.0f}"
            if st != BASE:
                d = summarize(v - base)
                cell += f"<br>Δ {d.mean:+.0f} [{d.ci_low:+.0f}, {d.ci_high:+.0f}]"
            cells.append(cell + ("" if done else " (incomplete runs)"))
        print(f"| {sc} | " + " | ".join(cells) + " |")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({sc: {st: [by[st][s][0] for s in seed_list] for st in by}
                       for sc, by in res.items()}, fh, indent=1)
    return 0


if __name__ == "__main__":
    _cli.run(main)
