"""Which runs ``swarmex reproduce foraging`` makes: the ch. 6 experiments of seed 002.

Setup (ch. 6, spec §4): 128×128 grid, nest (64, 64); separation bands 0–20 … 80–100 % of the
corner–nest distance plus RANDOM; 40 food cells per band, drawn once from ``--seed`` and shared
by every pattern and n (the thesis does not say whether its patterns saw the same cells; sharing
them removes placement noise from the comparisons); n = 4, 8, 16 for the tables (ZigZag and
Hilbert: 4, 16; Modified ZigZag: 8), n = 1 added for the exploration figures; k = 100 units
(the released simulator's value; the thesis gives none); Relay-Food transport for the tables, as
the thesis; Fig. 69 compares the three transports on the RANDOM cells at n = 16 (8 for Modified
ZigZag). Sectors with n = 4 *is* ZigZag with n = 4, so those runs are shared.

The runs are :mod:`.runs`, executed by the study runner (every finished run is appended to
``DIR/runs.jsonl`` at once; a rerun skips what is there); :mod:`.analysis` averages them into
the table written to ``DIR/foraging_results.csv``, :mod:`.figures` draws ``DIR/fig*.png`` and
:mod:`.report` writes ``DIR/foraging.md`` with the thesis's Figs. 78–79 numbers
(:func:`reference`) side by side.
"""

from __future__ import annotations

import csv
from typing import Any

import numpy as np

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


def run_key(
    pattern: str, n: int, band: str, i: int, food: tuple[int, int], transport: str
) -> str:
    """A run's journal key. It holds the food cell, not just its index in the band: another
    ``--seed``, or ``--quick`` then a full run into the same folder, draws other cells for the
    same index, and a key without the cell resumed from runs made on the old ones."""
    return f"{pattern}|{n}|{band}|{i}|{food[0]},{food[1]}|{transport}"


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


def reference() -> dict[tuple, dict[str, float]]:
    text = reference_file("foraging_fig78_79.csv").read_text(encoding="utf-8")
    inv = {v: k for k, v in BAND_LABEL.items()}
    out = {}
    for row in csv.DictReader(text.splitlines()):
        key = (inv[row["separation"]], row["pattern"], int(row["agents"]))
        out[key] = {c: float(row[c]) for c in COLUMNS}
        out[key]["total"] = sum(out[key][c] for c in COLUMNS)
    return out


AUTHOR = "author"  # the band tag of the runs on the author's published cells
AUTHOR_PHASES = {  # our column -> the author's (start, end) time stamps
    "exploration": (None, "foodDiscoveryTS"),
    "communication": ("foodDiscoveryTS", "firstCommTS"),
    "comm_transport": ("firstCommTS", "firstTransTS"),
    "transportation": ("firstTransTS", "FoodTransportedTS"),
}


def author_rows() -> list[dict[str, Any]]:
    """The seed author's published simulator runs (Strips, N = 16; see the file's header):
    its separation label, the food cell and its four phase columns and total, per run."""
    text = reference_file("foraging_author_strips16.csv").read_text(encoding="utf-8")
    body = [line for line in text.splitlines() if not line.startswith("#")]
    out = []
    for row in csv.DictReader(body):
        phases = {
            c: float(row[end]) - (float(row[start]) if start else 0.0)
            for c, (start, end) in AUTHOR_PHASES.items()
        }
        food = (int(row["foodX"]), int(row["foodY"]))
        total = float(row["FoodTransportedTS"])
        out.append({"separation": row["separation"], "food": food, **phases, "total": total})
    return out


def author_tasks(rows: list[dict[str, Any]]) -> list[tuple[str, int, str, int, Any, str]]:
    """Our runs on the author's cells: Strips, N = 16, Relay-Food, one per published run."""
    return [("strips", 16, AUTHOR, i, r["food"], "relay-food") for i, r in enumerate(rows)]
