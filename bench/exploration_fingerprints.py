"""Exploration records old vs new: the fingerprints of ~20 runs at 5–40 robots.

The exploration scale work (issue 14 item 2) must not change any record. The test suite's
fingerprints (tests/missions/exploration/fingerprints.py) cover 5–20 robots on small maps;
this script adds the sizes where the O(robots²) costs showed: 20 seeds over 5, 10, 20 and
40 robots, open fields and the walled rooms map, long and short radios (the mesh splits and
re-joins), AODV on and off, at the resolution of the benchmark (5 cm cells, 2 m laser on the
20 × 20 m bench case).

Record with one tree's code, check with another's (same interpreter, PYTHONPATH picks the
tree):

    PYTHONPATH=/work/main/src python bench/exploration_fingerprints.py --record /tmp/old.json
    PYTHONPATH=src python bench/exploration_fingerprints.py --check /tmp/old.json

``--check`` prints one line per case (same / CHANGED, CPU seconds of each side) and exits 1
if any record differs; it runs the cases the file holds. ``--only`` picks cases by substring.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import _cli

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # the tests package, for the rooms map and digest

from tests.missions.exploration.fingerprints import digest, rooms_map  # noqa: E402


def cases(folder: Path) -> dict[str, dict[str, Any]]:
    """Name -> ``swarmex.run("exploration", ...)`` keywords: 20 runs, 5–40 robots."""
    out: dict[str, dict[str, Any]] = {}
    for n, seed in ((5, 11), (10, 12), (20, 13), (40, 14)):  # open 10 x 10 m, 5 cm
        out[f"open10-{n}-s{seed}"] = dict(empty=(10.0, 10.0), cell=0.05, robots=n,
                                          laser_range=1.5, comm_range=10.0, seed=seed)
    for n, seed in ((5, 21), (10, 22), (20, 23), (40, 24)):  # short radio: splits, AODV
        out[f"short-{n}-s{seed}"] = dict(empty=(10.0, 10.0), cell=0.05, robots=n,
                                         laser_range=1.5, comm_range=2.0, seed=seed)
    for n, seed in ((10, 31), (40, 32)):  # no AODV
        out[f"noaodv-{n}-s{seed}"] = dict(empty=(10.0, 10.0), cell=0.05, robots=n,
                                          laser_range=1.5, comm_range=3.0, aodv=False,
                                          seed=seed)
    rooms = rooms_map(folder)
    for n, seed in ((5, 41), (10, 42), (20, 43), (40, 44)):  # walls and doors
        out[f"rooms-{n}-s{seed}"] = dict(map=rooms, cell=0.125, robots=n, laser_range=1.0,
                                         comm_range=2.0, seed=seed)
    for n, st, seed in ((20, "greedy", 51), (20, "minpos", 52), (20, "hungarian-exclusion", 53)):
        out[f"{st}-{n}-s{seed}"] = dict(empty=(8.0, 8.0), cell=0.05, robots=n,
                                        laser_range=1.0, comm_range=3.0, strategy=st,
                                        seed=seed)
    for n, seed in ((10, 0), (40, 0), (40, 7)):  # the scale bench's case (20 x 20 m)
        out[f"bench-{n}-s{seed}"] = dict(empty=(20.0, 20.0), cell=0.05, robots=n,
                                         laser_range=2.0, comm_range=10.0, seed=seed)
    return out


def run_all(only: str | None, names: set[str] | None = None) -> dict[str, dict[str, Any]]:
    import swarmex

    swarmex.run("exploration", empty="3x3", robots=2, laser_range=0.8)  # compile / load
    table: dict[str, dict[str, Any]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, kw in cases(Path(tmp)).items():
            if (only and only not in name) or (names is not None and name not in names):
                continue
            c0 = time.process_time()
            rec = swarmex.run("exploration", **kw).to_dict()
            cpu = time.process_time() - c0
            table[name] = {"sha256": digest(rec), "makespan": rec["makespan"],
                           "messages_sent": rec["metrics"].get("messages_sent"), "cpu": cpu}
            print(f"  {name}: makespan {rec['makespan']}, {cpu:.2f} s CPU", file=sys.stderr,
                  flush=True)
    return table


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    group = ap.add_mutually_exclusive_group(required=True)
    group.add_argument("--record", type=Path, help="write this tree's fingerprints here")
    group.add_argument("--check", type=Path, help="compare with fingerprints written before")
    ap.add_argument("--only", help="run only the cases whose name contains this")
    args = ap.parse_args(argv)
    # the files first: the runs take a minute, and a typo should not cost it
    if args.record and not args.record.resolve().parent.is_dir():
        ap.error(f"--record: folder {args.record.resolve().parent} does not exist")
    old = json.loads(args.check.read_text()) if args.check else {}
    if args.only:  # a name no case has ran nothing, wrote {} and exited 0
        with tempfile.TemporaryDirectory() as tmp:  # cases() writes the rooms map
            names = list(cases(Path(tmp)))
        if not any(args.only in name for name in names):
            ap.error(f"--only {args.only}: no case's name contains it (have: {', '.join(names)})")
    # a check runs the cases the file holds: `--record F --only rooms-5` then `--check F`
    # ran all 20 and reported 19 of them missing (exit 1)
    table = run_all(args.only, set(old) if args.check else None)
    if args.record:
        args.record.write_text(json.dumps(table, indent=1, sort_keys=True) + "\n")
        return 0
    bad = 0
    cpu_old = cpu_new = 0.0
    for name, new in table.items():
        ref = old.get(name)
        if ref is None:
            print(f"{name:32s} not in {args.check}")
            bad += 1
            continue
        same = ref["sha256"] == new["sha256"]
        bad += not same
        cpu_old += ref["cpu"]
        cpu_new += new["cpu"]
        print(f"{name:32s} {'same' if same else 'CHANGED':8s} makespan {new['makespan']:6g}  "
              f"CPU {ref['cpu']:6.2f} -> {new['cpu']:6.2f} s")
    print(f"{len(table) - bad} of {len(table)} records identical; CPU {cpu_old:.1f} -> "
          f"{cpu_new:.1f} s (ratio {cpu_new / max(cpu_old, 1e-9):.2f}; separate processes, "
          "so only a rough guide on a shared machine)")
    return 1 if bad else 0


if __name__ == "__main__":
    _cli.run(main)
