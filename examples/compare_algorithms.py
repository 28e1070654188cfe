"""Compare traversal algorithms from Python: one run, a sweep, paired differences, a figure,
and a drawing of the run that differs most.

The library's whole workflow in one script (docs/api.md): ``swarmex.run`` for one run,
``swarmex.sweep`` for the product of algorithms, grid sizes and seeds (resumable: running the
script again reruns nothing), ``swarmex.compare`` for each algorithm against MADGTA pair by
pair on the same grids and seeds (a paired interval cancels the spread between seeds, which
the means' intervals keep), ``swarmex.plot`` for the figure, and ``swarmex.render`` to draw
a run from its record.

    PYTHONPATH=src python examples/compare_algorithms.py --out /tmp/compare   # 120 runs, ~45 s CPU
    PYTHONPATH=src python examples/compare_algorithms.py --out /tmp/compare --quick  # seconds

Outputs in ``--out``: the sweep folder ``sweep/`` (records and ``results.parquet``),
``makespan.png`` (mean makespan per grid and algorithm with 95 % intervals) and
``largest-gain.png`` (the paths of the run where the best variant gained most).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import swarmex

ALGORITHMS = ["madgta", "madgta+", "madgta-k", "nearest"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=Path("compare-algorithms"),
                    help="folder for the sweep and the figures (default: compare-algorithms)")
    ap.add_argument("--quick", action="store_true", help="two small grids, three seeds")
    args = ap.parse_args(argv)
    grids = ["8x8", "10x8"] if args.quick else ["12x12", "16x16", "20x20"]
    seeds = 3 if args.quick else 10
    algorithms = ALGORITHMS[:2] if args.quick else ALGORITHMS

    one = swarmex.run("traversal", grid=grids[0], agents=4, seed=0)
    print("one run:", one)

    table = swarmex.sweep("traversal", out=args.out / "sweep", algorithm=algorithms,
                          grid=grids, agents=4, obstacles="2,2;3,3;4,2", seeds=seeds)
    print(f"sweep: {table.num_rows} runs in {args.out / 'sweep'}")

    paired = swarmex.compare(table, {"algorithm": "madgta"}, ["makespan", "total_time_all"])
    print("\nagainst MADGTA, pooled over the grids (mean relative Δ, 95 % CI):")
    for row in paired.to_pylist():
        if row["grid"] is None:  # the pooled rows
            print(f"  {row['algorithm']:>9} {row['metric']:>15}: "
                  f"{100 * row['relative']:+.2f} % [{100 * row['relative_low']:+.2f},"
                  f" {100 * row['relative_high']:+.2f}] over {row['pairs']} pairs,"
                  f" lower in {row['lower_in']}")

    swarmex.plot(table, "grid", "makespan", hue="algorithm", out=args.out / "makespan.png")
    print(f"wrote {args.out / 'makespan.png'}")

    # the run where a variant gained most on MADGTA, drawn from its record file
    rows = [r for r in table.to_pylist() if not r["error"]]
    base = {(r["grid"], r["seed"]): r["makespan"] for r in rows if r["algorithm"] == "madgta"}
    best = min((r for r in rows if r["algorithm"] != "madgta"),
               key=lambda r: r["makespan"] / base[r["grid"], r["seed"]])
    record = args.out / "sweep" / "runs" / f"{best['run']}.json"
    swarmex.render(record, args.out / "largest-gain.png")
    print(f"wrote {args.out / 'largest-gain.png'} ({best['algorithm']} on {best['grid']},"
          f" seed {best['seed']}: {best['makespan']:.1f} s against MADGTA's"
          f" {base[best['grid'], best['seed']]:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
