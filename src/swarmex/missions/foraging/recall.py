"""Recall: the team chooses its search from where food has been found (issue 17, item 3).

Why. No fixed pattern is best everywhere: Sectors and Spiral find food near the nest within a
few dozen rounds, Strips and Loop Strips are best once food lies far out, and every attempt at
one pattern that does both lost somewhere (docs/foraging.md). But a foraging team rarely
searches a field for the first time: food sources recur where they were before (site
fidelity, as in ant colonies). Issue 17 lets the robots choose from what they know, *where
food has been found* included. Recall uses that memory.

* **The memory** (``found``): the cells of the food on earlier trips, oldest first. Every
  robot learnt each one when it was told the food's cell (ch. 4), so it is common knowledge of
  the team. Recall keeps their **distances** from the nest, the :data:`MEMORY` most recent
  (Θ(MEMORY · log g) bits per robot): the seed's experiments place food by distance (ch. 6),
  and the direction of one find says little about the next.
* **The candidates**: every pattern of :data:`~.patterns.BUILDERS` that supports ``(g, n)``
  (the thesis's and ours), plus the **annulus**: Sectors (§3.4: its division, emission and
  deployment) whose robots first sweep the cells of their sector at a distance ``lo … hi``
  from the nest, then the rest of it, the side with fewer cells first (inward from ``lo − 1``
  or outward from ``hi + 1``; :func:`annulus_plan`). ``lo … hi`` is the range of the
  remembered distances widened at each end by (max − min)/(m − 1), the unbiased estimate of
  a uniform interval's ends from m draws (:func:`annulus_range`). The annulus is a candidate
  with two or more remembered distances, a team and grid Sectors' division accepts (n = 4 or
  a multiple of 8, a sector for every robot), and at most :data:`MAX_SHARE` of the cells
  inside it. A candidate that another beats by 10 % in every distance band of the prior
  (below) is dropped before the memory is replayed (ZigZag and Hilbert at N = 16): the
  memory is of distances, so it cannot favour them.
* **The choice**: every robot replays, in its head, each candidate's whole run (the mission's
  own rules: k, transport and communication rule), and the team takes the candidate with the
  least score; ties go to the earlier candidate. The replay is deterministic, so every robot
  makes the same choice in the nest before leaving, without a message.

  * With m remembered distances the score is the predicted mean total time: the mean over
    :data:`PER_DISTANCE` cells spread round each remembered distance's ring
    (:func:`ring_cells`), weighted m, and the mean under uniform food, weighted as one trip.
    The uniform mean comes from :data:`PER_BAND` fixed cells in each distance band
    0–20 … 80–100 % (the prior, :func:`prior_of`), weighted by the bands' cells. With two or
    more distances the team leaves the pattern best for uniform food only for a candidate
    whose gain over it, paired over the remembered distances, exceeds :data:`SIGNIFICANT`
    standard errors.
  * With no memory the team does not know whether food will lie near or far, so it takes the
    candidate whose worst ratio to the best candidate of a band is least (minimax regret).
    The pattern best for uniform food (Loop Strips) takes 3.4 times Sectors' time when food
    lies near the nest, and a memory is for exactly such fields.

Choices made here (each recorded in docs/foraging.md, "Recall"), all from the first
measurements (the band table there):

* *Distances, not cells.* Replayed on the remembered cells themselves, the choice followed
  the pattern that happened to pass one remembered cell early (Loop Strips on the second trip
  of the 20–40 % band, 1,240 rounds lost).
* *A widened range, and the smaller side first.* With [min, max] alone and the far side first,
  food just inside the range's lower end waited for the whole outer grid (+1,400 to +2,100
  rounds on single trips of the two near bands).
* *Minimax regret with no memory.* The uniform-best first trip (Loop Strips) cost the 0–20 %
  band +21 % at N = 16.
* *At most half the cells, and a significant gain.* Without them replay noise on uniform food
  chose another pattern than Loop Strips (the annulus, then Sectors with a hole, or Sectors)
  on 13–21 of 40 trips: RANDOM +3.5 % to +6.8 % against Strips.
* *The prior's weight is one trip*: with one remembered distance the replay does not stake
  the whole next trip on it; with sixteen it barely counts.

Cost: a choice replays ``candidates × (PER_DISTANCE · memory + 5 PER_BAND)`` runs, ≈ 1–3 ms
each on a 128 × 128 grid since the communication phase is compiled (10–20 ms before): 1.7 s
for a full memory in a fresh process at N = 16 (12.4 s with that phase in Python; 26 s before
dominated candidates were dropped), less per trip in a series, since replays are cached per
(candidate, cell).
On the largest grids the replays are long (1024 × 1024 with 1,024 robots, no memory: 120
replays, 45 s, 10.5 min before the communication phase was compiled; the timetables take
3 s); ``on_replay`` feeds the command line's progress bar.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.foraging import sectors
from swarmex.missions.foraging.food import BANDS, band_cells, check_food, nest_distances
from swarmex.missions.foraging.grid import Cell, manhattan, nest_of
from swarmex.missions.foraging.patterns import BUILDERS, build_plan
from swarmex.missions.foraging.plan import Plan
from swarmex.missions.foraging.sim import run_mission
from swarmex.missions.foraging.timed import Timed, execute, timed_plan

NAME = "recall"
ANNULUS = "annulus"
MEMORY = 16  # remembered distances the choice replays (the most recent)
PER_DISTANCE = 8  # cells standing for one remembered distance, spread round its ring
MAX_SHARE = 0.5  # the widest annulus that is a candidate, as a share of the cells
SIGNIFICANT = 2.0  # standard errors a remembered gain needs to leave the pattern for anywhere
DOMINATED = 0.9  # beaten in every distance band by this ratio: not a candidate
PER_BAND = 4  # cells per distance band standing for "food may be anywhere"
PRIOR_SEED = 2026  # fixed, so every robot draws the same cells
DISTANCE_BANDS = tuple(b for b in BANDS if b != "random")

Candidate = str | tuple[str, int, int]  # a pattern name, or (ANNULUS, lo, hi)


@dataclass(frozen=True)
class Choice:
    """What the team chose: the candidate, its timetable and every candidate's score (the
    least wins): with a memory, its predicted mean total time in rounds; without, its worst
    ratio to the best candidate over the distance bands."""

    candidate: Candidate
    timed: Timed
    predicted: dict[str, float]

    @property
    def pattern(self) -> str:
        """The chosen pattern as the record shows it: a name, or ``annulus LO-HI``."""
        return label(self.candidate)


def label(candidate: Candidate) -> str:
    if isinstance(candidate, str):
        return candidate
    return f"{ANNULUS} {candidate[1]}-{candidate[2]}"


def annulus_plan(g: int, n: int, lo: int, hi: int) -> Plan:
    """Sectors whose robots sweep the cells at distance ``lo … hi`` first (see the module)."""

    def annulus_first(cells: list[tuple[int, int]], lower: bool) -> list[tuple[int, int]]:
        order = sectors.sweep(cells, lower)  # frame (u, v): the distance is u + v
        band = [c for c in order if lo <= c[0] + c[1] <= hi]
        beyond = [c for c in order if c[0] + c[1] > hi]  # outward from hi + 1
        inside = [c for c in order if c[0] + c[1] < lo][::-1]  # inward from lo - 1
        # the smaller side first: food missed by the annulus then waits the least
        rest = inside + beyond if len(inside) <= len(beyond) else beyond + inside
        return band + rest

    plan = sectors.plan(g, n, name=ANNULUS, order_fn=annulus_first)
    plan.notes["annulus"] = (lo, hi)
    return plan


@lru_cache(maxsize=16)
def annulus_timed(g: int, n: int, lo: int, hi: int) -> Timed:
    return execute(annulus_plan(g, n, lo, hi))


def timed_of(candidate: Candidate, g: int, n: int) -> Timed:
    if isinstance(candidate, str):
        return timed_plan(candidate, g, n)
    return annulus_timed(g, n, candidate[1], candidate[2])


@lru_cache(maxsize=64)
def patterns_for(g: int, n: int) -> tuple[str, ...]:
    """The patterns that support ``(g, n)``, in :data:`BUILDERS` order."""
    out = []
    for name in BUILDERS:
        try:
            build_plan(name, g, n)
        except InputError:
            continue
        out.append(name)
    return tuple(out)


def check(g: int, n: int, found: Sequence[Cell]) -> None:
    """Recall's input rule: some pattern supports ``(g, n)``; every remembered cell is a
    non-nest cell of the grid."""
    if not patterns_for(g, n):
        raise InputError(f"{NAME}: no pattern supports --grid {g} with --agents {n}")
    for c in found:
        check_food(c, g, "--found")


@dataclass(frozen=True)
class Prior:
    """What the team assumes before any memory: food may lie in any of the five distance
    bands (:data:`~.food.BANDS`, the thesis's ch. 6 split), represented by
    :data:`PER_BAND` cells drawn uniformly in each from a fixed seed, and each band's share of
    the grid's cells (its weight under uniform food)."""

    cells: tuple[tuple[Cell, ...], ...]  # per band
    share: tuple[float, ...]  # per band, summing to 1


@lru_cache(maxsize=4)
def prior_of(g: int) -> Prior:
    rng = np.random.default_rng(PRIOR_SEED)
    per_band, shares = [], []
    for band in DISTANCE_BANDS:
        try:
            cells = band_cells(g, band)
        except InputError:  # a tiny grid has no cell in some band
            continue
        idx = rng.choice(len(cells), size=min(PER_BAND, len(cells)), replace=False)
        per_band.append(tuple((int(cells[i][0]), int(cells[i][1])) for i in idx))
        shares.append(float(len(cells)))
    total = sum(shares)
    return Prior(tuple(per_band), tuple(s / total for s in shares))


@lru_cache(maxsize=1 << 16)
def replay(
    candidate: Candidate, g: int, n: int, food: Cell, units: int, transport: str, comm: str
) -> int:
    """The total time of ``candidate``'s run with the food on ``food`` (what a robot
    computes in its head: the mission's own run, no record)."""
    timed = timed_of(candidate, g, n)
    return run_mission(timed, food, units, transport, record=False, comm=comm).makespan


def annulus_range(g: int, distances: Sequence[int]) -> tuple[int, int] | None:
    """Where food lies, estimated from m ≥ 2 remembered distances: their range widened by
    (max − min)/(m − 1) at each end (the unbiased estimate of a uniform interval's ends),
    rounded outward and kept to 1 … g; None for fewer than two."""
    m = len(distances)
    if m < 2:
        return None
    a, b = min(distances), max(distances)
    r = (b - a) / (m - 1)
    return max(1, math.floor(a - r)), min(g, math.ceil(b + r))


def candidates(g: int, n: int, distances: Sequence[int]) -> list[Candidate]:
    """Every pattern that supports ``(g, n)``, then the annulus of the remembered distances
    if it holds at most :data:`MAX_SHARE` of the cells (a wider one says little more than
    "anywhere", and its replayed edge over the patterns is then within the replay's noise)."""
    out: list[Candidate] = list(patterns_for(g, n))
    span = annulus_range(g, distances)
    if span is not None and share_within(g, *span) <= MAX_SHARE:
        try:
            annulus_timed(g, n, *span)  # Sectors' division: its team-size and grid rules
        except InputError:
            return out
        out.append((ANNULUS, *span))
    return out


@lru_cache(maxsize=4)
def _cells_by_distance(g: int) -> np.ndarray:
    return np.bincount(nest_distances(g).ravel(), minlength=2 * g + 1)


def share_within(g: int, lo: int, hi: int) -> float:
    """The share of the non-nest cells at a distance ``lo … hi`` from the nest."""
    counts = _cells_by_distance(g)
    return float(counts[max(lo, 1) : hi + 1].sum() / (g * g - 1))


@lru_cache(maxsize=1024)
def ring_cells(g: int, d: int) -> tuple[Cell, ...]:
    """:data:`PER_DISTANCE` cells at distance ``d`` from the nest, evenly spaced round the
    ring's cells inside the grid (counter-clockwise from East), or all of them if fewer."""
    nx, ny = nest_of(g)
    ring = []
    for s in range(d):  # the four sides of the diamond, East → North → West → South → East
        for x, y in ((d - s, -s), (-s, -(d - s)), (-(d - s), s), (s, d - s)):
            ring.append((nx + x, ny + y))
    ring.sort(key=lambda c: _angle(c[0] - nx, ny - c[1]))
    inside = [c for c in ring if 0 <= c[0] < g and 0 <= c[1] < g]
    if len(inside) <= PER_DISTANCE:
        return tuple(inside)
    step = len(inside) / PER_DISTANCE
    return tuple(inside[int((j + 0.5) * step)] for j in range(PER_DISTANCE))


def _angle(x: int, y: int) -> float:
    return math.atan2(y, x) % (2 * math.pi)


def choose(
    g: int,
    n: int,
    found: Sequence[Cell],
    units: int,
    transport: str,
    comm: str,
    on_replay: Callable[[int, int], None] | None = None,
) -> Choice:
    """The team's choice for the next trip (see the module docstring). ``on_replay(done,
    total)`` is called after every replay (for a progress bar: on a large grid a choice takes
    minutes); ``total`` shrinks once dominated candidates are dropped."""
    check(g, n, found)
    nest = nest_of(g)
    distances = [manhattan((int(x), int(y)), nest) for x, y in found][-MEMORY:]
    prior = prior_of(g)
    cands = candidates(g, n, distances)
    prior_n = sum(len(cells) for cells in prior.cells)
    memory_n = sum(len(ring_cells(g, d)) for d in distances)
    done, planned = 0, len(cands) * (prior_n + memory_n)

    def total(cand: Candidate, cells: Sequence[Cell]) -> float:
        nonlocal done
        out = []
        for c in cells:
            out.append(replay(cand, g, n, c, units, transport, comm))
            done += 1
            if on_replay is not None:
                on_replay(done, planned)
        return float(np.mean(out))

    # mean total per distance band, per candidate
    bands = np.array([[total(c, cells) for cells in prior.cells] for c in cands])
    # a candidate another one beats by DOMINATED in every band is not replayed further
    keep = [not any((b <= DOMINATED * a).all() for b in bands) for a in bands]
    cands = [c for c, k in zip(cands, keep, strict=True) if k]
    bands = bands[np.array(keep)]
    planned = done + len(cands) * memory_n
    if distances:
        uniform = bands @ np.array(prior.share)  # the mean under uniform food
        rings = np.array([[total(c, ring_cells(g, d)) for d in distances] for c in cands])
        m = len(distances)
        score = (m * rings.mean(axis=1) + uniform) / (m + 1)
        best = int(np.argmin(score))  # the first of equal scores
        # the pattern best for food anywhere, unless the memory shows a significant gain
        anywhere = int(np.argmin(np.where([isinstance(c, str) for c in cands], uniform, np.inf)))
        if m >= 2 and best != anywhere:
            gain = rings[best] - rings[anywhere]  # per remembered distance
            if gain.mean() + SIGNIFICANT * gain.std(ddof=1) / math.sqrt(m) >= 0:
                best = anywhere
    else:  # minimax regret: the least worst ratio to the best candidate of a band
        score = (bands / bands.min(axis=0)).max(axis=1)
        best = int(np.argmin(score))
    predicted = {label(c): float(v) for c, v in zip(cands, score, strict=True)}
    return Choice(cands[best], timed_of(cands[best], g, n), predicted)


__all__ = ["MEMORY", "NAME", "PER_BAND", "Choice", "annulus_plan", "check", "choose"]
