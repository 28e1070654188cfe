"""``swarmex reproduce foraging``: the ch. 6 experiments of seed 002 beside the thesis's numbers.

Setup (ch. 6, spec §4): 128×128 grid, nest (64, 64); separation bands 0–20 … 80–100 % of the
corner–nest distance plus RANDOM; 40 food cells per band, drawn once from ``--seed`` and shared
by every pattern and n (the thesis does not say whether its patterns saw the same cells; sharing
them removes placement noise from the comparisons); n = 4, 8, 16 for the tables (ZigZag and
Hilbert: 4, 16; Modified ZigZag: 8), n = 1 added for the exploration figures; k = 100 units
(the released simulator's value; the thesis gives none); Relay-Food transport for the tables, as
the thesis; Fig. 69 compares the three transports on the RANDOM cells at n = 16 (8 for Modified
ZigZag). Sectors with n = 4 *is* ZigZag with n = 4, so those runs are shared.

Every finished run is appended to ``DIR/runs.jsonl`` at once (a rerun skips what is there), the
tables go to ``DIR/foraging_results.csv``, the figures to ``DIR/fig*.png`` and the report with
the thesis's Figs. 78–79 numbers side by side to ``DIR/foraging.md``.
"""

from __future__ import annotations

import csv
import json
import os
from collections import defaultdict
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.experiments.progress import read_journal, runs_progress
from swarmex.studies import reference_file

G = 128
UNITS = 100
BANDS = ("0-20", "20-40", "40-60", "60-80", "80-100", "random")
BAND_LABEL = {
    "0-20": "0%-20%",
    "20-40": "20%-40%",
    "40-60": "40%-60%",
    "60-80": "60%-80%",
    "80-100": "80%-100%",
    "random": "RANDOM",
}
TABLE_CONFIGS: tuple[tuple[str, int], ...] = (
    ("strips", 4),
    ("strips", 8),
    ("strips", 16),
    ("zigzag", 4),
    ("zigzag", 16),
    ("hilbert", 4),
    ("hilbert", 16),
    ("sectors", 8),
    ("sectors", 16),
    ("spiral", 4),
    ("spiral", 8),
    ("spiral", 16),
    ("modified-zigzag", 8),
    ("loop-strips", 4),
    ("loop-strips", 8),
    ("loop-strips", 16),
    ("rings", 4),
    ("rings", 8),
    ("rings", 16),
)
SINGLE = ("strips", "zigzag", "spiral")  # patterns the thesis defines for one robot
TRANSPORT_CONFIGS = (
    ("strips", 16),
    ("zigzag", 16),
    ("hilbert", 16),
    ("sectors", 16),
    ("spiral", 16),
    ("modified-zigzag", 8),
    ("loop-strips", 16),
    ("rings", 16),
)
COLUMNS = ("exploration", "communication", "comm_transport", "transportation")
METRIC_OF = {
    "exploration": "exploration_time",
    "communication": "communication_time",
    "comm_transport": "comm_transport_overlap",
    "transportation": "transport_time",
}


def food_cells(seed: int, per_band: int) -> dict[str, list[tuple[int, int]]]:
    from swarmex.missions.foraging.food import band_cells

    rng = np.random.default_rng(seed)
    out = {}
    for band in BANDS:
        cells = band_cells(G, band)
        idx = rng.choice(len(cells), size=per_band, replace=False)
        out[band] = [(int(cells[i][0]), int(cells[i][1])) for i in idx]
    return out


def run_key(pattern: str, n: int, band: str, i: int, transport: str) -> str:
    return f"{pattern}|{n}|{band}|{i}|{transport}"


def _one(task: tuple[str, int, str, int, tuple[int, int], str]) -> dict[str, Any]:
    from swarmex.missions.foraging import run_forage

    pattern, n, band, i, food, transport = task
    run = run_forage(pattern, G, n, food, UNITS, transport, record=False)
    return {
        "key": run_key(pattern, n, band, i, transport),
        "pattern": pattern,
        "n": n,
        "band": band,
        "i": i,
        "food": list(food),
        "transport": transport,
        **{k: v for k, v in run.metrics.items()},
        "wall": round(run.wall_seconds, 4),
    }


def tasks(foods: dict[str, list[tuple[int, int]]]) -> list[tuple[str, int, str, int, Any, str]]:
    out = []
    for pattern, n in TABLE_CONFIGS:
        for band in BANDS:
            for i, f in enumerate(foods[band]):
                out.append((pattern, n, band, i, f, "relay-food"))
    for pattern, n in TRANSPORT_CONFIGS:
        for transport in ("relay-path", "end-to-end"):
            for i, f in enumerate(foods["random"]):
                out.append((pattern, n, "random", i, f, transport))
    # long runs first so the two workers finish together
    out.sort(key=lambda t: (t[1], t[0] != "spiral"))
    return out


def execute(todo: list, runs_path: Path, workers: int) -> None:
    done = read_journal(runs_path)
    todo = [t for t in todo if run_key(t[0], t[1], t[2], t[3], t[5]) not in done]
    if not todo:
        return
    with (
        runs_path.open("a", encoding="utf-8") as fh,
        runs_progress("foraging") as bar,
    ):
        job = bar.add_task("runs", total=len(todo))
        if workers <= 1:
            for t in todo:
                fh.write(json.dumps(_one(t)) + "\n")
                fh.flush()
                bar.advance(job)
            return
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(_one, t) for t in todo]
            for fut in as_completed(futures):
                fh.write(json.dumps(fut.result()) + "\n")
                fh.flush()
                bar.advance(job)


def single_agent_exploration(foods: dict[str, list[tuple[int, int]]]) -> dict[tuple, float]:
    """n = 1 exploration times (Figs. 56–61): a look-up in the pattern's timetable."""
    from swarmex.missions.foraging import timed_plan

    out = {}
    for pattern in SINGLE:
        pos = timed_plan(pattern, G, 1).pos[:, 0]
        first: dict[tuple[int, int], int] = {}
        for t, (x, y) in enumerate(pos):
            first.setdefault((int(x), int(y)), t)
        for band, cells in foods.items():
            out[(band, pattern, 1)] = float(np.mean([first[c] for c in cells]))
    return out


def exact_exploration() -> dict[tuple[str, int], float]:
    """Mean exploration time over *all* non-nest cells (uniform food), from the timetables.

    Noise-free: the 40-cell band means carry a sampling error of ≈ ±(g²/n)/√(12·40) rounds,
    larger than some of the differences between patterns.
    """
    from swarmex.missions.foraging import timed_plan

    out = {}
    configs = {(p, n) for p, n in TABLE_CONFIGS} | {("sectors", 4)}
    configs |= {(p, 1) for p in SINGLE}
    for pattern, n in sorted(configs):
        pos = timed_plan(pattern, G, n).pos
        first = np.full((G, G), -1, dtype=np.int64)
        for t in range(len(pos) - 1, -1, -1):
            first[pos[t, :, 0], pos[t, :, 1]] = t
        first[G // 2, G // 2] = -1
        out[(pattern, n)] = float(first[first >= 0].mean())
    return out


def aggregate(runs: dict[str, dict[str, Any]]) -> dict[tuple, dict[str, float]]:
    """Means per (band, pattern, n, transport) of the four phase columns and totals."""
    acc: dict[tuple, list[dict[str, Any]]] = defaultdict(list)
    for r in runs.values():
        acc[(r["band"], r["pattern"], r["n"], r["transport"])].append(r)
    out = {}
    for key, rs in acc.items():
        row = {c: float(np.mean([r[METRIC_OF[c]] for r in rs])) for c in COLUMNS}
        row["total"] = float(np.mean([r["total_time"] for r in rs]))
        row["cells_revisited"] = float(np.mean([r["cells_revisited"] for r in rs]))
        row["runs"] = len(rs)
        out[key] = row
    # Sectors with 4 robots is ZigZag with 4 robots (thesis §3.4.1)
    for band in BANDS:
        zz = out.get((band, "zigzag", 4, "relay-food"))
        if zz is not None:
            out[(band, "sectors", 4, "relay-food")] = dict(zz)
    return out


def reference() -> dict[tuple, dict[str, float]]:
    text = reference_file("foraging_fig78_79.csv").read_text(encoding="utf-8")
    inv = {v: k for k, v in BAND_LABEL.items()}
    out = {}
    for row in csv.DictReader(text.splitlines()):
        key = (inv[row["separation"]], row["pattern"], int(row["agents"]))
        out[key] = {c: float(row[c]) for c in COLUMNS}
        out[key]["total"] = sum(out[key][c] for c in COLUMNS)
    return out


def write_csv(table: dict[tuple, dict[str, float]], path: Path) -> None:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["separation", "pattern", "agents", "transport", *COLUMNS, "total", "runs"])
        for (band, pattern, n, transport), row in sorted(table.items()):
            w.writerow(
                [BAND_LABEL[band], pattern, n, transport]
                + [round(row[c], 1) for c in (*COLUMNS, "total")]
                + [row["runs"]]
            )


def reproduce(out: Path, quick: bool = False, workers: int = 2, seed: int = 2015) -> Path:
    from swarmex.viz.foraging_figures import all_figures
    from swarmex.viz.foraging_report import write_report

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    per_band = 1 if quick else 40
    foods = food_cells(seed, per_band)
    todo = tasks(foods)
    workers = max(1, min(workers, os.cpu_count() or 1))
    execute(todo, out / "runs.jsonl", workers)
    runs = read_journal(out / "runs.jsonl")
    keys = {run_key(t[0], t[1], t[2], t[3], t[5]) for t in todo}
    runs = {k: v for k, v in runs.items() if k in keys}
    table = aggregate(runs)
    single = single_agent_exploration(foods)
    write_csv(table, out / "foraging_results.csv")
    figures = all_figures(table, single, out)
    exact = exact_exploration()
    return write_report(
        out, table, single, reference(), figures, quick, seed, per_band, runs, exact
    )
