"""A team on one ray from the nest: the rotating spoke (issue 17.3, a family tried and measured).

docs/foraging.md ("Can any pattern meet the target?") finds the best start states of
Relay-Food, far from the nest, to be robots packed down the path from the nest to the food.
The level comb keeps its team together but across the grid, not along that path. A *spoke*
keeps the team on one ray from the nest as it sweeps round, like a radar beam: robot ``i``
owns a band of Chebyshev rings round the nest, the bands hold the same number of cells, and
each robot sweeps its band in radial zig-zag lines (rows on the East and West sides, columns
on the North and South) in one angular order. Equal cells per band give equal work per unit
of angle, so the robots turn together and, at any discovery, stand roughly on the ray through
the food, in order of distance from the nest.

* Band edges are fractional ring radii with equal cell counts. A line's cut between two bands
  is the edge rounded with a golden-ratio dither per line, so that each band's share is right
  on average. With whole rings, the outer bands, two or three rings wide, differed in size by
  up to 50 % and the team spread over 90°.
* Robots walk out along the shortest path to their first cell, the farthest first, one per
  round; consecutive cells of a sweep are joined by the shortest L-shaped walk.
* Neighbours for the communication are the adjacent bands. Two rules are measured: the seed
  rule (a detour to meet the neighbours) and Strips' route-kept rule.

On the N = 16 RANDOM cells (128 × 128, k = 100, Relay-Food) the script prints, for the
spoke, the level comb, Strips, Loop Strips and Sectors, the same columns as
bench/foraging_level_comb.py, plus the team's angular spread (the median over the rounds
after deployment of the largest angle between a robot and the team's mean direction), and
the bound that decides a family: with its own Q, a pattern meets −10 % against Strips only
if its exact E is at most 0.9 · (Strips' E + Q) − Q, and every pattern's exact E is at least
(g² − 1)/(2n). A second table gives the same bound with an oracle word
(:func:`instant_word_q`): where a faster word leads in the limit (not a bound: a staggered
word can do better, as the level comb's does).

    PYTHONPATH=src python bench/foraging_spoke.py [--per-band 40] [--seed 2015]
        [--floors floors.json] [--floor-search 40]

About 7 s of CPU, more when it computes Q_min rather than reading it.
"""

from __future__ import annotations

import math
import time

import numpy as np

import _cli
from foraging_level_comb import BAND, N, cells_parser, exact_e, level_plan, q_min
from swarmex.missions.foraging import timed_plan
from swarmex.missions.foraging.grid import Cell, nest_of
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.run import phase_metrics
from swarmex.missions.foraging.sim import JOIN, RELAY, TRANSPORT, Mission, run_mission
from swarmex.missions.foraging.timed import Timed, execute
from swarmex.missions.foraging.transport import RELAY_FOOD, relay_path
from swarmex.studies.foraging.design import UNITS, G, food_cells

GOLDEN = (math.sqrt(5) - 1) / 2
Line = tuple[str, int]  # a side of the square rings and the row or column on it


def line_of(dx: int, dy: int) -> tuple[Line, int]:
    """The zig-zag line of the cell at offset (dx, dy) from the nest, and its ring. Each ring
    splits into four sides of 2r cells (East takes its North-East corner, and so on round)."""
    r = max(abs(dx), abs(dy))
    if dx == r and dy > -r:
        return ("E", dy), r
    if dy == r and dx < r:
        return ("N", dx), r
    if dx == -r and dy < r:
        return ("W", dy), r
    return ("S", dx), r


def line_angle(line: Line, half: int) -> float:
    """Where a line lies round the nest, 0 (East, the nest's row) to 8, counter-clockwise: the
    square's analogue of an angle, measured at ring ``half``."""
    side, c = line
    s = {"E": c / half, "N": 2 - c / half, "W": 4 - c / half, "S": 6 + c / half}[side]
    return s if s >= 0 else s + 8


def walk(p: Cell, q: Cell) -> list[Cell]:
    """The cells after ``p`` of an L-shaped shortest walk to ``q`` (x first)."""
    (x, y), out = p, []
    while x != q[0]:
        x += 1 if q[0] > x else -1
        out.append((x, y))
    while y != q[1]:
        y += 1 if q[1] > y else -1
        out.append((x, y))
    return out


def band_edges(g: int, n: int) -> list[float]:
    """Fractional ring radii ρ_0 = 1 < … < ρ_n: rings [ρ_i, ρ_i+1) hold g²−1 / n cells each,
    counting a fraction of the ring ρ falls in."""
    nest = nest_of(g)
    xs, ys = np.meshgrid(np.arange(g), np.arange(g), indexing="ij")
    rings = np.maximum(abs(xs - nest[0]), abs(ys - nest[1]))
    counts = np.bincount(rings.ravel()).astype(float)
    counts[0] = 0.0  # the nest holds no food
    below = np.concatenate([[0.0], np.cumsum(counts)])  # below[R]: cells of rings < R
    edges = [1.0]
    for i in range(1, n):
        target = i * counts.sum() / n
        ring = int(np.searchsorted(below, target)) - 1
        edges.append(ring + (target - below[ring]) / counts[ring])
    edges.append(float(rings.max()) + 1.0)
    return edges


def sweeps(g: int, n: int) -> list[list[Cell]]:
    """Each robot's band, cell by cell: its lines in angular order, alternately outward and
    inward."""
    nest = nest_of(g)
    lines: dict[Line, list[tuple[int, Cell]]] = {}
    for x in range(g):
        for y in range(g):
            if (x, y) != nest:
                line, ring = line_of(x - nest[0], y - nest[1])
                lines.setdefault(line, []).append((ring, (x, y)))
    edges = band_edges(g, n)
    out: list[list[Cell]] = [[] for _ in range(n)]
    outward = [True] * n
    for j, line in enumerate(sorted(lines, key=lambda ln: line_angle(ln, g // 2))):
        cuts = [math.floor(e + (j * GOLDEN) % 1.0) for e in edges]
        cuts[-1] = g  # the last band takes the line to the border
        cells = sorted(lines[line])
        for i in range(n):
            seg = [c for ring, c in cells if cuts[i] <= ring < cuts[i + 1]]
            if seg:
                out[i].extend(seg if outward[i] else seg[::-1])
                outward[i] = not outward[i]
    return out


def spoke_plan(g: int, n: int, keep_route: bool) -> Plan:
    nest = nest_of(g)
    routes, explore_from = [], []
    for band in sweeps(g, n):
        route = [nest, *walk(nest, band[0])]
        explore_from.append(len(route) - 1)
        for c in band[1:]:
            route.extend(walk(route[-1], c))
        routes.append(route)
    # the farthest first, one per round: nobody waits behind a robot still walking out
    depart = [0] * n
    for k, a in enumerate(sorted(range(n), key=lambda a: -explore_from[a])):
        depart[a] = k + 1
    name = f"spoke, {'route kept' if keep_route else 'seed detour'}"
    plan = Plan(name, g, n, routes, depart=depart, explore_from=explore_from,
                neighbours=[[b for b in (a - 1, a + 1) if 0 <= b < n] for a in range(n)],
                follow_path_comm=keep_route)  # fmt: skip
    plan.validate()
    return plan


def spread(timed: Timed) -> float:
    """Median, over the rounds after every robot has begun its sweep, of the largest angle
    (degrees) between a robot and the team's mean direction from the nest."""
    nest = np.asarray(timed.plan.nest)
    pos = timed.pos[int(timed.explore_start.max()) :] - nest
    angle = np.arctan2(pos[:, :, 1], pos[:, :, 0])
    mean = np.angle(np.exp(1j * angle).mean(axis=1))
    off = np.abs(np.angle(np.exp(1j * (angle - mean[:, None]))))
    return float(np.degrees(np.median(off.max(axis=1))))


def instant_word_q(timed: Timed, food: Cell, units: int = UNITS) -> int:
    """Q of the run in ``timed`` had every robot learnt the food in the discovery round, where
    it stands then (an oracle: no pattern's word is this fast). Relay-Food as the seed plays
    it: the finder holds the food's path cell, every other robot walks to the food and joins
    the relay there: where a faster word leads in the limit, family by family."""
    nest = nest_of(timed.plan.g)
    pos = timed.pos
    hit = (pos[:, :, 0] == food[0]) & (pos[:, :, 1] == food[1])
    found = int(np.flatnonzero(hit.any(axis=1))[0])
    here = [(int(x), int(y)) for x, y in pos[found]]
    d = len(relay_path(nest, food)) - 1
    m = Mission(timed.plan.g, nest, food, units, RELAY_FOOD, here, t=0, timed=None)
    finder = here.index(food)
    for a in range(len(here)):
        m.mode[a], m.informed[a], m.informed_at[a], m.comm_done[a] = TRANSPORT, True, 0, 0
        m.tmode[a] = RELAY if a == finder else JOIN
        if a == finder:
            m.pidx[a] = d
        else:
            m.join_at[a] = d
    m.run(record=False)
    return int(m.t)


def main(argv: list[str] | None = None) -> int:
    a = cells_parser(__doc__.splitlines()[0]).parse_args(argv)
    cells = food_cells(a.seed, 40)[BAND][: a.per_band]
    t0 = time.process_time()
    tables = {p.algorithm: execute(p) for p in (spoke_plan(G, N, False), spoke_plan(G, N, True))}
    level = level_plan(G, N, keep_route=True)
    tables[level.algorithm] = execute(level)
    for pattern in ("strips", "loop-strips", "sectors"):
        tables[pattern] = timed_plan(pattern, G, N)
    qmin = q_min(cells, a.floors if a.seed == 2015 else None, a.floor_search)
    rows = {}
    for name, timed in tables.items():
        runs = [run_mission(timed, c, UNITS, RELAY_FOOD, record=False) for c in cells]
        e = np.array([o.discovery for o in runs], dtype=float)
        q = np.array([o.makespan for o in runs], dtype=float) - e
        phases = [phase_metrics(o, timed) for o in runs]
        co = np.array([m["communication_time"] + m["comm_transport_overlap"] for m in phases])
        instant = np.array([instant_word_q(timed, c) for c in cells], dtype=float)
        rows[name] = (exact_e(timed), co.mean(), q, q - qmin, spread(timed), instant)
    strips_nf = rows["strips"][0] + rows["strips"][2].mean()
    floor = (G * G - 1) / (2 * N)
    print(f"N = {N}, {len(cells)} {BAND} cells (seed {a.seed}), k = {UNITS}, {RELAY_FOOD}; "
          f"CPU {time.process_time() - t0:.0f} s; Q_min mean {qmin.mean():.0f}")  # fmt: skip
    print()
    print("| pattern | spread ° | exact E | C + O | Q | Q − Q_min (median) | exact E + Q "
          "| against Strips | exact E needed for −10 % |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (ee, co, q, excess, deg, _) in rows.items():
        nf = ee + q.mean()
        print(f"| {name} | {deg:.0f} | {ee:.0f} | {co:.0f} | {q.mean():.0f} | "
              f"{excess.mean():.0f} ({np.median(excess):.0f}) | {nf:.0f} | "
              f"{100 * (nf / strips_nf - 1):+.1f} % | {0.9 * strips_nf - q.mean():.0f} |")
    print()
    print("With the word instant (every robot informed in the discovery round, where it stands;"
          " an oracle):")
    print()
    print("| pattern | Q | Q, word instant | exact E | exact E needed for −10 %, word instant |")
    print("|---|---|---|---|---|")
    for name, (ee, _, q, _, _, instant) in rows.items():
        print(f"| {name} | {q.mean():.0f} | {instant.mean():.0f} | {ee:.0f} | "
              f"{0.9 * strips_nf - instant.mean():.0f} |")
    print()
    print(f"Any pattern's exact E is at least (g² − 1)/(2n) = {floor:.0f}.")
    return 0


if __name__ == "__main__":
    _cli.run(main)
