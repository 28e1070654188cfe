"""How much an end-game team plan could gain over MADGTA at best (issue 17, item 1).

An oracle, not a method: it runs MADGTA (16 identical agents, the maps, nests and seeds of
compare_traversal_variants.py) and takes a snapshot of the true state the first time at
most X reachable vertices are left without a job. From that state it plans the rest on the
TRUE map (every wall known):

* each agent starts where it is next free (the node it is moving to, or its vertex) at the
  time it is next free; a move it made towards a vacant vertex ends with that job;
* the plan starts from what MADGTA actually did after the snapshot (each agent's later
  jobs, in order; so the plan is never worse than MADGTA's own rest), then madgta-p's
  min-max local search (swarmex.missions.traversal.teamplan: 2-opt, or-opt, relocation,
  swaps, tail exchanges; makespan first, then the sum of the route ends) improves it.

It prints, per run and X, MADGTA's makespan, the plan's and a lower bound, each relative
to MADGTA's makespan. The lower bound spreads the remaining work evenly: every agent's
busy time up to the snapshot plus one job and one edge per vacant vertex, over the agents
(or the busiest agent, if later). The plan is a heuristic, so the true head-room lies
between the plan's and the bound's.

    .venv/bin/python bench/endgame_headroom.py [--maps M ...] [--seeds 4] [--x 100 200 400]
        [--ils ROUNDS]

``--ils`` also improves each plan by iterated local search (a cluster of the 12 nearest
planned vertices taken out and put back where each ends its route soonest, then the local
search again; the better plan kept): how much a stronger planner could add.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

import _cli

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_traversal_variants import (  # noqa: E402
    JOB,
    TRAVEL,
    fleet_for,
    load,
    map_name,
    nests_for,
)
from swarmex.engine.stats import summarize  # noqa: E402
from swarmex.missions.traversal import run_metrics, run_traversal  # noqa: E402
from swarmex.missions.traversal import sim as simmod  # noqa: E402
from swarmex.missions.traversal.rollout_sim import _fill_rows  # noqa: E402
from swarmex.missions.traversal.teamplan import (  # noqa: E402
    _improve,
    _iterated_search,
    _plan_ends,
)
from swarmex.planning.distance import distance_field  # noqa: E402

MAPS = ["empty-16-16", "random-32-32-20", "room-32-32-4", "random-64-64-20",
        "warehouse-10-20-10-2-1"]


def madgta_with_snapshots(world, specs, seed: int, xs: list[int]) -> tuple[float, list[dict]]:
    """MADGTA's makespan and one snapshot per X (the first event with <= X vacant)."""
    g = world.graph
    reach = np.isfinite(distance_field(g, [s.nest for s in specs], world.blocked))
    reach &= ~world.blocked
    holder: dict = {}
    original = simmod._Sim.__init__

    def grab(self, *args, **kwargs):  # the simulator, to read its true state
        original(self, *args, **kwargs)
        holder["sim"] = self

    snaps: dict[int, dict] = {}

    def on_frame(frame) -> None:
        sim = holder["sim"]
        vac = reach & (sim.job_count == 0)
        left = int(vac.sum())
        todo = [x for x in xs if x not in snaps and left <= x]
        if not todo:
            return
        pending = {a: (t, kind, node) for t, _, kind, a, node in sim.queue._heap
                   if kind in ("arrive", "job_end")}
        agents = []
        for a in range(1, sim.m + 1):
            start = (a - 1) * sim.start_interval
            log = sim.agent(a).log
            if a in pending:
                t, kind, node = pending[a]
                agents.append((t - start, int(node), kind))
            elif log.trajectory:
                agents.append((log.finished_at - start, int(log.node), "finished"))
            else:  # not started yet: at its nest when it starts
                agents.append((0.0, specs[a - 1].nest, "finished"))
        for x in todo:
            snaps[x] = {"t": frame.t, "agents": agents, "vacant": np.nonzero(vac)[0]}

    simmod._Sim.__init__ = grab
    try:
        run = run_traversal(world, specs, "madgta", seed=seed, on_frame=on_frame)
    finally:
        simmod._Sim.__init__ = original
    makespan = run_metrics(run, 1.0)[0]["max_total_time"]
    for snap in snaps.values():  # what MADGTA did after the snapshot: the warm start
        snap["later"] = [[int(v) for t, v in log.jobs if t > snap["t"] + 1e-9]
                         for log in run.agents]
    return makespan, [snaps[x] for x in xs if x in snaps]


def plan(world, snap: dict, passes: int = 200, ils: int = 0,
         seed: int = 0) -> tuple[float, float]:
    """(plan makespan, lower bound) from a snapshot, on the true map; with ``ils`` > 0 the
    local search's plan is then improved by that many rounds of ruin and recreate
    (madgta-p's own compiled ``_iterated_search``, clusters of 12 vertices)."""
    g = world.graph
    m = len(snap["agents"])
    vacant = {int(v) for v in snap["vacant"]}
    base = np.zeros(m + 1)
    pos = np.zeros(m + 1, dtype=np.int64)
    for a, (t, node, kind) in enumerate(snap["agents"], start=1):
        base[a] = t
        pos[a] = node
        if kind == "arrive" and node in vacant:  # it does that job on arrival
            vacant.discard(node)
            base[a] += JOB
    vac = np.array(sorted(vacant), dtype=np.int64)
    n = g.n_nodes
    row_of = np.full(n, -1, dtype=np.int64)
    row_of[vac] = np.arange(vac.size)
    table = np.empty((vac.size, n), dtype=np.int32)
    _fill_rows(g.indptr, g.indices, world.blocked, vac, row_of[vac], table,
               np.empty(n, dtype=np.int32))
    routes = np.full((m + 1, vac.size + 1), -1, dtype=np.int64)
    lens = np.zeros(m + 1, dtype=np.int64)
    for a, later in enumerate(snap["later"], start=1):
        for v in later:
            if v in vacant:
                vacant.discard(v)
                routes[a, lens[a]] = v
                lens[a] += 1
    assert not vacant, "MADGTA left vacant vertices"
    active = np.ones(m + 1, dtype=np.bool_)
    active[0] = False
    edge = np.full(m + 1, TRAVEL)
    jt = np.full(m + 1, JOB)
    _improve(base, pos, active, routes, lens, edge, jt, table, row_of, passes)
    state = (base, pos, active, routes, lens, edge, jt, table, row_of)
    if ils > 0:
        _iterated_search(*state, ils, 12, 50, seed)
    makespan = _plan_ends(*state, np.zeros(m + 1))[0]
    bound = max(base[1:].max(), (base[1:].sum() + vac.size * (JOB + TRAVEL)) / m)
    return float(makespan), float(bound)


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--maps", nargs="+", type=map_name, default=MAPS)
    ap.add_argument("--seeds", type=_cli.positive_int, default=4)
    ap.add_argument("--x", type=_cli.positive_int, nargs="+", default=[100, 200, 400, 800])
    ap.add_argument("--agents", type=_cli.positive_int, default=16)
    ap.add_argument("--ils", type=_cli.positive_int, default=None,
                    help="also improve each plan by this many ruin-and-recreate rounds")
    args = ap.parse_args(argv)
    rows: dict[tuple[str, int], list[tuple[float, float]]] = {}
    cpu0 = time.process_time()
    for name in args.maps:
        world = load(name)
        if world is None:
            continue
        for mode in ("shared", "dist"):
            for seed in range(args.seeds):
                specs = fleet_for(nests_for(world, args.agents, mode, seed), "same", seed)
                mk, snaps = madgta_with_snapshots(world, specs, seed, args.x)
                for x, snap in zip(args.x, snaps, strict=False):
                    p, lb = plan(world, snap)
                    q = plan(world, snap, ils=args.ils)[0] if args.ils else math.nan
                    rows.setdefault((name, x), []).append((p / mk - 1, lb / mk - 1,
                                                           q / mk - 1))
                    more = f" ils {q:.0f} ({100 * (q / mk - 1):+.2f} %)" if args.ils else ""
                    print(f"{name} {mode} seed {seed} X={x}: madgta {mk:.0f} plan {p:.0f} "
                          f"({100 * (p / mk - 1):+.2f} %){more} bound {lb:.0f} "
                          f"({100 * (lb / mk - 1):+.2f} %)", flush=True)
    if not rows:
        print("none of the maps was found; nothing to run", file=sys.stderr)
        return 0
    ils = " | with ruin and recreate (mean, 95 % CI)" if args.ils else ""
    print(f"\n| map | X | runs | plan vs MADGTA (mean, 95 % CI){ils} | lower bound vs MADGTA |")
    print("|---|---|---|---|" + ("---|" if args.ils else "") + "---|")

    def cell(col: np.ndarray) -> str:
        # Student's t, as the other comparisons (1.96 was 1.6x too narrow at four runs)
        s = summarize(col)
        half = f"{s.half_width:.2f} %" if s.has_ci else "n/a (one run)"
        return f"{s.mean:+.2f} % ± {half}"

    for (name, x), vals in rows.items():
        arr = 100 * np.array(vals)
        extra = f" | {cell(arr[:, 2])}" if args.ils else ""
        print(f"| {name} | {x} | {len(arr)} | {cell(arr[:, 0])}{extra} "
              f"| {arr[:, 1].mean():+.2f} % |")
    print(f"\nCPU {time.process_time() - cpu0:.0f} s")
    return 0


if __name__ == "__main__":
    _cli.run(main)
