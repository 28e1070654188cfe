"""A team leaving one nest on a large open grid: branch 3 with and without the sum's bound.

While the team stands together most of the map ties at the max-min (docs/traversal.md, "Many
agents on one nest"), and ``lattice.far_choice`` used to gather and score every tied vertex
for Algorithm 2's tie-break by the sum over rivals. It now goes on by a bound of that sum
once no region can beat the best max-min, and skips the regions that cannot reach the best
tied sum. For each team size this runs the first ``--events`` events of MADGTA from the
grid's first cell twice in one process, with the search as it is and with the plain search
(the same kernel, the sum's bound off), checks that both runs are the same (their
fingerprints: every agent's path, jobs and times), and prints the CPU seconds and their
ratio. ``--full`` then runs each team to the end with the search as it is.

Before the table a small run loads numba's kernels (compiled or from the disk cache),
untimed, so the first timed run does not pay it.

    .venv/bin/python bench/traversal_crowd.py                        # ~1 min
    .venv/bin/python bench/traversal_crowd.py --agents 64 --full     # + a 1000 x 1000 run, ~3 min
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

import _cli
from swarmex.missions.traversal import lattice, run_traversal, uniform_agents
from swarmex.missions.traversal.metrics import run_fingerprint
from swarmex.worlds import empty_grid


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


def timed(side: int, agents: int, events: int | None) -> tuple[float, str, bool]:
    """CPU seconds, fingerprint and completeness of MADGTA from cell 0 (2.22 s an edge, 10 s
    a job, seed 0)."""
    world = empty_grid(side, side)
    t0 = time.process_time()
    run = run_traversal(world, uniform_agents([0] * agents, 2.22, 10.0), seed=0,
                        max_events=events)
    return time.process_time() - t0, run_fingerprint(run), run.complete


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--side", type=_cli.positive_int, default=1000)
    ap.add_argument("--agents", type=_cli.positive_int, nargs="+", default=[16, 64])
    ap.add_argument("--events", type=_cli.positive_int, default=400)
    ap.add_argument("--full", action="store_true", help="also run each team to the end")
    args = ap.parse_args(argv)
    timed(64, 8, 2000)  # numba's one-time load, untimed
    print(f"MADGTA from one nest on {args.side} x {args.side}, first {args.events} events")
    print(f"{'agents':>6} {'sum bound s':>12} {'plain s':>9} {'ratio':>7}  same run")
    for agents in args.agents:
        fast, fp_fast, _ = timed(args.side, agents, args.events)
        with plain_search():
            slow, fp_slow, _ = timed(args.side, agents, args.events)
        print(f"{agents:>6} {fast:>12.2f} {slow:>9.2f} {slow / fast:>6.1f}x  "
              f"{'yes' if fp_fast == fp_slow else 'NO'}")
    if args.full:
        for agents in args.agents:
            cpu, _, complete = timed(args.side, agents, None)
            print(f"{agents} agents to the end: {cpu:.1f} s CPU, complete={complete}")
    return 0


if __name__ == "__main__":
    _cli.run(main)
