"""What announcing the rivals' branch-3 targets could buy at best: an oracle over MADGTA.

MADGTA's C05 announces an agent's next *node*, not the distant vertex it is heading for
(branch 3). Would one more field in C05, the target, let the team avoid sending two
travellers to one vertex, or a sweeper to a traveller's target? This bench answers with an
oracle that is better than any such message: the simulator's one policy object remembers
every agent's current branch-3 target, and while an agent decides, its rivals' targets
count as reserved by them (in KM). A target stops being one when its agent decides again.
It is not a decentralized method (the policy object is shared), only an upper bound on
what the message could do (docs/traversal-variants.md §5, "The rivals' targets known
exactly"):

* ``oracle-targets``: the rivals' targets are reserved for branch 3 only (two travellers
  never share a target; a sweeper may still take a traveller's target);
* ``oracle-targets-both``: reserved for branch 2 as well (sweepers leave them to their
  traveller).

Runs as bench/compare_traversal_variants.py does (16 identical agents, 2 s per edge, 9 s
per job, both nest modes, the same nests and seeds), serially, and prints each oracle's
makespan against MADGTA: per map, on the three small and the two large maps, and pooled
over every map run in the row "all" (paired relative Δ, Student-t 95 % intervals). A group
row is left out when it would repeat another row (one small map given, or only small maps);
"all" is always printed, also after a single map's row.

    .venv/bin/python bench/traversal_targets_oracle.py            # 120 runs, about 2 min
    .venv/bin/python bench/traversal_targets_oracle.py --seeds 8 --runs oracle.jsonl
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import _cli

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_traversal_variants import (  # noqa: E402
    MAPS,
    NEST_MODES,
    Job,
    load,
    map_name,
    paired_ci,
    run_all,
    select,
)
from swarmex.missions.traversal.belief import TraversalBelief  # noqa: E402
from swarmex.missions.traversal.policies import POLICIES, Decision, Madgta  # noqa: E402

SMALL = ["empty-16-16", "random-32-32-20", "room-32-32-4"]
LARGE = ["random-64-64-20", "warehouse-10-20-10-2-1"]


class TargetsOracle(Madgta):
    """MADGTA whose deciding agent sees its rivals' current branch-3 targets as reserved
    (for branch 3 only; :class:`TargetsOracleBoth`: for branch 2 as well). One object
    serves every agent of a run, which is what makes it an oracle."""

    name = "oracle-targets"
    both = False

    def __init__(self) -> None:
        self.targets: dict[int, int] = {}  # agent -> its current branch-3 target

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        me = belief.me
        self.targets.pop(me, None)  # deciding again ends its last target
        if not self.both:
            state = rng.bit_generator.state
            plain = super().decide(belief, rng)
            if plain.branch != 3:
                return plain
            rng.bit_generator.state = state  # branch 3 again, from the same draws
        marks = [(v, a) for a, v in self.targets.items()
                 if belief.status[v] == 0 and belief.reserved[v] == 0]
        for v, a in marks:
            belief.reserved[v] = a
        try:
            decision = super().decide(belief, rng)
        finally:
            for v, _ in marks:
                belief.reserved[v] = 0
        if decision.branch == 3:
            self.targets[me] = int(decision.target)
        return decision


class TargetsOracleBoth(TargetsOracle):
    name = "oracle-targets-both"
    both = True


ORACLES = {cls.name: cls for cls in (TargetsOracle, TargetsOracleBoth)}


def relative(rows: list[dict], maps: list[str], variant: str) -> tuple[np.ndarray, int]:
    """``variant``'s makespan / MADGTA's − 1 for every paired run on ``maps``, and its wins."""
    rel = []
    for mp in maps:
        for mode in NEST_MODES:
            base = select(rows, map=mp, mode=mode, algorithm="madgta")
            ours = select(rows, map=mp, mode=mode, algorithm=variant)
            rel += [o["makespan"] / b["makespan"] - 1.0
                    for b, o in zip(base, ours, strict=True)]
    r = np.array(rel)
    return r, int((r < 0).sum())


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    # a map the folder lacks is refused at once (it printed an empty table and exit 0)
    ap.add_argument("--maps", nargs="+", type=map_name, choices=MAPS, default=SMALL + LARGE)
    ap.add_argument("--seeds", type=_cli.paired_count, default=4)
    ap.add_argument("--agents", type=_cli.positive_int, default=16)
    ap.add_argument("--runs", type=_cli.out_file, default=None,
                    help="a JSON-lines file: finished runs are appended and reused")
    args = ap.parse_args(argv)
    POLICIES.update(ORACLES)  # by name, for the runs of this process (run serially)
    present = [m for m in args.maps if load(m) is not None]
    algorithms = ["madgta", *ORACLES]
    jobs = [Job(mp, args.agents, mode, s, alg)
            for mp in present for mode in NEST_MODES for s in range(args.seeds)
            for alg in algorithms]
    print(f"{len(jobs)} runs on {', '.join(present) or 'no map'}", file=sys.stderr)
    rows = run_all(jobs, 1, args.runs) if jobs else []
    groups = [(mp, [mp]) for mp in present]
    for label, maps in (("the small maps", SMALL), ("the large maps", LARGE)):
        held = [m for m in maps if m in present]
        if len(held) > 1 and len(held) < len(present):  # else a map's row, or "all"'s
            groups.append((label, held))
    if present:
        groups.append(("all", present))  # the pooled row, always under this name
    print("| maps | runs | " + " | ".join(f"{v} against MADGTA" for v in ORACLES) + " |")
    print("|---|---|" + "---|" * len(ORACLES))
    for label, maps in groups:
        cells = []
        for variant in ORACLES:
            r, wins = relative(rows, maps, variant)
            d, half = paired_ci(r, np.zeros_like(r))
            cells.append(f"{100 * d:+.2f} % ± {100 * half:.2f} % ({wins}/{r.size})")
        print(f"| {label} | {r.size} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    _cli.run(main)
