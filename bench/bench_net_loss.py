"""Done-nodes lists over a lossy radio: duplicate jobs and missed nodes with and without them.

The networked traversal protocol with ``serve --inject-loss P``'s fault injection, run
socket-free (``swarmex.net.traversal.run_inprocess(mission, loss)``: the same agent cores,
stream order and loss draws as real processes; ``tests/e2e/test_net_loss.py`` checks a real
run equals it). For each map family and team, ``--seeds`` runs in three modes:

* ``km``: every broadcast carries the sender's done-nodes list and known walls (the
  thesis's KM), merged by every receiver (the default);
* ``no-walls``: the list without the walls (the wire before issue 15);
* ``none``: ``--no-done-lists``: only the broadcasts' own content.

Prints mean duplicate jobs, missed nodes, makespan, total travel and bytes per broadcast, and
the ratio of duplicate jobs none / km against the reference (docs/net.md: >= 10).

Usage: ``python bench/bench_net_loss.py [--loss 0.3] [--seeds 10]``.
"""

from __future__ import annotations

import importlib
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import _cli
from swarmex.missions.traversal import uniform_agents
from swarmex.net.traversal import Mission, run_inprocess
from swarmex.worlds import random_obstacles, rooms

AGENT = importlib.import_module("swarmex.missions.traversal.agent")
KM = AGENT.TraversalAgent.encode_done_list
REFERENCE_RATIO = 10.0


def without_walls(self: Any) -> Any:
    return AGENT.encode_done_list(self.belief.status)


def one(world: Any, agents: int, seed: int, loss: float, mode: str) -> tuple[float, ...]:
    AGENT.TraversalAgent.encode_done_list = without_walls if mode == "no-walls" else KM
    try:
        nest = int(np.flatnonzero(world.free.ravel())[0])
        mission = Mission(world, uniform_agents([nest] * agents, 2.22, 10.0), seed=seed,
                          done_lists=mode != "none")
        cores, rec = run_inprocess(mission, loss)
    finally:
        AGENT.TraversalAgent.encode_done_list = KM
    reach = rec.reachable()
    return (
        float(np.maximum(rec.job_count - 1, 0).sum()),
        float((rec.job_count[reach] == 0).sum()),
        max(c.log.travel_time + c.log.job_time for c in cores.values()),
        sum(c.log.travel_time for c in cores.values()),
        rec.message_bytes / max(rec.messages, 1),
    )


def main() -> None:
    ap = _cli.Parser()
    ap.add_argument("--loss", type=_cli.probability, default=0.3)
    ap.add_argument("--seeds", type=_cli.positive_int, default=10)
    args = ap.parse_args()
    families: list[tuple[str, int, Callable[[int], Any]]] = [
        ("random 10x10, 20 % walls", 4, lambda s: random_obstacles(10, 10, 0.2, seed=s)),
        ("random 16x16, 20 % walls", 6, lambda s: random_obstacles(16, 16, 0.2, seed=s)),
        ("rooms 24x24 (4-cell rooms)", 6, lambda s: rooms(24, 24, 4, seed=s)),
    ]
    print(f"loss {args.loss:g}, {args.seeds} seeds a row, means per run")
    print("| map | agents | lists | duplicate jobs | missed nodes | makespan s | travel s |"
          " bytes / broadcast |")
    print("|---|---|---|---|---|---|---|---|")
    ratios = []
    t0 = time.perf_counter()
    for name, agents, make in families:
        means = {}
        for mode in ("km", "no-walls", "none"):
            rows = np.array([one(make(s), agents, s, args.loss, mode)
                             for s in range(args.seeds)])
            means[mode] = rows.mean(axis=0)
            d, mi, span, travel, size = means[mode]
            print(f"| {name} | {agents} | {mode} | {d:.1f} | {mi:.1f} | {span:.1f} |"
                  f" {travel:.1f} | {size:.0f} |")
        ratios.append(means["none"][0] / max(means["km"][0], 0.1))
    ratio = min(ratios)
    print(f"duplicate jobs none / km, worst family: {ratio:.1f} "
          f"(reference >= {REFERENCE_RATIO:g}: {ratio / REFERENCE_RATIO:.2f}x);"
          f" {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    _cli.run(main)
