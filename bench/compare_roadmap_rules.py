"""Compare the WMA-RRT edge rules on seed 004's environments, paired by seed (issue 17 item 4).

Rules: ``wma-rrt`` (the paper's), ``wma-rrt-takeover`` and ``wma-rrt-fairshare``
(swarmex.missions.roadmap.wma_policy). Every rule runs on the same tree: the same seed builds
the same WMA-RRT, so a row's difference is the rule's alone. Rows are the roadmap study's
(swarmex.studies.roadmap.design):

* ``coverage``: Table 1's (nodes, step) on the Fig. 8 environment; the measure is the steps
  until every branch is COMPLETE (the sensor range does not change a coverage run's moves,
  so one range stands for Table 1's four columns);
* ``search``: Table 2's rows on the Fig. 11 environment at ranges r, 2r, 4r, ∞; the measure is
  the step of the first sighting, or the run's steps when the goal was never seen (so a
  miss counts as the whole run, never as zero);
* ``unreach``: Figs. 14 and 17 (goal walled off / reachable from outside); the run's steps.

For each row and rule: mean over seeds, the ratio of means against ``wma-rrt``, and the mean
paired difference (rule − wma-rrt, same seed) with its Student-t 95 % interval. A row where
the interval lies above zero is a significant loss, below zero a significant gain.

    .venv/bin/python bench/compare_roadmap_rules.py                # 30 seeds, every row
    .venv/bin/python bench/compare_roadmap_rules.py --quick        # 5 seeds, r rows only
    .venv/bin/python bench/compare_roadmap_rules.py --seeds 10 --json out.json --jobs 2
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import dataclass

import numpy as np

import _cli
from swarmex.engine.stats import summarize
from swarmex.missions.registry import get
from swarmex.studies.roadmap.design import (
    AGENTS,
    MULTS,
    R_BASE,
    UNREACH_NODES,
    UNREACH_STEP,
    reference,
    world,
)

RULES = ("wma-rrt", "wma-rrt-takeover", "wma-rrt-fairshare")


@dataclass(frozen=True)
class Row:
    kind: str  # coverage | search | unreach
    env: str
    nodes: int
    step: float
    mult: str

    @property
    def label(self) -> str:
        return f"{self.kind} {self.env} {self.nodes}/{self.step:g} {self.mult}"


def rows(quick: bool) -> list[Row]:
    out: list[Row] = []
    cov = {(int(r["nodes"]), float(r["step"])) for r in reference("roadmap_table1.csv")}
    out += [Row("coverage", "fig8", n, s, "r") for n, s in sorted(cov, key=lambda c: (c[1], c[0]))]
    for r in reference("roadmap_table2.csv"):
        if quick and r["sensor_range"] != "r":
            continue
        out.append(Row("search", "fig11", int(r["nodes"]), float(r["step"]), r["sensor_range"]))
    out += [Row("unreach", env, UNREACH_NODES, UNREACH_STEP, "r") for env in ("fig14", "fig17")]
    return out


def measure(job: tuple[Row, str, int]) -> tuple[Row, str, int, float]:
    row, rule, seed = job
    task = "coverage" if row.kind == "coverage" else "search"
    mission = get("roadmap")
    params = mission.params(env=world(row.env), agents=AGENTS, nodes=row.nodes, step=row.step,
                            sensor_range=R_BASE * MULTS[row.mult], task=task, planner=rule,
                            seed=seed)
    m = mission.run(params, trace=False).record.metrics
    value = m["found_step"] if row.kind == "search" and m.get("goal_found") else m["steps"]
    return row, rule, seed, float(value)


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=_cli.paired_count, default=None,
                    help="seeds per row (30; --quick 5)")
    ap.add_argument("--quick", action="store_true", help="5 seeds, search at range r only")
    ap.add_argument("--jobs", type=_cli.positive_int, default=2, help="worker processes")
    ap.add_argument("--json", type=_cli.out_file, help="write every run's value here")
    args = ap.parse_args(argv)
    seeds = args.seeds or (5 if args.quick else 30)
    table = rows(args.quick)
    jobs = [(r, rule, s) for r in table for rule in RULES for s in range(seeds)]
    values: dict[tuple[Row, str], dict[int, float]] = {}
    t0 = time.perf_counter()
    with _cli.process_pool(args.jobs) as pool:
        for i, (row, rule, seed, v) in enumerate(pool.map(measure, jobs, chunksize=4), 1):
            values.setdefault((row, rule), {})[seed] = v
            if sys.stderr.isatty() and (i % 50 == 0 or i == len(jobs)):  # a terminal's line
                print(f"\r{i}/{len(jobs)} runs, {time.perf_counter() - t0:.0f} s", end="",
                      file=sys.stderr, flush=True)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    print(f"{seeds} seeds per row, {AGENTS} agents; Δ = rule − wma-rrt on the same seed, "
          "mean and Student-t 95 % interval\n")
    print("| row | wma-rrt | takeover | ratio | Δ takeover | fairshare | ratio | Δ fairshare |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for row in table:
        base = np.array([values[(row, "wma-rrt")][s] for s in range(seeds)])
        cells = [f"{base.mean():.0f}"]
        for rule in RULES[1:]:
            v = np.array([values[(row, rule)][s] for s in range(seeds)])
            d = summarize(v - base)
            cells += [f"{v.mean():.0f}", f"{v.mean() / base.mean():.2f}",
                      f"{d.mean:+.0f} [{d.ci_low:+.0f}, {d.ci_high:+.0f}]"]
        print(f"| {row.label} | " + " | ".join(cells) + " |")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump([{"row": r.label, "rule": rule, "values": [vals[s] for s in range(seeds)]}
                       for (r, rule), vals in values.items()], fh, indent=1)
    return 0


if __name__ == "__main__":
    _cli.run(main)
