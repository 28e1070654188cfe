"""A team leaving one nest: branch 3 as it is against the route before, in one process.

While the team stands together most of the map ties at the max-min (docs/traversal.md, "Many
agents on one nest").

* **Open grid** (default): ``lattice.far_choice`` used to gather and score every tied
  vertex for Algorithm 2's tie-break by the sum over rivals. It now goes on by a bound of
  that sum once no region can beat the best max-min, and skips the regions that cannot reach
  the best tied sum; the reference is the plain search (the same kernel, the bound off).
* **Walled map** (``--map``, e.g. den520d; hop rows, ``fartiles``): rivals on one vertex
  share a hop row, and branch 3 now reads each row once per (row, class) group, drops a
  vertex as soon as one rival puts it below the tie, and breaks ties without the whole
  utility matrix; the reference reads every near rival at every vertex and builds the matrix
  (``policies.each_rival_alone``, ``far_tiles(..., drop_early=False)``,
  ``policies.tied_top_by_matrix``).

For each team size this runs the first ``--events`` events of MADGTA from the map's first
free cell twice, checks that both runs are the same (their fingerprints: every agent's path,
jobs and times), and prints the CPU seconds and their ratio. ``--full`` then runs each team
to the end as it is.

Before the table a small run loads numba's kernels (compiled or from the disk cache),
untimed, so the first timed run does not pay it.

    .venv/bin/python bench/traversal_crowd.py                        # ~1 min
    .venv/bin/python bench/traversal_crowd.py --agents 64 --full     # + a 1000 x 1000 run, ~3 min
    .venv/bin/python bench/traversal_crowd.py --map den520d.map --agents 100 \
        --events 3000                                                # ~1.5 min
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

import _cli
from swarmex.missions.traversal import lattice, policies, run_traversal, uniform_agents
from swarmex.missions.traversal.metrics import run_fingerprint
from swarmex.worlds import GridWorld, empty_grid, load_movingai


@contextmanager
def plain_search() -> Iterator[None]:
    """``lattice.far_choice`` without the sum's bound, for the reference run."""
    searched = lattice.far_choice

    def plain(width, height, sx, sy, klass, ctpu, cjt, status, reserved, me, step, tpu_me,
              jt_me, block, far, mins, dead):  # type: ignore[no-untyped-def]
        found, tied, scanned, _ = lattice._far_search(
            width, height, sx, sy, klass, ctpu, cjt, status, reserved, me, step, tpu_me,
            jt_me, block, far, mins, dead, False)
        return found, tied, scanned

    lattice.far_choice = plain
    try:
        yield
    finally:
        lattice.far_choice = searched


@contextmanager
def every_rival() -> Iterator[None]:
    """Branch 3 on hop rows as before: every near rival read at every vertex (no early
    drop), no groups, the whole utility matrix."""
    grouped, fused, searched = policies._rival_groups, policies._tied_top, policies.far_tiles

    def reading_all(*args):  # type: ignore[no-untyped-def]
        return searched(*args, False)

    policies._rival_groups = policies.each_rival_alone
    policies._tied_top = policies.tied_top_by_matrix
    policies.far_tiles = reading_all
    try:
        yield
    finally:
        policies._rival_groups, policies._tied_top = grouped, fused
        policies.far_tiles = searched


def timed(world: GridWorld, agents: int, events: int | None) -> tuple[float, str, bool]:
    """CPU seconds, fingerprint and completeness of MADGTA from the first free cell (2.22 s
    an edge, 10 s a job, seed 0)."""
    nest = int(np.flatnonzero(world.free.ravel())[0])
    t0 = time.process_time()
    run = run_traversal(world, uniform_agents([nest] * agents, 2.22, 10.0), seed=0,
                        max_events=events)
    return time.process_time() - t0, run_fingerprint(run), run.complete


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--side", type=_cli.positive_int, default=1000)
    ap.add_argument("--map", type=_cli.map_file,
                    help="a MovingAI map (walled: hop rows) instead: a path, or a name in"
                         " $SWARMEX_MAPS (den520d.map)")
    ap.add_argument("--agents", type=_cli.positive_int, nargs="+", default=[16, 64])
    ap.add_argument("--events", type=_cli.positive_int, default=400)
    ap.add_argument("--full", action="store_true", help="also run each team to the end")
    args = ap.parse_args(argv)
    world = load_movingai(args.map) if args.map else empty_grid(args.side, args.side)
    reference = every_rival if args.map else plain_search
    timed(world if args.map else empty_grid(64, 64), 8, 2000)  # numba
    where = args.map.name if args.map else f"{args.side} x {args.side}"
    ours, theirs = ("groups", "each rival") if args.map else ("sum bound", "plain")
    print(f"MADGTA from one nest on {where}, first {args.events} events")
    print(f"{'agents':>6} {ours + ' s':>12} {theirs + ' s':>13} {'ratio':>7}  same run")
    for agents in args.agents:
        fast, fp_fast, _ = timed(world, agents, args.events)
        with reference():
            slow, fp_slow, _ = timed(world, agents, args.events)
        print(f"{agents:>6} {fast:>12.2f} {slow:>13.2f} {slow / fast:>6.1f}x  "
              f"{'yes' if fp_fast == fp_slow else 'NO'}")
    if args.full:
        for agents in args.agents:
            cpu, _, complete = timed(world, agents, None)
            print(f"{agents} agents to the end: {cpu:.1f} s CPU, complete={complete}")
    return 0


if __name__ == "__main__":
    _cli.run(main)
