"""MADGTA's gap to the exact optimum, and how long the exact MILP takes as maps grow.

Gap (default): 32 seeded random small instances, a full 2⁵ factorial. The five bits of the
instance number choose:

* the grid: 3×4 or 4×4;
* obstacles: none, or 15 % random ones;
* 2 or 3 agents;
* nests: all agents on one nest, as in Tables 5.1–5.2, or on distinct nests;
* agents: the worked example's identical UAVs (2 s per edge, 9 s per job), or mixed ones
  (1–2 s per edge, 5–10 s per job).

On each instance this script runs MADGTA and the nearest-vacant baseline with several seeds
each (their ties are random) and solves the exact optimum for both objectives. It prints
one row per instance, then the mean and max gap in % of each online algorithm to the
optimum:

* sum:      total_time_all / optimal sum − 1       (the thesis's objective, §3.1)
* makespan: largest total_time / optimal makespan − 1

It also prints the share of runs that were exactly optimal; the thesis reports 2–5 % on
6×6. The last line is the ratio of MADGTA's total_time_all to the optimum, averaged over
runs, against the reference 1.0, the optimum itself.

Online algorithms (``--algorithms``, default madgta, nearest, madgta+, madgta-h, madgta-r;
``madgta-h@RHO`` runs madgta-h at another point of its sum/makespan trade-off,
``madgta-r@KEY=VALUE,...`` madgta-r with other settings (``madgta-p@...`` likewise), and
``known:NAME`` runs NAME with the whole map known from the start: how much of its gap is
for lack of information). A table per agent type gives each algorithm's mean gaps and its
paired difference to MADGTA (same instance, same seed) with a 95 % Student-t interval, in
percentage points, and its CPU time per run.

Trade-off (``--pareto [CAP ...]``): what the optimum itself can do. Among the plans whose
makespan is at most CAP × the optimal makespan, it finds the least sum. On mixed teams a low
sum and a low makespan conflict, and this measures by how much. With each least sum it keeps
a proven floor (the MILP's dual bound when a solve times out) and prints the least mean sum
gap that any method with a mean makespan gap of at most ``--budget`` can reach
(:mod:`swarmex.missions.traversal.pareto`).

Thesis setting (``--thesis``): Table 5.1's 6×6 grid, 3 identical agents on one nest, for
one nest per symmetry class. This gives MADGTA's sum gap where the thesis has its own
numbers; the makespan is out of reach there, because 36 > 16.

Scaling (``--scaling``): solve time of both objectives on growing random grids. This is
what sets :data:`swarmex.missions.traversal.optimal.MAX_FREE_VERTICES`.

    .venv/bin/python bench/gap_traversal_optimal.py [--instances 32] [--seeds 5] [--json F]
    .venv/bin/python bench/gap_traversal_optimal.py --algorithms madgta madgta-h madgta-h@0.5
    .venv/bin/python bench/gap_traversal_optimal.py --pareto [1 1.02 1.1 1.25] [--kind mixed]
    .venv/bin/python bench/gap_traversal_optimal.py --thesis [--seeds 20]
    .venv/bin/python bench/gap_traversal_optimal.py --scaling [--time-limit 60] [--largest 64]
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

import _cli
from swarmex.engine.stats import summarize
from swarmex.missions.traversal import make_policy, run_metrics, run_traversal, sim
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.optimal import solve_optimal
from swarmex.worlds import random_obstacles


def instance(i: int) -> tuple[object, list[AgentSpec], str]:
    """Instance i of the gap study: every choice is a function of i (seeded)."""
    rng = np.random.default_rng(1000 + i)
    w, h = (3, 4) if i % 2 == 0 else (4, 4)
    density = 0.0 if (i // 2) % 2 == 0 else 0.15
    world = random_obstacles(w, h, density, seed=rng)
    m = 2 + (i // 4) % 2
    shared = (i // 8) % 2 == 0
    mixed = (i // 16) % 2 == 1
    free = np.nonzero(~world.blocked)[0]
    nests = [int(rng.choice(free))] * m if shared else [int(v) for v in rng.choice(free, m, False)]
    agents = []
    for nest in nests:
        if mixed:
            agents.append(AgentSpec(nest, float(rng.uniform(0.5, 1.0)), float(rng.uniform(5, 10))))
        else:
            agents.append(AgentSpec(nest, 0.5, 9.0))  # 2 s per unit edge, 9 s per job
    label = (
        f"{w}x{h} d={density:.2f} m={m} {'shared' if shared else 'distinct'} "
        f"{'mixed' if mixed else 'same'}"
    )
    return world, agents, label


#: online algorithms of the gap study; ``NAME@RHO`` is madgta-h with that rho
ALGORITHMS = ["madgta", "nearest", "madgta+", "madgta-h", "madgta-r"]
#: prefix of an algorithm run with the whole map known from the start (a diagnostic)
KNOWN = "known:"


def online_policy(name: str) -> str:
    """The algorithm spec to run: a name, or ``NAME@KEY=VALUE,...`` with a policy's options
    (``swarmex.missions.traversal.policies.parse_algorithm``, e.g. ``madgta-r@far=2,ties=4``);
    ``madgta-h@RHO`` is short for ``madgta-h@rho=RHO``. A ``known:`` prefix is dropped (see
    :func:`map_known`)."""
    name = name.removeprefix(KNOWN)
    base, _, rest = name.partition("@")
    if base == "madgta-h" and rest and "=" not in rest:
        return f"madgta-h@rho={rest}"
    return name


def check_algorithms(names: list[str]) -> None:
    """Refuse an unknown or malformed algorithm spec before any run (``InputError``).

    Checked up front because the study runs every instance's MILP and the other algorithms
    first: a typo in the last name used to surface minutes later, as a traceback."""
    from swarmex.errors import InputError
    from swarmex.missions.traversal.params import ALGORITHMS as KNOWN_NAMES

    for name in names:
        base = name.removeprefix(KNOWN).split("@", 1)[0]
        if base not in KNOWN_NAMES or base == "optimal":
            online = ", ".join(a for a in KNOWN_NAMES if a != "optimal")
            raise InputError(f"unknown online algorithm {name!r} (choose from {online}, "
                             "NAME@KEY=VALUE,... or known:NAME)")
        make_policy(online_policy(name))  # an InputError names what is wrong


@contextmanager
def map_known(enabled: bool) -> Iterator[None]:
    """Diagnostic only: every agent's sensor reports every obstacle of the map at its first
    look (and the start message carries them to all), so the team knows the whole map from
    the start. What is left of an algorithm's gap then is not for lack of information."""
    if not enabled:
        yield
        return
    original = sim.AdjacencySensor

    class Omniscient(original):  # type: ignore[misc, valid-type]
        def __call__(self, node: int) -> np.ndarray:
            return np.nonzero(self.blocked)[0]

    sim.AdjacencySensor = Omniscient
    try:
        yield
    finally:
        sim.AdjacencySensor = original


def run_online(world: object, agents: list[AgentSpec], name: str, seed: int) -> tuple:
    """One online run of algorithm spec ``name``: (run, CPU seconds)."""
    with map_known(name.startswith(KNOWN)):
        t = time.process_time()
        run = run_traversal(world, agents, algorithm=online_policy(name), seed=seed)
        return run, time.process_time() - t


def gap_study(n_instances: int, seeds: int, time_limit: float,
              algorithms: list[str] | None = None) -> dict:
    algorithms = algorithms or ALGORITHMS
    rows = []
    print(f"{'#':>3} {'instance':38} {'n':>3} {'opt sum':>8} {'opt mk':>7}  "
          + "  ".join(f"{a[:14]:>14} sum%/mk%" for a in algorithms))
    for i in range(n_instances):
        world, agents, label = instance(i)
        opt_sum = solve_optimal(world, agents, "sum", time_limit=time_limit)
        opt_mk = solve_optimal(world, agents, "makespan", time_limit=time_limit)
        row = {
            "instance": i,
            "label": label,
            "mixed": label.endswith("mixed"),
            "n": len(opt_sum.vertices),
            "opt_sum": opt_sum.value,
            "opt_makespan": opt_mk.value,
            "proven": opt_sum.proven_optimal and opt_mk.proven_optimal,
            "solve_seconds": opt_sum.solve_seconds + opt_mk.solve_seconds,
        }
        for algorithm in algorithms:
            sums, mks, errors, messages, cpu = [], [], [], [], []
            for seed in range(seeds):
                try:
                    run, dt = run_online(world, agents, algorithm, seed)
                except Exception as exc:  # an online-policy bug must not hide the other runs
                    errors.append(f"seed {seed}: {type(exc).__name__}: {exc}")
                    continue
                assert run.complete, (i, algorithm, seed)
                totals, _ = run_metrics(run, 1.0)
                sums.append(totals["total_time_all"] / opt_sum.value - 1.0)
                mks.append(totals["max_total_time"] / opt_mk.value - 1.0)
                messages.append(totals["messages"])
                cpu.append(dt)
            row[algorithm] = {"sum_gap": sums, "makespan_gap": mks, "errors": errors,
                              "messages": messages, "cpu": cpu}
        rows.append(row)
        cells = []
        for a in algorithms:
            g = row[a]
            cells.append(
                f"{100 * np.mean(g['sum_gap']):>14.2f} {100 * np.mean(g['makespan_gap']):>7.2f}"
                if g["sum_gap"] else f"{'failed':>22}")
        # "*": the solve timed out, so this is the best plan found and a gap may be negative
        star_sum = " " if opt_sum.proven_optimal else "*"
        star_mk = " " if opt_mk.proven_optimal else "*"
        print(f"{i:>3} {label:38} {row['n']:>3} {row['opt_sum']:>7.2f}{star_sum} "
              f"{row['opt_makespan']:>6.2f}{star_mk}  " + "  ".join(cells), flush=True)
    summary = {}
    for algorithm in algorithms:
        failed = sum(len(r[algorithm]["errors"]) for r in rows)
        if failed:
            print(f"{algorithm}: {failed} of {len(rows) * seeds} runs raised and are left out: "
                  + "; ".join(f"instance {r['instance']} {e}" for r in rows
                              for e in r[algorithm]["errors"][:1]))
        for key in ("sum_gap", "makespan_gap"):
            runs = np.array([v for r in rows for v in r[algorithm][key]])
            per_instance = np.array([np.mean(r[algorithm][key]) for r in rows
                                     if r[algorithm][key]])
            summary[f"{algorithm}_{key}"] = {
                "mean_pct": float(100 * runs.mean()),
                "max_pct": float(100 * runs.max()),
                "median_instance_pct": float(100 * np.median(per_instance)),
                "optimal_runs_pct": float(100 * np.mean(np.abs(runs) < 1e-9)),
            }
    if not all(r["proven"] for r in rows):
        print("* not proven optimal within --time-limit: the best plan the solver found, which"
              " an online run may beat (a negative gap); raise --time-limit for a true gap")
    print(f"\n{len(rows)} instances × {seeds} seeds; all optima proven: "
          f"{all(r['proven'] for r in rows)}; "
          f"exact solve time mean {np.mean([r['solve_seconds'] for r in rows]):.2f} s, "
          f"max {max(r['solve_seconds'] for r in rows):.2f} s")
    print(f"{'gap to optimum':32} {'mean %':>8} {'max %':>8} {'median inst %':>14} "
          f"{'optimal runs %':>15}")
    for name, st in summary.items():
        print(f"{name:32} {st['mean_pct']:>8.2f} {st['max_pct']:>8.2f} "
              f"{st['median_instance_pct']:>14.2f} {st['optimal_runs_pct']:>15.1f}")
    by_agents = split_by_agents(rows, algorithms)
    ratio = 1.0 + summary["madgta_sum_gap"]["mean_pct"] / 100 if "madgta" in algorithms else None
    if ratio is not None:
        print(f"\nratio MADGTA total_time_all / optimum (reference 1.0): {ratio:.4f}")
    return {"rows": rows, "summary": summary, "by_agents": by_agents}


def split_by_agents(rows: list[dict], algorithms: list[str]) -> dict:
    """Mean gaps per agent type, and each algorithm's paired difference to MADGTA (same
    instance, same seed) with its 95 % Student-t interval, in percentage points."""
    out: dict = {}
    print("\n| agents | algorithm | sum gap mean / max % | makespan gap mean / max % | "
          "Δ sum gap vs madgta (95 % CI) | Δ makespan gap vs madgta (95 % CI) | messages "
          "| CPU ms per run |")
    print("|---|---|---|---|---|---|---|---|")
    for mixed in (False, True):
        group = [r for r in rows if r["mixed"] == mixed]
        kind = "mixed" if mixed else "identical"
        if not group:
            continue
        for a in algorithms:
            cell: dict = {}
            for key in ("sum_gap", "makespan_gap"):
                v = np.array([x for r in group for x in r[a][key]])
                cell[key] = (float(100 * v.mean()), float(100 * v.max()))
                if "madgta" in algorithms and a != "madgta":
                    pairs = [(x, y) for r in group
                             for x, y in zip(r[a][key], r["madgta"][key], strict=False)]
                    d = summarize(100 * np.array([x - y for x, y in pairs]))
                    cell[f"delta_{key}"] = (float(d.mean), float(d.half_width))
            msgs = float(np.mean([x for r in group for x in r[a]["messages"]]))
            cpu = float(np.mean([x for r in group for x in r[a].get("cpu", [np.nan])]))
            out[f"{kind}/{a}"] = {**cell, "messages": msgs, "cpu_seconds": cpu}

            def delta(key: str, c: dict = cell) -> str:
                if f"delta_{key}" not in c:
                    return "–"
                m, h = c[f"delta_{key}"]
                return f"{m:+.2f} ± {h:.2f}"

            print(f"| {kind} | {a} | {cell['sum_gap'][0]:.2f} / {cell['sum_gap'][1]:.1f} | "
                  f"{cell['makespan_gap'][0]:.2f} / {cell['makespan_gap'][1]:.1f} | "
                  f"{delta('sum_gap')} | {delta('makespan_gap')} | {msgs:.1f} | "
                  f"{1000 * cpu:.0f} |")
    return out


def pareto(n_instances: int, caps: list[float], time_limit: float, budget: float,
           kinds: tuple[str, ...] = ("identical", "mixed")) -> dict:
    """What the optimum itself can do: among all plans whose makespan is at most
    ``cap`` × the optimal makespan, the least sum, as a gap to the optimal sum. A low sum
    and a low makespan conflict on mixed teams (the fast agent should do nearly everything
    for the sum, and its share is capped for the makespan); this measures by how much.

    Uses the exact partition model of ``optimal`` (all 2^n routes, n <= 16) with a cap on
    every route's cost. Next to each least sum it keeps a proven *floor*: the solve's value
    when proven optimal, else the MILP's dual bound, over the optimal sum found (an upper
    bound of the true one). From the floors, :mod:`~swarmex.missions.traversal.pareto`
    bounds the least mean sum gap of any method whose mean makespan gap is at most
    ``budget``."""
    from swarmex.missions.traversal.optimal_instance import _prepare
    from swarmex.missions.traversal.optimal_partition import _assign, _class_costs, _partition_sum
    from swarmex.missions.traversal.pareto import least_mean_sum_gap, staircase

    res: dict = {c: {"identical": [], "mixed": []} for c in caps}
    floors: dict = {"identical": [], "mixed": []}
    unproven = {c: 0 for c in caps}
    sum_unproven: list[int] = []  # instances whose optimal sum is not proven
    for i in range(n_instances):
        world, agents, label = instance(i)
        kind = "mixed" if label.endswith("mixed") else "identical"
        if kind not in kinds:
            continue
        opt_sum = solve_optimal(world, agents, "sum", time_limit=time_limit)
        opt_mk = solve_optimal(world, agents, "makespan", time_limit=time_limit)
        if not opt_sum.proven_optimal:  # then a floor of 0 % is no longer a floor
            sum_unproven.append(i)
        inst, _ = _prepare(world, agents, 1.0, 16, "makespan")
        cost, _ = _class_costs(inst)
        incumbent = [[inst.verts.index(v) for v in p.jobs] for p in opt_mk.agents]
        row = []
        for c in caps:
            cap = np.full(len(inst.classes), opt_mk.value * c * (1 + 1e-9) + 1e-9)
            milp, picks, _ = _partition_sum(inst, cost, cap, incumbent, time_limit)
            unproven[c] += not milp.optimal  # a time-out: the plan is feasible, maybe not least
            routes = _assign(inst, picks)
            total = sum(inst.route_cost(a, r) for a, r in enumerate(routes))
            res[c][kind].append(total / opt_sum.value - 1)
            bound = milp.bound if np.isfinite(milp.bound) else -np.inf
            low = total if milp.optimal else min(total, bound)
            row.append(low / opt_sum.value - 1)
        floors[kind].append(row)
        print(f"  instance {i} done", file=sys.stderr, flush=True)  # progress, not table
    print("| makespan at most | least sum gap, identical agents | mixed agents (mean / max) "
          "| proven floor of the mean, identical / mixed | solves not proven |")
    print("|---|---|---|---|---|")
    for j, c in enumerate(caps):
        ident, mixed = np.array(res[c]["identical"]), np.array(res[c]["mixed"])
        left = f"{100 * ident.mean():.2f} %" if ident.size else "–"
        right = f"{100 * mixed.mean():.2f} % / {100 * mixed.max():.1f} %" if mixed.size else "–"
        fl = " / ".join(f"{100 * np.mean([r[j] for r in floors[k]]):.2f} %" if floors[k]
                        else "–" for k in ("identical", "mixed"))
        print(f"| {c:.2f} × optimal | {left} | {right} | {fl} | {unproven[c]} |")
    if sum_unproven:
        print(f"optimal sum not proven within --time-limit on instance(s) "
              f"{', '.join(map(str, sum_unproven))}: their floors are not proven either")
    least = {}
    for k in kinds:
        if floors[k]:
            least[k] = least_mean_sum_gap([staircase(caps, r) for r in floors[k]], budget)
            print(f"{k}: any method with a mean makespan gap <= {100 * budget:.1f} % has a mean "
                  f"sum gap >= {100 * least[k]:.2f} % (proven floor)")
    return {"pareto": {str(c): v for c, v in res.items()},
            "floors": floors, "caps": caps, "budget": budget,
            "least_mean_sum_gap": least,
            "unproven": {str(c): v for c, v in unproven.items()}}


def thesis_setting(seeds: int, time_limit: float) -> dict:
    """Table 5.1's setting: 6×6 nodes on 40×40 m, no obstacles, 3 identical agents on one
    nest (3 m/s, 10 s jobs), one nest per symmetry class of the thesis's Tables 5.1-5.2."""
    world = random_obstacles(6, 6, 0.0, seed=0)
    unit = 40.0 / 6.0
    out = []
    print(f"{'nest (thesis id)':>16} {'optimal sum':>12} {'madgta mean':>12} {'min':>8} "
          f"{'max':>8} {'gap mean %':>11} {'optimal runs':>13}")
    for tid in (1, 2, 3, 8, 9, 15):  # corner, near corner, mid-border, diagonal, inner, centre
        x, yb = (tid - 1) % 6, (tid - 1) // 6
        nest = (5 - yb) * 6 + x
        agents = [AgentSpec(nest, 3.0, 10.0)] * 3
        opt = solve_optimal(world, agents, "sum", unit_length=unit, time_limit=time_limit)
        totals = []
        for seed in range(seeds):
            run = run_traversal(world, agents, seed=seed, unit_length=unit)
            totals.append(run_metrics(run, unit)[0]["total_time_all"])
        t = np.array(totals)
        gap = 100 * (t / opt.value - 1)
        out.append({"nest": tid, "optimal_sum": opt.value, "proven": opt.proven_optimal,
                    "madgta_sum": totals})
        print(f"{tid:>16} {opt.value:>12.2f} {t.mean():>12.2f} {t.min():>8.2f} {t.max():>8.2f} "
              f"{gap.mean():>11.2f} {np.mean(gap < 1e-6) * 100:>12.1f}%", flush=True)
    return {"thesis_setting": out}


def scaling(time_limit: float, largest: int) -> dict:
    """Solve times on growing random grids: 2-4 agents, mixed on distinct nests or identical
    on one shared nest (the symmetric case)."""
    sizes = [(4, 4), (5, 4), (6, 3), (5, 5), (6, 5), (6, 6), (7, 6), (7, 7), (8, 7), (8, 8)]
    cases = [(w, h, d) for w, h in sizes for d in (0.0, 0.15)]
    out = []
    print(f"{'grid':>6} {'agents':>8} {'m':>2} {'n':>3} {'objective':>9} {'seconds':>8} "
          f"{'status':>20}")
    for w, h, density in cases:
        if w * h > largest:
            continue
        for m in (2, 3, 4):
            for style in ("mixed", "same"):
                rng = np.random.default_rng(w * 100 + h * 10 + m)
                world = random_obstacles(w, h, density, seed=rng)
                free = np.nonzero(~world.blocked)[0]
                if style == "mixed":
                    agents = [
                        AgentSpec(int(v), float(rng.uniform(0.5, 1.0)), float(rng.uniform(5, 10)))
                        for v in rng.choice(free, m, replace=False)
                    ]
                else:
                    agents = [AgentSpec(int(free[0]), 0.5, 9.0)] * m
                n = int(len(free))
                for objective in ("sum", "makespan"):
                    if objective == "makespan" and n > 18:
                        continue  # the partition tables hold 2^n·n floats
                    t = time.perf_counter()
                    plan = solve_optimal(world, agents, objective, time_limit=time_limit,
                                         max_vertices=largest)
                    dt = time.perf_counter() - t
                    out.append({"grid": f"{w}x{h}", "agents": style, "m": m, "n": n,
                                "objective": objective, "seconds": dt, "status": plan.status,
                                "gap": plan.gap})
                    print(f"{w}x{h:<4} {style:>8} {m:>2} {n:>3} {objective:>9} {dt:>8.2f} "
                          f"{plan.status:>20}", flush=True)
    return {"scaling": out}


def main() -> None:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--instances", type=_cli.positive_int, default=32)
    ap.add_argument("--seeds", type=_cli.positive_int, default=5, help="online runs per instance")
    ap.add_argument("--time-limit", type=_cli.positive_float, default=60.0)
    ap.add_argument("--scaling", action="store_true", help="measure solve time instead")
    ap.add_argument("--largest", type=_cli.positive_int, default=64,
                    help="--scaling: largest grid (cells)")
    ap.add_argument("--thesis", action="store_true",
                    help="Table 5.1's 6x6 setting (sum only) instead")
    ap.add_argument("--algorithms", nargs="+", default=ALGORITHMS,
                    help="online algorithms (madgta-h@RHO: madgta-h with that rho; "
                    "madgta-r@K=V,... / madgta-p@K=V,...: with those keywords; "
                    "known:NAME: NAME with the whole map known from the start, a diagnostic)")
    ap.add_argument("--pareto", nargs="*", type=_cli.cap, metavar="CAP",
                    help="instead: the least sum gap of plans with makespan <= CAP x optimal "
                    "(default caps 1 1.01 1.02 1.03 1.05 1.1 1.25 1.5 2)")
    ap.add_argument("--budget", type=_cli.nonneg_float, default=0.02,
                    help="--pareto: the mean makespan gap allowed (default 0.02, issue 17)")
    ap.add_argument("--kind", choices=["all", "identical", "mixed"], default="all",
                    help="--pareto: which agent type's instances to solve")
    ap.add_argument("--json", type=_cli.out_file, help="also write the numbers to this file")
    args = ap.parse_args()
    check_algorithms(args.algorithms)
    if args.pareto is not None:
        caps = sorted(args.pareto or [1.0, 1.01, 1.02, 1.03, 1.05, 1.10, 1.25, 1.5, 2.0])
        kinds = ("identical", "mixed") if args.kind == "all" else (args.kind,)
        result = pareto(args.instances, caps, args.time_limit, args.budget, kinds)
    elif args.scaling:
        result = scaling(args.time_limit, args.largest)
    elif args.thesis:
        result = thesis_setting(args.seeds, args.time_limit)
    else:
        result = gap_study(args.instances, args.seeds, args.time_limit, args.algorithms)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(result, fh, indent=1)


if __name__ == "__main__":
    _cli.run(main)
