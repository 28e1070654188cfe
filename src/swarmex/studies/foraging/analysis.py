"""The analysis of ``swarmex reproduce foraging``: mean phase times per configuration.

:func:`aggregate` turns the journaled runs into the table the figures and the report read,
``{(band, pattern, n, transport): {column: mean}}``; the single-robot and all-cell
exploration times come straight from the patterns' timetables, without simulation.
"""

from __future__ import annotations

import csv
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.studies.foraging.design import (
    BAND_LABEL,
    BANDS,
    COLUMNS,
    METRIC_OF,
    SINGLE,
    TABLE_CONFIGS,
    G,
)


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
        first = timed_plan(pattern, G, n).first_visits()
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
