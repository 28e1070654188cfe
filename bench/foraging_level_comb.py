"""A comb that never shears: what a team that stays together costs and gives (issue 17.3).

docs/foraging.md ("Can any pattern meet the target?") asks for a pattern whose exploration
time E is near its floor and whose time after the discovery Q is near Q_min at once. Comb
(``--algorithm comb``) explores at nearly the floor but its staircase turns shear the team, so
the word travels slowly (communication + overlap 130–240 rounds). This script measures the
other extreme, a *level* comb, on the RANDOM cells at N = 16 (128 × 128, k = 100, Relay-Food,
the seed communication rule): the same bands, loop and deployment as Comb, but every turn
shifts the whole comb n rows along the border column, so the n robots stand in n adjacent rows
of one column in every round. Two communication rules:

* ``level comb, route kept``: an informed robot keeps to its route while it tells its
  neighbours, as Strips' robots do (§4.1, the pattern's ``follow_path_comm``): the
  neighbour in the next row is at distance 1 in the next round, so the word passes one row
  per round;
* ``level comb, seed detour``: the seed rule's default for a pattern without that flag (detour
  at once to meet the neighbours). The robot that has just been told loses a round and then
  trails its neighbour by one column, moving away at the same speed: it cannot catch up before
  the border.

Why the turns cost: a turn that keeps the comb level and revisits no cell does not exist for
n ≥ 2. Its n paths would be disjoint, so in the plane they nest, and the outermost (the robot
farthest from the next band) would have to visit the whole border column of both bands, 2n
cells, in the rounds the others need to cross only n of them. The shift turn revisits n − 1
rounds' worth of cells at each of the comb's turns.

For each pattern the script prints the exact mean E over every cell (from the timetable), and
on the cells: mean E, communication + overlap, Q, Q − Q_min (Q_min from
:func:`~swarmex.missions.foraging.floor.least_transport`, or read from the ``--floors`` file of
bench/compare_foraging_patterns.py), the noise-free estimate (exact E + mean Q) against
Strips', and the exact E the pattern would need, with its own Q, to be 10 % below Strips.

    PYTHONPATH=src python bench/foraging_level_comb.py [--per-band 40] [--seed 2015]
        [--floors floors.json] [--floor-search 40] [--transport relay-food]

``--transport`` runs every pattern with another seed transport (Q − Q_min still subtracts
Relay-Food's Q_min): Relay-Path lowers every pattern's Q by 6–17 rounds and End-to-End raises
it by 130–160, so neither opens the target.

About 3 s of CPU, 5 s when it computes Q_min rather than reading it.
"""

from __future__ import annotations

import os
import time
from dataclasses import replace

import numpy as np

import _cli
from compare_foraging_patterns import read_floors
from swarmex.missions.foraging import comb, timed_plan
from swarmex.missions.foraging.floor import least_transport
from swarmex.missions.foraging.grid import Cell
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.run import phase_metrics
from swarmex.missions.foraging.sim import run_mission
from swarmex.missions.foraging.timed import Timed, execute
from swarmex.missions.foraging.transport import RELAY_FOOD, TRANSPORTS
from swarmex.studies.foraging.design import UNITS, G, food_cells

N = 16
BAND = "random"


def level_routes(g: int, n: int) -> tuple[list[list[Cell]], list[int]]:
    """Comb's passes (:func:`~swarmex.missions.foraging.comb.passes`) with level turns: at the
    end of a pass every robot walks n rows along the border column, so robot ``a`` keeps row
    ``rows[a] + (band − first band) · n`` and all share one column in every round."""
    ps = comb.passes(g, n)
    first_rows = [ps[0][0] * n + r for r in range(n)]
    rows = list(first_rows)
    col = ps[0][1]
    out: list[list[Cell]] = [[(col, y)] for y in rows]
    for j, (band, _, last, d) in enumerate(ps):
        for a in range(n):
            out[a].extend((x, rows[a]) for x in range(col + d, last + d, d))
        col = last
        if j + 1 == len(ps):
            break
        v = ps[j + 1][0] - band  # -1: the next band is above, +1: below
        for a in range(n):
            out[a].extend((col, rows[a] + v * s) for s in range(1, n + 1))
            rows[a] += v * n
    return out, first_rows


def level_plan(g: int, n: int, keep_route: bool) -> Plan:
    name = f"level comb, {'route kept' if keep_route else 'seed detour'}"
    return replace(comb.deployed(name, g, n, *level_routes(g, n)), follow_path_comm=keep_route)


def check_level(timed: Timed) -> None:
    """The premise of the measurement: from the synchronised start on, every robot stands in
    the same column in every round and the team visits every cell."""
    pos = timed.pos[timed.t_sync :]
    if (pos[:, :, 0] != pos[:, :1, 0]).any():
        raise AssertionError(f"{timed.plan.algorithm}: the comb is not level")
    seen = np.zeros((timed.plan.g, timed.plan.g), dtype=bool)
    seen[timed.pos[:, :, 0], timed.pos[:, :, 1]] = True
    if not seen.all():
        raise AssertionError(f"{timed.plan.algorithm}: {int((~seen).sum())} cells never visited")


def exact_e(timed: Timed) -> float:
    """Mean discovery round over every cell but the nest (uniform food without sampling
    error)."""
    first = timed.first_visits()
    return float(first[first >= 0].mean())


def q_min(cells: list[Cell], floors_file: str | None, search: int) -> np.ndarray:
    """Q_min per cell: from compare_foraging_patterns.py's ``--floors`` file when it has the
    same cells (its entries are per band index), else computed here."""
    if floors_file and os.path.exists(floors_file):
        saved = read_floors(floors_file)
        if all((BAND, i, N) in saved for i in range(len(cells))):
            return np.array([saved[(BAND, i, N)][0] for i in range(len(cells))], dtype=float)
    return np.array([least_transport(G, c, N, UNITS, budget=search)[0] for c in cells], float)


def cells_parser(description: str) -> _cli.Parser:
    """The options of a measurement on the RANDOM cells at N = 16 (this script's and
    bench/foraging_spoke.py's): how many cells, their seed, and where Q_min comes from."""
    ap = _cli.Parser(description=description)
    ap.add_argument("--per-band", type=_cli.paired_count, default=40)
    ap.add_argument("--seed", type=_cli.nonneg_int, default=2015)
    ap.add_argument(
        "--floors",
        help="compare_foraging_patterns.py's --floors file; read with the default --seed only "
        "(the file does not record its cells), else Q_min is computed",
    )
    ap.add_argument("--floor-search", type=_cli.positive_int, default=40)
    return ap


def main(argv: list[str] | None = None) -> int:
    ap = cells_parser(__doc__.splitlines()[0])
    ap.add_argument(
        "--transport", choices=TRANSPORTS, default=RELAY_FOOD,
        help="the seed transport every pattern runs (Q_min is Relay-Food's in every case)",
    )  # fmt: skip
    a = ap.parse_args(argv)
    cells = food_cells(a.seed, 40)[BAND][: a.per_band]
    t0 = time.process_time()
    tables = {p.algorithm: execute(p) for p in (level_plan(G, N, True), level_plan(G, N, False))}
    for timed in tables.values():
        check_level(timed)
    tables["comb (staircase)"] = timed_plan("comb", G, N)
    tables["strips"] = timed_plan("strips", G, N)
    qmin = q_min(cells, a.floors if a.seed == 2015 else None, a.floor_search)
    rows = {}
    for name, timed in tables.items():
        runs = [run_mission(timed, c, UNITS, a.transport, record=False) for c in cells]
        e = np.array([o.discovery for o in runs], dtype=float)
        q = np.array([o.makespan for o in runs], dtype=float) - e
        phases = [phase_metrics(o, timed) for o in runs]
        co = np.array([m["communication_time"] + m["comm_transport_overlap"] for m in phases])
        rows[name] = (exact_e(timed), e.mean(), co.mean(), q, q - qmin)
    strips_nf = rows["strips"][0] + rows["strips"][3].mean()
    print(
        f"N = {N}, {len(cells)} {BAND} cells (seed {a.seed}), k = {UNITS}, {a.transport}; "
        f"CPU {time.process_time() - t0:.0f} s; Q_min mean {qmin.mean():.0f}"
    )
    print()
    print(
        "| pattern | exact E | E (cells) | C + O | Q | Q − Q_min (median; cells > 90) "
        "| exact E + Q | against Strips | exact E needed for −10 % |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (ee, e, co, q, excess) in rows.items():
        nf = ee + q.mean()
        print(
            f"| {name} | {ee:.0f} | {e:.0f} | {co:.0f} | {q.mean():.0f} | {excess.mean():.0f} "
            f"({np.median(excess):.0f}; {int((excess > 90).sum())}) | {nf:.0f} | "
            f"{100 * (nf / strips_nf - 1):+.1f} % | {0.9 * strips_nf - q.mean():.0f} |"
        )
    print()
    print(f"Any pattern's exact E is at least (g² − 1)/(2n) = {(G * G - 1) / (2 * N):.0f}.")
    return 0


if __name__ == "__main__":
    _cli.run(main)
