"""Compare traversal policies on the real MovingAI maps, and MADGTA over imperfect channels.

Section 1 (``variants``): ``madgta``, ``madgta+`` (swarmex.missions.traversal.variants),
``madgta-h`` (swarmex.missions.traversal.madgta_h), ``madgta-r``
(swarmex.missions.traversal.rollout) and ``nearest`` on the same maps, agent counts, nests
and seeds. Algorithm names are those of bench/gap_traversal_optimal.py (``madgta-r@K=V,...``
for other settings, ``known:NAME`` with the whole map known from the start); the CPU time
per run is printed per map. ``--fleets mixed`` also (or instead) runs mixed fleets: 1-2 s
per edge and 5-10 s per job per agent, as in the gap study. That is where madgta-h
differs from madgta+. ``--channel LABEL`` runs it over one of section 2's channels (e.g.
``"loss 0.3 + range 5"``) instead of the perfect broadcast. For every (map, agents, nests)
cell it prints the mean makespan (largest ``total_time``, metrics.py), ``total_time_all``,
``nodes_without_job_all`` and the ratio variant/madgta of mean makespans with the 95 %
confidence interval of the *paired* difference (same seed, same nests), Student t, for each
variant (madgta+, madgta-h); pooled tables give the paired relative difference per map and
per agent count (for madgta-h also of ``total_time_all``, the thesis's sum).

Section 2 (``comm``): MADGTA with the §4.1 done-nodes list over lossy, range-limited and
delayed channels (the thesis's future work), against the perfect broadcast on the same
nests and seeds: how often the mission completes, duplicate jobs, moves without a job, extra
travel and makespan.

Nests: ``shared`` puts every agent on one free cell; ``dist`` gives each agent its own cell.
Cells are drawn from the largest 4-connected free component with a generator seeded by
(seed, agents, nest mode), so every algorithm sees the same start. Agents are identical:
2 s per edge, 9 s per job (the §3.2.4 example's figures), 0.5 s between starts.

Maps are read from ``SWARMEX_MAPS`` (default ``../shared/maps``); an absent map is skipped
with a message. den520d is left out by default (a run with 16 agents takes about 90 s).

    .venv/bin/python bench/compare_traversal_variants.py                 # both sections
    .venv/bin/python bench/compare_traversal_variants.py --section variants --seeds 10
    .venv/bin/python bench/compare_traversal_variants.py --quick         # small maps only
    .venv/bin/python bench/compare_traversal_variants.py --json out.json --jobs 2
    .venv/bin/python bench/compare_traversal_variants.py --section variants --agents 16 \
        --algorithms madgta madgta-k madgta-f --reference madgta-k --runs runs.jsonl

``--runs`` keeps every finished run in a JSON-lines file and reuses the runs already there,
so an interrupted bench loses nothing and a larger bench grows a smaller one;
``--reference`` adds the paired tables against another algorithm of the same runs.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import as_completed
from contextlib import contextmanager
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np
from scipy import ndimage

import _cli
from swarmex.comm.channel import Channel
from swarmex.engine.stats import summarize
from swarmex.missions.traversal import AgentSpec, run_metrics, run_traversal, uniform_agents
from swarmex.worlds import GridWorld, load_movingai

sys.path.insert(0, str(Path(__file__).resolve().parent))  # when imported from elsewhere
from gap_traversal_optimal import (  # noqa: E402
    KNOWN,
    check_algorithms,
    map_known,
    online_policy,
)

REPO = Path(__file__).resolve().parents[1]
MAPS = [
    "empty-16-16",
    "random-32-32-20",
    "room-32-32-4",
    "random-64-64-20",
    "warehouse-10-20-10-2-1",
    "ost003d",
]
QUICK_MAPS = ["empty-16-16", "random-32-32-20", "room-32-32-4"]
ALGORITHMS = ["madgta", "madgta+", "madgta-h", "madgta-r", "nearest"]
#: algorithms the paired tables do not compare with madgta (every other one is a variant)
NOT_VARIANTS = ("madgta", "nearest")
FLEETS = ("same", "mixed")
TRAVEL, JOB = 2.0, 9.0
NEST_MODES = ("shared", "dist")

# (label, Channel kwargs): edge time is 2 s, so delay 1 is half an edge, 2 a whole one
CHANNELS: list[tuple[str, dict]] = [
    ("perfect", {}),
    ("loss 0.1", {"loss": 0.1}),
    ("loss 0.3", {"loss": 0.3}),
    ("loss 0.6", {"loss": 0.6}),
    ("range 10", {"range": 10.0}),
    ("range 5", {"range": 5.0}),
    ("range 3", {"range": 3.0}),
    ("delay 2", {"delay": 2.0}),
    ("delay 1", {"delay": 1.0}),
    ("loss 0.3 + range 5", {"loss": 0.3, "range": 5.0}),
]
COMM_MAPS = ["random-32-32-20", "room-32-32-4"]


maps_dir = _cli.maps_dir  # $SWARMEX_MAPS, default ../shared/maps


def map_name(text: str) -> str:
    """A ``--maps`` value: refused at once when the maps folder is there without it (a typo
    used to print an empty table, or run every other section, and exit 0); with no folder,
    every map is skipped later, saying so."""
    folder = maps_dir()
    if folder.is_dir() and not (folder / f"{text}.map").exists():
        have = sorted(p.stem for p in folder.glob("*.map"))
        raise argparse.ArgumentTypeError(f"no map {text!r} in {folder} (have: {', '.join(have)})")
    return text


def load(name: str) -> GridWorld | None:
    path = maps_dir() / f"{name}.map"
    if not path.exists():
        print(f"skipping {name}: {path} not found (set SWARMEX_MAPS)", file=sys.stderr)
        return None
    return load_movingai(path)


def nests_for(world: GridWorld, agents: int, mode: str, seed: int) -> list[int]:
    """Start cells from the largest free component, the same for every algorithm."""
    labels, count = ndimage.label(world.free)
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    cells = np.nonzero(labels.ravel() == int(np.argmax(sizes)))[0]
    rng = np.random.default_rng([seed, agents, NEST_MODES.index(mode)])
    if mode == "shared":
        return [int(rng.choice(cells))] * agents
    return [int(v) for v in rng.choice(cells, agents, replace=False)]


def fleet_for(nests: list[int], fleet: str, seed: int) -> list[AgentSpec]:
    """Identical agents (2 s per edge, 9 s per job), or a mixed fleet as in the gap study of
    bench/gap_traversal_optimal.py: 1-2 s per edge and 5-10 s per job, drawn per agent from
    a generator seeded by (seed, agents), the same for every algorithm."""
    if fleet == "same":
        return uniform_agents(nests, TRAVEL, JOB)
    rng = np.random.default_rng([seed, len(nests), 7])
    return [AgentSpec(v, float(rng.uniform(0.5, 1.0)), float(rng.uniform(5, 10))) for v in nests]


@dataclass(frozen=True)
class Job:
    map: str
    agents: int
    mode: str
    seed: int
    algorithm: str
    channel: str = "perfect"
    carry_obstacles: bool = True  # the done list carries KM's obstacles (sim.py's own rule)
    fleet: str = "same"  # "mixed": speeds and job times drawn per agent (fleet_for)


@contextmanager
def done_list_without_obstacles(enabled: bool):
    """What-if for the simulator: the done-nodes list without the sender's known obstacles,
    as swarmex sent it before 23 Nov 2026 (the §4.1 list's done / not-done vertices only).

    An agent that misses the one message announcing a wall then never learns it from anyone
    and plans paths through it. The patch replaces ``agent.encode_km`` (what every agent's
    outgoing list is) for one run and restores it afterwards.
    """
    if not enabled:
        yield
        return
    from swarmex.missions.traversal import agent

    original = agent.encode_km

    def without_walls(status):
        return (*agent.encode_done_list(status), np.zeros(0, dtype=np.int64))

    agent.encode_km = without_walls
    try:
        yield
    finally:
        agent.encode_km = original


def run_one(job: Job) -> dict:
    world = load(job.map)
    assert world is not None
    nests = nests_for(world, job.agents, job.mode, job.seed)
    channel = Channel(**dict(CHANNELS)[job.channel])
    t0 = time.perf_counter()
    cpu = time.process_time()
    with done_list_without_obstacles(not job.carry_obstacles), map_known(
        job.algorithm.startswith(KNOWN)
    ):
        run = run_traversal(
            world, fleet_for(nests, job.fleet, job.seed), online_policy(job.algorithm),
            seed=job.seed, channel=channel,
        )
    cpu = time.process_time() - cpu
    totals, _ = run_metrics(run, 1.0)
    return {
        **job.__dict__,
        "complete": run.complete,
        "makespan": totals["max_total_time"],
        "total_time_all": totals["total_time_all"],
        "nodes_without_job_all": totals["nodes_without_job_all"],
        "travel_time_all": totals["travel_time_all"],
        "duplicate_jobs": totals["duplicate_jobs"],
        "nodes_missed": totals["nodes_missed"],
        "message_bytes": totals["message_bytes"],
        "messages": totals["messages"],
        "wall": time.perf_counter() - t0,
        "cpu": cpu,
    }


def _job_key(row: dict) -> tuple:
    """What identifies a run (a Job's fields), for reusing saved runs."""
    return tuple(row[f.name] for f in fields(Job))


def run_all(jobs: list[Job], workers: int, runs: Path | None = None) -> list[dict]:
    """Every job's figures, in the jobs' order. With ``runs`` (a JSON-lines file), each
    finished run is appended to it at once and runs already there are reused, not run
    again: an interrupted bench loses no finished run, and a larger one grows a smaller."""
    saved: dict[tuple, dict] = {}
    if runs is not None and runs.exists():
        for line in runs.read_text().splitlines():
            if line.strip():
                row = json.loads(line)
                saved[_job_key(row)] = row
    todo = [j for j in dict.fromkeys(jobs) if _job_key(j.__dict__) not in saved]
    if runs is not None:
        print(f"  {len(jobs) - len(todo)} of {len(jobs)} runs reused from {runs}",
              file=sys.stderr)

    def finished(row: dict) -> None:
        saved[_job_key(row)] = row
        if runs is not None:
            with runs.open("a") as f:
                f.write(json.dumps(row) + "\n")

    t0 = time.perf_counter()
    if workers <= 1:
        for i, job in enumerate(todo, 1):
            finished(run_one(job))
            _progress(i, len(todo), t0)
    elif todo:
        with _cli.process_pool(workers) as pool:
            futures = [pool.submit(run_one, job) for job in todo]
            for i, fut in enumerate(as_completed(futures), 1):
                finished(fut.result())
                _progress(i, len(todo), t0)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    return [saved[_job_key(j.__dict__)] for j in jobs]


def _progress(i: int, n: int, t0: float) -> None:
    if sys.stderr.isatty():
        print(f"\r  {i}/{n} runs, {time.perf_counter() - t0:6.0f} s", end="", file=sys.stderr)
    elif i == n or i % max(1, n // 10) == 0:
        print(f"  {i}/{n} runs, {time.perf_counter() - t0:6.0f} s", file=sys.stderr)


def paired_ci(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """Mean of a - b and the half-width of its 95 % Student-t interval (NaN for one pair)."""
    s = summarize(a - b)
    return s.mean, s.half_width


def select(rows: list[dict], **key) -> list[dict]:
    out = [r for r in rows if all(r[k] == v for k, v in key.items())]
    return sorted(out, key=lambda r: r["seed"])


def variants_table(rows: list[dict], algorithms: list[str], variant: str | None = "madgta+",
                   ref: str = "madgta") -> list[str]:
    """Per (map, agents, nests) cell: every algorithm's mean makespan, ``total_time_all``
    and moves without a job, and ``variant`` against ``ref`` (ratio of the mean makespans,
    paired Δ with its 95 % interval); ``variant=None``: the means alone, no paired columns."""
    paired = f" | {variant} / {ref} | paired Δ (95 % CI)" if variant is not None else ""
    lines = [
        "| map | agents | nests | "
        + " | ".join(f"{a} makespan" for a in algorithms)
        + paired + " | "
        + " | ".join(f"{a} total_time_all" for a in algorithms)
        + " | "
        + " | ".join(f"{a} moves w/o job" for a in algorithms)
        + " |",
    ]
    lines.append("|" + "---|" * (3 + 3 * len(algorithms) + (2 if variant is not None else 0)))
    cells = sorted({(r["map"], r["agents"], r["mode"]) for r in rows}, key=_cell_order)
    for mp, m, mode in cells:
        means = {a: select(rows, map=mp, agents=m, mode=mode, algorithm=a) for a in algorithms}
        mk = {a: np.array([r["makespan"] for r in v]) for a, v in means.items()}
        base, plus = mk.get(ref), mk.get(variant) if variant is not None else None
        if base is not None and plus is not None and base.size == plus.size and base.size:
            d, half = paired_ci(plus, base)
            cols = f" | {plus.mean() / base.mean():.3f} | {d:+.1f} ± {half:.1f}"
        else:
            cols = " | – | –" if variant is not None else ""
        tt = [np.mean([r["total_time_all"] for r in means[a]]) for a in algorithms]
        wj = [np.mean([r["nodes_without_job_all"] for r in means[a]]) for a in algorithms]
        lines.append(
            f"| {mp} | {m} | {mode} | "
            + " | ".join(f"{mk[a].mean():.1f}" for a in algorithms)
            + cols + " | "
            + " | ".join(f"{x:.0f}" for x in tt)
            + " | "
            + " | ".join(f"{x:.0f}" for x in wj)
            + " |"
        )
    return lines


def pooled_summary(rows: list[dict], by: str, variant: str = "madgta+",
                   metric: str = "makespan", ref: str = "madgta") -> list[str]:
    """Paired relative difference ``variant`` vs ``ref``, pooled per ``by`` ("map" or
    "agents"), of ``metric`` (``makespan`` or ``total_time_all``).

    Each run of the variant is paired with ``ref``'s run on the same map, agents, nests and
    seed; the mean of ``variant / ref − 1`` gets a 95 % Student-t interval.
    """
    lines = [
        f"| {by} | runs | mean {metric} ratio | paired relative Δ (95 % CI) | better in |",
        "|---|---|---|---|---|",
    ]
    keys = sorted({r[by] for r in rows}, key=lambda k: (MAPS.index(k) if k in MAPS else 99, k))
    for key in [*keys, None]:
        rel, wins = [], 0
        cells = sorted({(r["map"], r["agents"], r["mode"]) for r in rows})
        for mp, m, mode in cells:
            if key is not None and {"map": mp, "agents": m}[by] != key:
                continue
            base = select(rows, map=mp, agents=m, mode=mode, algorithm=ref)
            plus = select(rows, map=mp, agents=m, mode=mode, algorithm=variant)
            if len(base) != len(plus) or not base:
                continue
            for b, p in zip(base, plus, strict=True):
                rel.append(p[metric] / b[metric] - 1.0)
                wins += p[metric] < b[metric]
        if not rel:
            continue
        r = np.array(rel)
        d, half = paired_ci(r, np.zeros_like(r))
        lines.append(
            f"| {'all' if key is None else key} | {r.size} | {1 + r.mean():.3f} | "
            f"{100 * d:+.2f} % ± {100 * half:.2f} % | {wins}/{r.size} |"
        )
    return lines


def comm_table(rows: list[dict]) -> list[str]:
    """One line per (map, algorithm, channel), against the same algorithm's perfect runs."""
    lines = [
        "| map | algorithm | channel | complete | duplicate jobs | moves w/o job "
        "| extra travel | makespan / perfect | message kB |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    algs = sorted({r["algorithm"] for r in rows}, key=lambda a: (a != "madgta", a))
    variants = [(label, carry) for label, _ in CHANNELS for carry in (True, False)]
    for mp, alg in [(m, a) for m in sorted({r["map"] for r in rows}) for a in algs]:
        perfect = select(rows, map=mp, algorithm=alg, channel="perfect")  # the list is unused
        for label, carry in variants:
            if label == "perfect" and not carry:
                continue
            pick = {} if label == "perfect" else {"carry_obstacles": carry}
            cur = select(rows, map=mp, algorithm=alg, channel=label, **pick)
            if not cur or len(cur) != len(perfect):
                continue
            if not carry:
                label = f"{label}, list without obstacles"
            trav = np.array([r["travel_time_all"] for r in cur])
            trav0 = np.array([r["travel_time_all"] for r in perfect])
            mk = np.array([r["makespan"] for r in cur])
            mk0 = np.array([r["makespan"] for r in perfect])
            lines.append(
                f"| {mp} | {alg} | {label} | {sum(r['complete'] for r in cur)}/{len(cur)} | "
                f"{np.mean([r['duplicate_jobs'] for r in cur]):.1f} | "
                f"{np.mean([r['nodes_without_job_all'] for r in cur]):.0f} | "
                f"{100 * (trav.sum() / trav0.sum() - 1):+.1f} % | "
                f"{np.mean(mk / mk0):.3f} | "
                f"{np.mean([r['message_bytes'] for r in cur]) / 1000:.0f} |"
            )
    return lines


def print_summaries(rows: list[dict], variant: str = "madgta+", ref: str = "madgta") -> None:
    for metric in ("makespan", "total_time_all"):
        if metric == "total_time_all" and variant == "madgta+":
            continue  # madgta+ aims at the makespan; madgta-h at the sum as well
        v = f"{variant} / {ref}, {metric}"
        print(f"\n## {v} per map (agent counts and nests pooled)\n")
        print("\n".join(pooled_summary(rows, "map", variant, metric, ref)))
        print(f"\n## {v} per agent count (maps and nests pooled)\n")
        print("\n".join(pooled_summary(rows, "agents", variant, metric, ref)))
        crowded = [r for r in rows if r["agents"] == max(x["agents"] for x in rows)]
        print(f"\n## {v} per map, {crowded[0]['agents']} agents only\n")
        print("\n".join(pooled_summary(crowded, "map", variant, metric, ref)))


def print_variant_tables(rows: list[dict], algorithms: list[str],
                         references: tuple[str, ...] = ()) -> None:
    """Per fleet: the mean table and the paired summaries of each variant against madgta,
    and against each of ``references`` (other algorithms of the same runs); with no variant
    among the algorithms (only madgta and nearest), the mean table alone. Then the CPU per
    run."""
    for fleet in FLEETS:
        part = [r for r in rows if r.get("fleet", "same") == fleet]
        if not part:
            continue
        algs = [a for a in algorithms if any(r["algorithm"] == a for r in part)]
        variants = [v for v in algs if v not in NOT_VARIANTS]
        if not variants:  # nothing to pair, but the runs' makespans are still the result
            print(f"\n## {fleet} agents: mean over seeds (no variant of madgta to pair)\n")
            print("\n".join(variants_table(part, algs, None)))
        for variant in variants:
            print(f"\n## {fleet} agents: {variant} against madgta (mean over seeds)\n")
            print("\n".join(variants_table(part, algs, variant)))
            if "madgta" in algs:
                print_summaries(part, variant)
            for ref in [r for r in references if r in algs and r != variant]:
                print(f"\n## {fleet} agents: {variant} against {ref} (mean over seeds)\n")
                print("\n".join(variants_table(part, algs, variant, ref)))
                print_summaries(part, variant, ref)
        print(f"\n## {fleet} agents: CPU seconds per run (mean over the runs above)\n")
        print("| algorithm | " + " | ".join(sorted({r['map'] for r in part}, key=_map_order))
              + " |")
        print("|---|" + "---|" * len({r["map"] for r in part}))
        for a in algs:
            cells = [np.mean([r.get("cpu", np.nan) for r in part
                              if r["algorithm"] == a and r["map"] == mp])
                     for mp in sorted({r["map"] for r in part}, key=_map_order)]
            print(f"| {a} | " + " | ".join(f"{c:.2f}" for c in cells) + " |")


def _map_order(mp: str) -> tuple:
    return (MAPS.index(mp) if mp in MAPS else 99, mp)


def _cell_order(cell: tuple[str, int, str]) -> tuple:
    mp, m, mode = cell
    return (MAPS.index(mp) if mp in MAPS else 99, mp, m, NEST_MODES.index(mode))


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--section", choices=["variants", "comm", "both"], default="both")
    ap.add_argument("--maps", nargs="+", type=map_name, default=None,
                    help=f"default: {' '.join(MAPS)}")
    ap.add_argument("--agents", nargs="+", type=_cli.positive_int, default=[4, 8, 16])
    ap.add_argument("--seeds", type=_cli.paired_count, default=None,
                    help="seeds per configuration (default 5; --quick 3)")
    ap.add_argument("--nests", nargs="+", choices=NEST_MODES, default=list(NEST_MODES))
    ap.add_argument("--algorithms", nargs="+", default=ALGORITHMS)
    ap.add_argument("--fleets", nargs="+", choices=FLEETS, default=["same"],
                    help="same: identical agents; mixed: 1-2 s per edge, 5-10 s per job "
                    "(see fleet_for)")
    ap.add_argument("--channel", choices=[label for label, _ in CHANNELS], default="perfect",
                    help="variants: the radio of every run (one of comm's channels)")
    ap.add_argument("--comm-maps", nargs="+", type=map_name, default=COMM_MAPS)
    ap.add_argument("--comm-agents", type=_cli.positive_int, default=8)
    ap.add_argument("--comm-seeds", type=_cli.paired_count, default=None,
                    help="seeds per imperfect-radio configuration (default 4; --quick 2)")
    ap.add_argument("--comm-algorithms", nargs="+", default=["madgta", "madgta+"])
    ap.add_argument(
        "--without-obstacles",
        action="store_true",
        help="comm: also run each imperfect channel with the done list stripped of the "
        "sender's obstacles (the simulator before 23 Nov 2026, see done_list_without_obstacles)",
    )
    ap.add_argument("--quick", action="store_true", help="small maps, 3 seeds")
    ap.add_argument("--jobs", type=_cli.positive_int, default=1,
                    help="worker processes (default 1)")
    ap.add_argument("--json", type=_cli.out_file, default=None,
                    help="write every run's figures here")
    ap.add_argument("--runs", type=_cli.out_file, default=None,
                    help="a JSON-lines file: each finished run is appended to it, and runs "
                    "already in it are reused (an interrupted bench loses no finished run)")
    ap.add_argument("--reference", nargs="+", default=[],
                    help="also pair every variant with these algorithms of the same runs "
                    "(e.g. madgta-k), besides madgta")
    ap.add_argument(
        "--from-json",
        type=Path,
        default=None,
        help="print the tables of a previous --json file instead of running",
    )
    args = ap.parse_args(argv)
    if args.from_json:
        saved = json.loads(args.from_json.read_text())
        for row in saved.get("comm", []):
            row.setdefault("carry_obstacles", False)  # files from before the option
        if saved.get("variants"):
            rows = saved["variants"]
            algs = list(dict.fromkeys(r["algorithm"] for r in rows))
            print_variant_tables(rows, algs, tuple(args.reference))
        if saved.get("comm"):
            print("\n## Imperfect channels\n")
            print("\n".join(comm_table(saved["comm"])))
        return 0
    check_algorithms([*args.algorithms, *args.comm_algorithms])
    for ref in args.reference:
        if ref not in args.algorithms:
            ap.error(f"--reference {ref}: not one of --algorithms")
    maps = args.maps or (QUICK_MAPS if args.quick else MAPS)
    # an explicit count wins over --quick's, as an explicit --maps does
    seeds = range(args.seeds or (3 if args.quick else 5))
    out: dict[str, list[dict]] = {}

    if args.section in ("variants", "both"):
        present = [m for m in maps if load(m) is not None]
        if not present:
            print(f"variants: none of the maps is in {maps_dir()}; nothing to run", file=sys.stderr)
        jobs = [
            Job(mp, m, mode, s, alg, args.channel, fleet=fleet)
            for fleet in args.fleets
            for mp in present
            for m in args.agents
            for mode in args.nests
            for s in seeds
            for alg in args.algorithms
        ]
        print(f"variants: {len(jobs)} runs on {', '.join(present)}", file=sys.stderr)
        rows = run_all(jobs, args.jobs, args.runs) if jobs else []
        out["variants"] = rows
        if rows:
            print_variant_tables(rows, args.algorithms, tuple(args.reference))

    if args.section in ("comm", "both"):
        present = [m for m in args.comm_maps if load(m) is not None]
        jobs = [
            Job(mp, args.comm_agents, "dist", s, alg, label, carry)
            for mp in present
            for s in range(args.comm_seeds or (2 if args.quick else 4))
            for label, _ in CHANNELS
            for alg in args.comm_algorithms
            for carry in (
                [True, False] if args.without_obstacles and label != "perfect" else [True]
            )
        ]
        print(f"comm: {len(jobs)} runs on {', '.join(present)}", file=sys.stderr)
        rows = run_all(jobs, args.jobs, args.runs) if jobs else []
        out["comm"] = rows
        if rows:
            print(f"\n## Imperfect channels ({args.comm_agents} agents, own nests)\n")
            print("\n".join(comm_table(rows)))

    if args.json:
        args.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    _cli.run(main)
