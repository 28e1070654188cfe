"""Our foraging patterns against the best seed pattern per separation band (issue 17, item 3).

Regenerates the table of docs/foraging.md ("Beyond the seed: Sector Loop"): the reproduction's
setup (128×128 grid, nest (64, 64), k = 100 units, Relay-Food, the seed's communication rule
``--comm seed``), the same food cells for every pattern (``food_cells(2015, 40)``: 40 cells per
band 0–20 … 80–100 % and RANDOM), N = 8 and 16. For each of our patterns and each (band, N) it
prints the mean total time, the best seed pattern (strips, zigzag, hilbert, sectors, spiral;
lowest mean on the same cells) and the paired difference, ours − best, on the same cells, with
a t and a bootstrap 95 % interval. A difference is significant when its interval excludes 0.

    PYTHONPATH=src python bench/compare_foraging_patterns.py [--per-band 40] [--workers 2]
        [--ours comb,sector-loop,loop-strips,recall] [--raw runs.json | --load runs.json]
        [--floor-search 40] [--floors floors.json]

Every run goes through the mission contract (``registry.get("foraging")``), like
``swarmex reproduce foraging``. 40 cells: 1,920 seed runs plus 480 per pattern of ours; about
0.15 s of CPU each after the timetables (≈ 6 min on 2 workers). ``recall`` runs each (band, N)
as 40 trips whose memory is the band's earlier cells (docs/foraging.md, "Recall"); its trips
also replay the patterns (≈ 10 min of CPU for its 480 trips), and a table of what it chose
follows the comparison.

Then the exploration budgets ("Can any pattern meet the target?" in docs/foraging.md): for
every food cell and N, Q_min (the real Relay-Food run from the best start state found,
:func:`~swarmex.missions.foraging.floor.least_transport`) and the proven floor
(:func:`~swarmex.missions.foraging.floor.proven_floor`), checked against every measured run,
and the budget table under the empirical floor, Q_min and the proven floor, with standard
errors. The floors cost ≈ 170 s of CPU in this process (``--floors FILE`` keeps them);
``--load`` reuses the runs of an earlier ``--raw``.
"""

from __future__ import annotations

import json
import os
import time
from typing import Any

import numpy as np

import _cli
from swarmex.engine.record import write_json_atomic
from swarmex.missions.foraging.patterns import ALGORITHMS as FORAGING_ALGORITHMS
from swarmex.studies.foraging.design import BAND_LABEL, BANDS, UNITS, G, food_cells

SEED_PATTERNS = ("strips", "zigzag", "hilbert", "sectors", "spiral")
NS = (8, 16)
Task = tuple[str, int, str, int, tuple[int, int], tuple[tuple[int, int], ...]]
RECALL = "recall"


def supports(pattern: str, n: int) -> bool:
    """The (pattern, N) pairs the reproduction runs: ZigZag and Hilbert need a power of 4."""
    return not (pattern in ("zigzag", "hilbert") and n not in (4, 16))


def run_one(task: Task) -> tuple[Task, float, dict[str, Any]]:
    from swarmex.missions.registry import get

    pattern, n, band, i, food, found = task
    mission = get("foraging")
    params = mission.params(
        algorithm=pattern, grid=G, agents=n, food=food, food_units=UNITS, transport="relay-food",
        found=found,
    )  # fmt: skip
    t0 = time.process_time()
    record = mission.run(params, trace=False).record
    return task, time.process_time() - t0, {**record.metrics, **record.extra}


def memory(pattern: str, cells: list[tuple[int, int]], i: int) -> tuple[tuple[int, int], ...]:
    """What the team remembers on trip ``i`` of a band: recall, the cells of trips 0 … i - 1
    (the choice replays the last MEMORY of them); a pattern, nothing."""
    return tuple(cells[:i]) if pattern == RECALL else ()


def choices(rows: list[tuple[Task, float, dict[str, Any]]]) -> list[str]:
    """How often recall chose each pattern per (band, N), and its mean total after the first
    eight trips of each band (once the memory holds several cells)."""
    acc: dict[tuple[int, str], list[tuple[int, str, float]]] = {}
    for (p, n, band, i, _, _), _, m in rows:
        if p == RECALL:
            acc.setdefault((n, band), []).append((i, str(m["pattern"]), m["total_time"]))
    lines = ["| N | band | patterns chosen (trips) | mean total, trips 8 on |", "|---|---|---|---|"]
    for (n, band), trips in sorted(acc.items(), key=lambda e: (e[0][0], BANDS.index(e[0][1]))):
        names: dict[str, int] = {}
        for _, name, _ in trips:
            key = "annulus" if name.startswith("annulus") else name
            names[key] = names.get(key, 0) + 1
        late = [t for i, _, t in trips if i >= 8]
        chosen = ", ".join(f"{k} {v}" for k, v in sorted(names.items(), key=lambda e: -e[1]))
        mean = f"{np.mean(late):.0f}" if late else "–"
        lines.append(f"| {n} | {BAND_LABEL[band]} | {chosen} | {mean} |")
    return lines


def t_interval(d: np.ndarray) -> tuple[float, float]:
    from scipy import stats

    half = stats.t.ppf(0.975, len(d) - 1) * d.std(ddof=1) / np.sqrt(len(d))
    return float(d.mean() - half), float(d.mean() + half)


def bootstrap_interval(d: np.ndarray, reps: int = 10_000, seed: int = 17) -> tuple[float, float]:
    rng = np.random.default_rng(seed)
    means = d[rng.integers(0, len(d), size=(reps, len(d)))].mean(axis=1)
    lo, hi = np.percentile(means, [2.5, 97.5])
    return float(lo), float(hi)


def table(totals: dict[tuple[str, int, str], np.ndarray], ours: list[str]) -> list[str]:
    lines = [
        "| ours | N | band | ours: mean total | best seed pattern | its mean | ours − best "
        "(t 95 %) | bootstrap 95 % | verdict |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for pattern in ours:
        for n in NS:
            for band in BANDS:
                mine = totals.get((pattern, n, band))
                if mine is None:
                    continue
                seeds = [p for p in SEED_PATTERNS if (p, n, band) in totals]
                best = min(seeds, key=lambda p: totals[(p, n, band)].mean())
                ref = totals[(best, n, band)]
                d = mine - ref
                lo, hi = t_interval(d)
                blo, bhi = bootstrap_interval(d)
                pct = 100 * d.mean() / ref.mean()
                verdict = "better" if hi < 0 else "worse" if lo > 0 else "n.s."
                lines.append(
                    f"| {pattern} | {n} | {BAND_LABEL[band]} | {mine.mean():.0f} | {best} | "
                    f"{ref.mean():.0f} | {d.mean():+.0f} [{lo:+.0f}, {hi:+.0f}] ({pct:+.1f} %) | "
                    f"[{blo:+.0f}, {bhi:+.0f}] | {verdict} |"
                )
    return lines


def phases(rows: list[tuple[Task, float, dict[str, Any]]], ours: list[str]) -> list[str]:
    """Mean exploration and communication (+ overlap) per (pattern, N, band): why."""
    acc: dict[tuple[str, int, str], list[dict[str, Any]]] = {}
    for (pattern, n, band, _, _, _), _, m in rows:
        acc.setdefault((pattern, n, band), []).append(m)
    lines = ["| pattern | N | " + " | ".join(BAND_LABEL[b] for b in BANDS) + " |",
             "|---|---|" + "---|" * len(BANDS)]
    for pattern in (*SEED_PATTERNS, *ours):
        for n in NS:
            cells = []
            for band in BANDS:
                ms = acc.get((pattern, n, band))
                if not ms:
                    cells.append("–")
                    continue
                e = np.mean([m["exploration_time"] for m in ms])
                c = np.mean([m["communication_time"] + m["comm_transport_overlap"] for m in ms])
                cells.append(f"{e:.0f} / {c:.0f}")
            if any(c != "–" for c in cells):
                lines.append(f"| {pattern} | {n} | " + " | ".join(cells) + " |")
    return lines


Floors = dict[tuple[str, int, int], tuple[int, int, str]]  # (band, i, n) -> Q_min, proven, how


def floors(foods: dict[str, list[tuple[int, int]]], per_band: int, search: int) -> Floors:
    """Q_min (:func:`~swarmex.missions.foraging.floor.least_transport`: the real Relay-Food
    run from the best start state found) and the proven floor, per food cell and N."""
    from swarmex.missions.foraging.floor import least_transport, proven_floor
    from swarmex.missions.foraging.grid import manhattan, nest_of

    out: Floors = {}
    for band in BANDS:
        for i, food in enumerate(foods[band][:per_band]):
            d = manhattan(nest_of(G), food)
            for n in NS:
                q, start = least_transport(G, food, n, UNITS, budget=search)
                out[(band, i, n)] = (q, proven_floor(d, n, UNITS), start.describe(n))
    return out


def read_floors(path: str) -> Floors:
    """The floors a ``--floors`` run wrote (per band, cell index and N)."""
    with open(path, encoding="utf-8") as fh:
        return {(b, i, n): (q, p, how) for b, i, n, q, p, how in json.load(fh)}


def _se(x: np.ndarray) -> float:
    """Standard error of the mean of ``x`` (the 40-cell sample of a band)."""
    return float(x.std(ddof=1) / np.sqrt(len(x)))


def first_visits(pattern: str, n: int) -> np.ndarray:
    """Every cell's discovery round under ``pattern`` (its timetable's first visit; -1 for the
    nest and cells never visited)."""
    from swarmex.missions.foraging import timed_plan

    return timed_plan(pattern, G, n).first_visits()


def exact_band_e(
    rows: list[tuple[Task, float, dict[str, Any]]],
) -> dict[tuple[str, int, str], float]:
    """The seed patterns' exact mean discovery time over every cell of each band (not just
    the 40 drawn), for budgets without E's sampling error; checks the timetable against the
    runs' exploration times on the drawn cells."""
    from swarmex.missions.foraging.food import band_cells

    out = {}
    for pattern in SEED_PATTERNS:
        for n in NS:
            if not supports(pattern, n):
                continue
            first = first_visits(pattern, n)
            for (p, nn, _, _, food, _), _, m in rows:
                if p == pattern and nn == n and first[food] != m["exploration_time"]:
                    raise AssertionError(f"{pattern} N = {n} {food}: timetable disagrees")
            for band in BANDS:
                cells = band_cells(G, band)
                out[(pattern, n, band)] = float(first[cells[:, 0], cells[:, 1]].mean())
    return out


def budget(
    rows: list[tuple[Task, float, dict[str, Any]]],
    fl: Floors,
    exact: dict[tuple[str, int, str], float] | None = None,
) -> list[str]:
    """Is "no worse than the best seed pattern in every band" reachable at all?

    A run's total is its exploration time E plus what follows the discovery, Q. Given a floor
    Q_b for Q in band b, a pattern matching the best seed pattern there must find its food
    within the budget ``best_b − Q_b`` on average. The bands partition the grid, so the
    band-size-weighted budget must be at least the mean discovery time of *any* pattern, which
    is at least ``(g² − 1) / (2n)``: ``n`` robots find at most ``n`` new cells per round. Three
    floors: the lowest band mean any measured pattern reached (empirical), the mean of Q_min
    (the least Relay-Food time from the best start state found, zero communication and
    gathering) and the mean of the proven floor (:func:`~.floor.proven_floor`), each on the
    same 40 cells. ± is one standard error of the budget as an estimate of its value over the
    whole band (from the per-cell spread of best total − floor). With ``exact`` (the seed
    patterns' exact band-mean E, :func:`exact_band_e`) each seed run's total is taken as that
    exact mean plus its own Q, so only Q's spread is left in the error.
    """
    from swarmex.missions.foraging.food import band_cells

    acc: dict[tuple[str, int, str], dict[int, dict[str, Any]]] = {}
    for (pattern, n, band, i, _, _), _, m in rows:
        acc.setdefault((pattern, n, band), {})[i] = m

    def per_cell(pattern: str, n: int, band: str, key: str) -> np.ndarray:
        ms = acc[(pattern, n, band)]
        if key == "q":
            return np.asarray([ms[i]["total_time"] - ms[i]["exploration_time"] for i in sorted(ms)])
        if key == "total_time" and exact is not None:
            return exact[(pattern, n, band)] + per_cell(pattern, n, band, "q")
        return np.asarray([ms[i][key] for i in sorted(ms)], dtype=float)

    lines = [
        "| N | band | cells | best seed total | Q floor: empirical / Q_min / proven | "
        "E budget: empirical | with Q_min | with proven floor |",
        "|---|---|---|---|---|---|---|---|",
    ]
    verdicts = []
    for n in NS:
        sums = {"emp": [0.0, 0.0], "qmin": [0.0, 0.0], "proven": [0.0, 0.0]}  # budget, var
        cells = 0
        for band in BANDS:
            seeds = [p for p in SEED_PATTERNS if (p, n, band) in acc]
            everyone = [p for p in {k[0] for k in acc} if (p, n, band) in acc]
            if not seeds:
                continue
            best_p = min(seeds, key=lambda p: per_cell(p, n, band, "total_time").mean())
            best = per_cell(best_p, n, band, "total_time")
            emp_p = min(everyone, key=lambda p: per_cell(p, n, band, "q").mean())
            floor = {
                "emp": per_cell(emp_p, n, band, "q"),
                "qmin": np.asarray([fl[(band, i, n)][0] for i in sorted(acc[(best_p, n, band)])]),
                "proven": np.asarray(
                    [fl[(band, i, n)][1] for i in sorted(acc[(best_p, n, band)])]
                ),
            }
            size = len(band_cells(G, band)) if band != "random" else G * G - 1
            for frac, label in ((1.0, BAND_LABEL[band]), (0.9, "RANDOM, 10 % below the best")):
                if frac < 1 and band != "random":
                    continue
                b = {k: (frac * best - f).mean() for k, f in floor.items()}
                se = {k: _se(frac * best - f) for k, f in floor.items()}
                qs = " / ".join(f"{floor[k].mean():.0f}" for k in ("emp", "qmin", "proven"))
                tail = " | ".join(f"{b[k]:.0f} ± {se[k]:.0f}" for k in ("emp", "qmin", "proven"))
                need = f" (vs at least {size / (2 * n):.0f})" if frac < 1 else ""
                lines.append(f"| {n} | {label} | {size} | {frac * best.mean():.0f} | {qs} | "
                             f"{tail}{need} |")
                if frac < 1:
                    verdicts.append((n, "RANDOM −10 %", b, se, size / (2 * n)))
            if band != "random":
                for k, f in floor.items():
                    sums[k][0] += size * (best - f).mean()
                    sums[k][1] += (size * _se(best - f)) ** 2
                cells += size
        b = {k: v[0] / cells for k, v in sums.items()}
        se = {k: float(np.sqrt(v[1])) / cells for k, v in sums.items()}
        tail = " | ".join(f"**{b[k]:.0f}** ± {se[k]:.0f}" for k in ("emp", "qmin", "proven"))
        lines.append(f"| {n} | weighted over the five bands | {cells} | | | {tail} "
                     f"(vs at least {cells / (2 * n):.0f}) |")
        verdicts.append((n, "bands", b, se, cells / (2 * n)))
    lines.append("")
    lines.append("Shortfall = the least mean discovery time minus the budget, in standard errors "
                 "of the budget (> 2: beyond sampling error; < 0: the budget is not exceeded):")
    for n, what, b, se, need in verdicts:
        parts = [f"{k} {need - b[k]:+.0f} ({(need - b[k]) / se[k]:+.1f} SE)"
                 for k in ("emp", "qmin", "proven")]
        lines.append(f"* N = {n}, {what}: " + ", ".join(parts))
    return lines


def floor_checks(rows: list[tuple[Task, float, dict[str, Any]]], fl: Floors) -> list[str]:
    """Q_min and the proven floor against every measured run (a run below the proven floor
    would refute its argument) and against the steady-state closed form 2k(d − n)/n."""
    from swarmex.missions.foraging.grid import manhattan, nest_of

    below_q: list[str] = []
    below_p = 0
    for (pattern, n, band, i, food, _), _, m in rows:
        q = m["total_time"] - m["exploration_time"]
        if q < fl[(band, i, n)][0]:
            below_q.append(f"{pattern} N = {n} food {food}: Q {q} < Q_min {fl[(band, i, n)][0]} "
                           f"({fl[(band, i, n)][2]})")
        below_p += q < fl[(band, i, n)][1]
    lines = [f"{len(rows)} measured runs: {len(below_q)} with Q below Q_min of their cell, "
             f"{below_p} below the proven floor.", *below_q, "",
             "| N | band | mean d | mean Q_min | mean 2k(d − n)/n | mean proven floor | "
             "lowest measured Q | Q_min: relay only / with joining robots |",
             "|---|---|---|---|---|---|---|---|"]
    foods = {(band, i): f for (_, _, band, i, f, _), _, _ in rows}
    for n in NS:
        for band in BANDS:
            keys = sorted(k for k in fl if k[0] == band and k[2] == n)
            ds = np.asarray([manhattan(nest_of(G), foods[(b, i)]) for b, i, _ in keys])
            qmin = np.asarray([fl[k][0] for k in keys])
            proven = np.asarray([fl[k][1] for k in keys])
            closed = 2 * UNITS * (ds - n) / n
            qs: dict[str, list[float]] = {}
            for (pattern, nn, b, _, _, _), _, m in rows:
                if nn == n and b == band:
                    qs.setdefault(pattern, []).append(m["total_time"] - m["exploration_time"])
            joining = sum(" 0 joining" not in fl[k][2] for k in keys)
            lines.append(
                f"| {n} | {BAND_LABEL[band]} | {ds.mean():.0f} | {qmin.mean():.0f} | "
                f"{closed.mean():.0f} | {proven.mean():.0f} | "
                f"{min(np.mean(v) for v in qs.values()):.0f} | {len(keys) - joining} / {joining} |"
            )
    return lines


def noise_free(rows: list[tuple[Task, float, dict[str, Any]]], ours: list[str]) -> list[str]:
    """Uniform food without the sampling error of E: the exact mean discovery time over every
    non-nest cell (from the pattern's timetable) plus the measured mean Q on the RANDOM cells.
    E's 40-cell mean has a standard error of ≈ (g²/n)/√(12·40) rounds (≈ 47 at n = 16), larger
    than most differences between patterns."""
    from swarmex.missions.foraging import timed_plan

    lines = ["| pattern | N | exact mean E | mean Q (RANDOM cells) | estimate | 40-cell mean |",
             "|---|---|---|---|---|---|"]
    for pattern in (*SEED_PATTERNS, *(p for p in ours if p != RECALL)):  # recall: no timetable
        for n in NS:
            ms = [m for (p, nn, band, _, _, _), _, m in rows
                  if p == pattern and nn == n and band == "random"]
            if not ms:
                continue
            pos = timed_plan(pattern, G, n).pos
            first = np.full((G, G), -1, dtype=np.int64)
            for t in range(len(pos) - 1, -1, -1):
                first[pos[t, :, 0], pos[t, :, 1]] = t
            first[G // 2, G // 2] = -1
            e = float(first[first >= 0].mean())
            q = float(np.mean([m["total_time"] - m["exploration_time"] for m in ms]))
            tot = float(np.mean([m["total_time"] for m in ms]))
            lines.append(f"| {pattern} | {n} | {e:.0f} | {q:.0f} | {e + q:.0f} | {tot:.0f} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-band", type=_cli.paired_count, default=40)
    ap.add_argument("--workers", type=_cli.positive_int, default=2)
    ap.add_argument("--ours", default="comb,sector-loop,loop-strips,recall")
    ap.add_argument("--seed", type=_cli.nonneg_int, default=2015)
    ap.add_argument("--raw", type=_cli.out_file, help="write every run's metrics to this JSON file")
    ap.add_argument("--load", help="read the runs' metrics from this --raw file instead")
    ap.add_argument("--floors", type=_cli.out_file,
                    help="Q_min and proven floors: read this JSON file if it exists, else "
                    "compute them and write it")
    ap.add_argument("--floor-search", type=_cli.positive_int, default=40,
                    help="local-search runs per food cell and N for Q_min (after the formations)")
    a = ap.parse_args(argv)
    ours = [p for p in a.ours.split(",") if p]
    unknown = [p for p in ours if p not in FORAGING_ALGORITHMS]
    if unknown:  # before the pool: the 1,920 seed runs come first
        ap.error(f"--ours: unknown {', '.join(unknown)}; choose from "
                 f"{', '.join(FORAGING_ALGORITHMS)}")
    foods = food_cells(a.seed, 40)  # the reproduction's cells; --per-band takes the first ones
    tasks: list[Task] = [
        (p, n, band, i, f, memory(p, foods[band], i))
        for p in (*SEED_PATTERNS, *ours)
        for n in NS
        if supports(p, n)
        for band in BANDS
        for i, f in enumerate(foods[band][: a.per_band])
    ]
    t0 = time.time()
    if a.load:  # the metrics of an earlier --raw, for the same cells
        with open(a.load, encoding="utf-8") as fh:
            saved = {tuple(key): m for key, m in json.load(fh)}
        rows = [(t, 0.0, saved[t[:4]]) for t in tasks]
    else:
        with _cli.process_pool(a.workers) as ex:
            rows = list(ex.map(run_one, tasks, chunksize=8))
    cpu = sum(r[1] for r in rows)
    totals: dict[tuple[str, int, str], list[float]] = {}
    for (p, n, band, _, _, _), _, m in rows:
        totals.setdefault((p, n, band), []).append(float(m["total_time"]))
    arr = {k: np.asarray(v) for k, v in totals.items()}
    print(f"{len(rows)} runs, {a.per_band} cells per band, CPU {cpu:.0f} s in the runs, "
          f"wall {time.time() - t0:.0f} s (shared machine: use CPU time)")
    print()
    print("\n".join(table(arr, ours)))
    print()
    print("Mean exploration / communication + overlap (rounds), same cells:")
    print("\n".join(phases(rows, ours)))
    print()
    if RECALL in ours:
        print("Recall's choices (the memory: the band's earlier trips):")
        print("\n".join(choices(rows)))
        print()
    print("Uniform food, noise-free estimate (exact mean E + measured mean Q):")
    print("\n".join(noise_free(rows, ours)))
    print()
    t1 = time.process_time()
    if a.floors and os.path.exists(a.floors):
        fl = read_floors(a.floors)
    else:
        fl = floors(foods, a.per_band, a.floor_search)
        if a.floors:  # 170 s of CPU: an interrupted write must not leave half a file
            write_json_atomic([[*k, *v] for k, v in fl.items()], a.floors)
    print(f"Transport floors per food cell and N: CPU {time.process_time() - t1:.0f} s")
    print("\n".join(floor_checks(rows, fl)))
    print()
    print("Exploration budgets (docs/foraging.md, 'Can any pattern meet the target?'):")
    print("\n".join(budget(rows, fl)))
    print()
    print("The same with the seed patterns' exact band-mean E (no sampling error in E):")
    print("\n".join(budget(rows, fl, exact_band_e(rows))))
    if a.raw:
        write_json_atomic([[list(t[:4]), m] for t, _, m in rows], a.raw)
    return 0


if __name__ == "__main__":
    _cli.run(main)
