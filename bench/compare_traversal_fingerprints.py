"""Same traversal decisions as a reference revision: run fingerprints, old code vs new.

Speed work on the traversal policy must not change a single decision. This script runs a
set of cases (random walled maps, the MovingAI maps in ``$SWARMEX_MAPS`` including
den520d, empty grids, MADGTA and the nearest baseline, equal and mixed teams) for several
seeds with the code of this tree and with the code of a reference git revision (exported
with ``git archive`` into a temporary folder, run in its own process with its own numba
cache), and compares the fingerprints (``metrics.run_fingerprint``: the record, the paths,
the branch counts, who did what, the messages). Prints one line per case and the number of
mismatches; exits 1 if there is any.

    PYTHONPATH=src .venv/bin/python bench/compare_traversal_fingerprints.py            # vs main
    PYTHONPATH=src .venv/bin/python bench/compare_traversal_fingerprints.py --seeds 5 --rev HEAD~3
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import _cli

HERE = Path(__file__).resolve().parent
REPO = HERE.parent


maps_dir = _cli.maps_dir  # $SWARMEX_MAPS, default ../shared/maps


def cases(seeds: int, den_events: int) -> list[dict[str, Any]]:
    """The cases: JSON-able descriptions that :func:`run_case` understands."""
    out: list[dict[str, Any]] = []
    for seed in range(seeds):
        out += [
            {"map": "random", "side": 40, "density": 0.2, "agents": 6, "seed": seed},
            {"map": "random", "side": 56, "density": 0.3, "agents": 12, "seed": seed},
            {"map": "random", "side": 32, "density": 0.1, "agents": 4, "seed": seed,
             "algorithm": "nearest"},
            {"map": "random", "side": 36, "density": 0.25, "agents": 5, "seed": seed,
             "mixed": True},
            {"map": "empty", "side": 48, "agents": 8, "seed": seed},
            {"map": "file", "name": "random-64-64-20.map", "agents": 8, "seed": seed},
            {"map": "file", "name": "room-32-32-4.map", "agents": 6, "seed": seed},
        ]
    for seed in range(min(seeds, 4)):
        out.append({"map": "file", "name": "den520d.map", "agents": 16, "seed": seed,
                    "max_events": den_events})
    return out


def run_case(case: dict[str, Any]) -> str:
    """The fingerprint of one case, with whatever ``swarmex`` this process imports."""
    import numpy as np

    from swarmex.missions.traversal import AgentSpec, run_traversal, uniform_agents
    from swarmex.missions.traversal.metrics import run_fingerprint
    from swarmex.worlds import empty_grid, load_movingai, random_obstacles

    seed = int(case["seed"])
    if case["map"] == "random":
        world = random_obstacles(case["side"], case["side"], case["density"], seed=seed)
    elif case["map"] == "empty":
        world = empty_grid(case["side"], case["side"])
    else:
        path = maps_dir() / case["name"]
        if not path.exists():
            return SKIPPED
        world = load_movingai(path)
    free = np.flatnonzero(~world.blocked)
    rng = np.random.default_rng(seed + 1000)
    nests = [int(v) for v in rng.choice(free, 2, replace=False)]
    n = int(case["agents"])
    if case.get("mixed"):
        specs = [AgentSpec(nests[i % 2], 1.0 + 0.5 * (i % 3), 0.5 + (i % 2)) for i in range(n)]
    else:
        specs = uniform_agents([nests[i % 2] for i in range(n)], 1.0, 1.0)
    run = run_traversal(world, specs, algorithm=case.get("algorithm", "madgta"), seed=seed,
                        max_events=case.get("max_events"))
    return run_fingerprint(run)


SKIPPED = "skipped (map not found)"


def child(path: str) -> None:
    for line in Path(path).read_text().splitlines():
        print(run_case(json.loads(line)), flush=True)


def fingerprints(src: Path, todo: list[dict[str, Any]], cache: Path) -> list[str]:
    with tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False) as fh:
        fh.write("\n".join(json.dumps(c) for c in todo))
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache)}
    proc = subprocess.run([sys.executable, __file__, "--child", fh.name], env=env,
                          capture_output=True, text=True, check=False)
    os.unlink(fh.name)
    if proc.returncode != 0:
        raise SystemExit(f"run with {src} failed:\n{proc.stderr[-2000:]}")
    return proc.stdout.splitlines()


def main() -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--rev", default="main", help="reference git revision (default main)")
    ap.add_argument("--seeds", type=_cli.positive_int, default=20,
                    help="seeds per case (default 20)")
    ap.add_argument("--den-events", type=_cli.positive_int, default=60_000,
                    help="events of each den520d run (default 60,000)")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.child)
        return 0
    todo = cases(args.seeds, args.den_events)
    with tempfile.TemporaryDirectory() as tmp:
        ref = Path(tmp) / "ref"
        ref.mkdir()
        got = subprocess.run(["git", "-C", str(REPO), "archive", args.rev, "src"],
                             capture_output=True)
        if got.returncode:  # an unknown revision, or no git checkout: git's own words
            why = got.stderr.decode(errors="replace").strip().splitlines()
            ap.error(f"--rev {args.rev}: {why[0] if why else 'git archive failed'}")
        archive = got.stdout
        subprocess.run(["tar", "-x", "-C", str(ref)], input=archive, check=True)
        new = fingerprints(REPO / "src", todo, Path(tmp) / "cache-new")
        old = fingerprints(ref / "src", todo, Path(tmp) / "cache-ref")
    bad = skipped = 0
    for case, a, b in zip(todo, new, old, strict=True):
        label = ", ".join(f"{k}={v}" for k, v in case.items())
        if SKIPPED in (a, b):  # not compared: it must not count as the same
            skipped += 1
            print(f"{'skipped':9s} {'(no map)':16s}  {label}")
            continue
        same = a == b
        bad += not same
        print(f"{'same' if same else 'DIFFERENT':9s} {a[:16]}  {label}")
    compared = len(todo) - skipped
    tail = f", {skipped} skipped: map not found in {maps_dir()}" if skipped else ""
    print(f"{compared} cases compared, {bad} different (reference: {args.rev}){tail}")
    return 1 if bad else 0


if __name__ == "__main__":
    _cli.run(main)
