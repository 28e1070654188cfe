"""``madgta-k``: a sweep phase on a re-partitioned known graph, then madgta-p's end game.

Idea
----
MADGTA wastes moves in the sweep when agents crowd one region (a shared nest, the rooms of
room-32-32-4) and race for the same vertices; madgta-p (:mod:`.teamplan`) only acts in the
end game (at most ``max_vacant`` = 200 vacant vertices), and an oracle showed that no
end-game method reaches issue 17's -3 % (docs/traversal-variants.md §5). So before the end
game ``madgta-k`` splits the vacant vertices among the agents, at every decision and from
the agent's own belief only, and keeps each agent to its own part:

1. **The partition** (:func:`_balanced_parts`). Each known agent is placed where it is next
   free (the node a moving rival announced, C05; else its last vertex; the agent itself at
   its vertex), with a head start of its remaining busy time in edges (``free_at`` - now,
   the eta of C05/C07). A vacant vertex (not done, not a known wall, not reserved by a
   rival, reachable by the agent on its known graph, unknown cells free) goes to the agent
   with the least ``hops + head start + weight``: an additively weighted Voronoi partition
   on hop distances. The weights start at 0; 40 rounds raise the weight of parts above the
   mean size and lower the others (step ``0.8 sqrt(n/m) / (1 + round/8)`` times the relative
   excess); the partition kept is the first one of least imbalance. Ties go to the lowest
   agent id. Deterministic: the same belief gives the same parts, and under a perfect
   broadcast the agents' beliefs, hence their partitions, nearly agree.
2. **The decision** (:class:`PartSweep`). Branch 1 as MADGTA (a job on a vacant vertex).
   Branch 2: among the vacant neighbours in the agent's own part, MADGTA's max-min choice
   (Algorithm 2, same draws). Branch 3: the nearest vertex of its part (MADGTA's max-min
   among equally near ones), one hop on a shortest path. An empty part, or two agents at
   the same place (a shared nest before it disperses: their parts would be arbitrary), gives
   MADGTA's own decision.
3. **The end game** is madgta-p's, unchanged (its fallbacks are MADGTA, not the partition).
4. **Optional size gate** (``tip_per_agent``, off by default, screened at 60; selected in
   the benches as ``madgta-k@tip_per_agent=60``): while the belief holds more than
   ``tip_per_agent`` x (agents + 1) vacant vertices the sweep is MADGTA with the dead-end
   tip rule (:meth:`PartSweep.tip_decision`) instead of the partition. It only acts on
   large maps (random-64-64-20, the warehouse), where the partition does nothing
   measurable and MADGTA leaves the tips of dead ends behind; on the 32 x 32 and 16 x 16
   maps the gate never opens and the runs are madgta-k's.

Choices, and why (screened on 16 identical agents, both nest modes, seeds 0-3 of
docs/traversal-variants.md §1 on empty-16-16, random-32-32-20 and room-32-32-4: 24 runs,
makespan against MADGTA unless said, paired, normal 95 % intervals; throw-away script)
---------------------------------------------------------------------------------------
* **Weighted Voronoi, not plain Voronoi nor round robin.** Unweighted Voronoi parts:
  +0.92 % ± 1.30 % (no end game; weighted: -2.16 % ± 1.18 %); a round robin (each agent
  in turn takes its nearest unassigned vertex, exactly balanced counts, scattered parts):
  room-32-32-4, shared nest, seed 0, 666 s against MADGTA's 610 s. The weights never
  balance the counts exactly (hop distances are integers, and an agent between another and
  a region shifts all of it at once): the imbalance kept is about 27 vertices in the median
  decision on room-32-32-4. Balancing harder by raising the
  largest part's weight to its exact k-th margin was worse (room-32-32-4, own nests, seed
  0: 566 s against 531 s; MADGTA 554 s).
* **Balance by count**, not by count plus the travel to the part: -1.66 % against MADGTA
  without end game against -2.16 %.
* **MADGTA's order inside the part**, not the fewest in-part neighbours first (a
  boustrophedon-like compactness rule): -1.07 % against -2.16 % (both without end game);
  branch 3 to the nearest vertex of the part, not MADGTA's max-min over the part: -2.33 %
  against -2.73 % with madgta-p's end game.
* **Vacant neighbours outside the part are left**; taking any vacant neighbour when none
  is in the part: -2.64 % against -2.73 %.
* **MADGTA in the end game's fallbacks and at a shared place**: -3.12 % against -2.73 %
  with the partition there (both against MADGTA); the difference is mostly on
  empty-16-16 (-4.96 % against -3.84 %).
* **40 rounds**: 20 and 60 gave -0.47 % and -0.34 % against madgta-p, 40 gave -1.04 %
  (same 24 runs): the result depends on which unbalanced partition is kept, so the gain
  is not robust to this setting.

Results (docs/traversal-variants.md §6; five MovingAI maps, 16 identical agents, 8 seeds,
both nest modes, 80 paired runs): makespan -1.95 % ± 0.53 % against MADGTA (madgta-p
-1.50 % ± 0.49 %), paired against madgta-p -0.46 % ± 0.34 %; lower than MADGTA in every map
and nest row. The gain is on the small crowded maps (against madgta-p: random-32-32-20
-0.96 %, room-32-32-4 -1.43 %); on random-64-64-20 and the warehouse it is noise (+0.13 %,
+0.01 %). Issue 17's -3 % is not reached. On the 32 gap instances (at most 16 vertices,
always the end game) it is madgta-p, run for run. With the size gate
(``tip_per_agent=60``; the same 80 runs, the small maps' runs unchanged): -2.23 % ± 0.50 %
against MADGTA and -0.27 % ± 0.15 % against madgta-k (random-64-64-20 -1.01 %, warehouse
-0.36 %), no map and nest row above MADGTA. A truly balanced partition (a capacitated
assignment instead of the weights) was as good as the weights, not better, at 2-3 times
the CPU on the large maps (docs/traversal-variants.md §6, "Tried and not kept").
``madgta-f`` (:mod:`.followed`) is this gated madgta-k whose agents follow a searched, kept
end-game plan once a wall is known: -2.88 % ± 0.49 % against MADGTA (§7).

Cost
----
Per decision before the end game: one hop row per agent's place (the field cache MADGTA
already keeps) and up to 40 rounds over (vacant vertices x agents). CPU per run with 16
agents: 0.95 s on empty-16-16, 3.0 s on random-32-32-20, 3.5 s on room-32-32-4, 17 s on
random-64-64-20 and 40 s on warehouse-10-20-10-2-1 in the results' bench (madgta-p:
0.95-7.4 s); with the costs gathered once per decision (the same runs, bit for bit) 12 s
and 28.5 s on the two large maps (4 runs each). With the size gate the partition runs
less often: 6.2 s and 8.9 s per run there (madgta-k in the same bench: 14.4 s, 28.0 s);
the tip rule itself looks at the neighbours of the few vacant neighbours. No message is
added.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.missions.traversal.policies import (
    POLICIES,
    Decision,
    Madgta,
    _pick,
    _sorted_unique,
    get_best_node,
)
from swarmex.missions.traversal.teamplan import MadgtaP

#: the hop count standing for "unreachable" in the partition's costs
_UNREACHABLE = 1e9


@kernel(cache=True, nogil=True)
def _balanced_parts(
    hops: NDArray[np.signedinteger], rows: NDArray[np.int64], vac: NDArray[np.int64],
    off: NDArray[np.float64], rounds: int, assign: NDArray[np.int64],
) -> tuple[int, float]:  # pragma: no cover - compiled
    """Additively weighted Voronoi parts of the vertices ``vac``: ``assign[j]`` is the index
    ``a`` (into ``rows``) of least ``hops[rows[a], vac[j]] + off[a] + w[a]`` (ties: lowest
    ``a``). The weights start at 0 and move towards equal counts for ``rounds`` rounds; the
    first partition of least imbalance (max |count - mean|) is kept. Returns (the last
    round, that imbalance)."""
    m = rows.shape[0]
    n = vac.shape[0]
    # the costs without the weights, gathered once into contiguous rows (the rounds then
    # read them in order instead of hopping through the hop table)
    base = np.empty((n, m))
    for a in range(m):
        row = hops[rows[a]]
        for j in range(n):
            h = row[vac[j]]
            base[j, a] = (_UNREACHABLE if h < 0 else float(h)) + off[a]
    w = np.zeros(m)
    cur = np.empty(n, dtype=np.int64)
    counts = np.zeros(m)
    best_err = np.inf
    target = n / m
    scale = max(np.sqrt(target), 1.0)
    last = 0
    for it in range(rounds):
        last = it
        counts[:] = 0.0
        for j in range(n):
            bi = 0
            bc = np.inf
            for a in range(m):
                c = base[j, a] + w[a]
                if c < bc:
                    bc = c
                    bi = a
            cur[j] = bi
            counts[bi] += 1.0
        mean = counts.sum() / m
        err = 0.0
        for a in range(m):
            e = abs(counts[a] - mean)
            if e > err:
                err = e
        if err < best_err:
            best_err = err
            assign[:] = cur
        if err <= 1.0:
            break
        step = 0.8 * scale / (1.0 + it / 8.0)
        for a in range(m):
            w[a] += step * (counts[a] - mean) / max(mean, 1.0)
    return last, best_err


def _places(belief: TraversalBelief) -> tuple[np.ndarray, np.ndarray]:
    """(ids of the known agents, where each is next free): a moving rival's announced node
    (C05), else its last vertex; the agent itself at its vertex."""
    agents = np.nonzero(belief.loc >= 0)[0]
    agents = agents[agents > 0]
    src = belief.loc[agents].copy()
    nxt = belief.next_loc[agents]
    moving = (nxt >= 0) & (nxt != src) & (agents != belief.me)
    src[moving] = nxt[moving]
    return agents, src


def parts(
    belief: TraversalBelief, rounds: int = 40,
    places: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, int]:
    """The partition of the agent's belief (see the module docstring): (vacant vertices,
    index of the owning agent for each, index of the agent itself); indices are into the
    known agents in id order. ``places``: :func:`_places` of the belief, if already known."""
    known = belief.known
    me = belief.me
    agents, src = _places(belief) if places is None else places
    edge = known.step * belief.time_per_unit[agents]
    off = np.maximum(belief.free_at[agents].astype(float) - belief.now, 0.0) / edge
    off[agents == me] = 0.0  # the agent decides now: no head start
    rows = np.asarray(known.slots(src), dtype=np.int64)
    mi = int(np.nonzero(agents == me)[0][0])
    free = (belief.status == 0) & ~known.blocked
    r = belief.reserved
    free &= (r == 0) | (r == me)
    free &= known.hops[rows[mi]] >= 0
    vac = np.nonzero(free)[0].astype(np.int64)
    assign = np.zeros(vac.size, dtype=np.int64)
    if vac.size:
        _balanced_parts(known.hops, rows, vac, off, rounds, assign)
    return vac, assign, mi


class PartSweep(Madgta):
    """MADGTA kept to the agent's own part of a balanced partition of the vacant vertices,
    recomputed from the belief at every decision (the sweep of ``madgta-k``; see the module
    docstring). ``rounds``: of the weight balancing. ``tip_per_agent``: the size gate (see
    :meth:`tip_decision`; None, the default: off)."""

    name = "madgta-k-sweep"

    def __init__(self, rounds: int = 40, tip_per_agent: int | None = None) -> None:
        if rounds < 1:
            raise ValueError(f"rounds must be >= 1, got {rounds}")
        if tip_per_agent is not None and tip_per_agent < 0:
            raise ValueError(f"tip_per_agent must be >= 0 or None, got {tip_per_agent}")
        self.rounds = rounds
        self.tip_per_agent = tip_per_agent
        self.parted = 0  # decisions taken in the agent's own part (for the benches)
        self.tipped = 0  # decisions the dead-end tip rule made (for the benches)

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        here = belief.here
        if not belief.in_km(here):
            return Decision("job", here, here, 1)
        gate = self.tip_per_agent
        if gate is not None and int((~belief.km_mask()).sum()) > gate * belief.loc.size:
            return self.tip_decision(belief, rng)
        places = _places(belief)
        src = places[1]
        if np.unique(src).size < src.size:  # agents at one place: arbitrary parts
            return Madgta.decide(self, belief, rng)
        vac, assign, mi = parts(belief, self.rounds, places)
        mine = vac[assign == mi]
        if mine.size == 0:
            return Madgta.decide(self, belief, rng)
        inpart = np.zeros(belief.status.size, dtype=bool)
        inpart[mine] = True
        nbrs = belief.graph.neighbors(here)
        near = nbrs[~belief.km_at(nbrs)]
        near = np.unique(near[inpart[near]])
        self.parted += 1
        if near.size == 1:
            return Decision("move", int(near[0]), int(near[0]), 2)
        if near.size:
            v = self.best(belief, near, rng)
            return Decision("move", v, v, 2)
        known = belief.known
        slot = known.slot(here)
        hops = known.hops[slot][mine]
        nearest = mine[hops == hops.min()]
        f = int(nearest[0]) if nearest.size == 1 else self.best(belief, nearest, rng)
        steps = known.first_steps(known.slot(here), f)
        return Decision("move", _pick(steps, rng), f, 3)

    def tip_decision(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        """MADGTA with the dead-end tip rule in front of branch 2: the sweep above the size
        gate (``tip_per_agent``; docs/traversal-variants.md §6).

        A *tip* is a vacant neighbour with at most one vacant neighbour of its own besides
        the agent's vertex (unknown cells count as vacant, known walls and KM do not): the
        end of a dead end or of a 1-wide spur. When some but not all of the vacant
        neighbours are tips, MADGTA's max-min chooses among the tips (the same utilities
        and draws); otherwise MADGTA decides as it always does. Why: on the large maps
        MADGTA leaves such cells behind, and an agent comes back for each later (a trip of
        many moves without a job); taking them while passing removes 90-180 of those moves
        per run. Why only while the belief holds more than ``tip_per_agent`` x (agents + 1)
        vacant vertices (not done, not claimed by a rival, unknown cells counted; the
        screening wrote it as the rows of ``belief.loc``, 1020 for 16 agents with 60): the
        rule breaks MADGTA's spreading away from the rivals, which is what matters on the
        small crowded maps and later on, where madgta-k's partition does the work; on
        the 32 x 32 and 16 x 16 maps the gate never opens. Not on an open lattice (no wall
        known yet): the rule was screened that way, and there the only tips are the grid's
        own corners.
        """
        known = belief.known
        here = belief.here
        if not known.open_lattice:
            g = belief.graph
            nbrs = g.neighbors(here)
            vac = nbrs[~belief.km_at(nbrs)]
            if vac.size > 1:
                vac = _sorted_unique(vac)
                keep = np.zeros(vac.size, dtype=bool)
                for i, c in enumerate(vac.tolist()):
                    around = g.neighbors(c)
                    around = around[around != here]
                    keep[i] = int((~belief.km_at(around)).sum()) <= 1
                tips = vac[keep]
                if 0 < tips.size < vac.size:
                    self.tipped += 1
                    if tips.size == 1:
                        v = int(tips[0])
                    elif known.uniform:  # the compiled utilities, as branch 2's own
                        util = self._utility_matrix(belief, tips, belief.rivals(),
                                                    float(belief.job_time[belief.me]))
                        v = get_best_node(tips, util, rng)
                    else:
                        v = self.best(belief, tips, rng)
                    return Decision("move", v, v, 2)
        return Madgta.decide(self, belief, rng)


class MadgtaK(MadgtaP):
    """:class:`PartSweep` before the end game, madgta-p in it (see the module docstring).

    ``rounds``: of the partition's weight balancing. ``tip_per_agent``: the size gate of
    :meth:`PartSweep.tip_decision` (MADGTA with the dead-end tip rule instead of the
    partition while more than ``tip_per_agent`` x (agents + 1) vertices are vacant; None,
    the default, keeps madgta-k's runs as they were; 60 is the screened value). It is a
    keyword, not a new algorithm name, because it is one constant fitted to two map sizes
    (docs/traversal-variants.md §6) and the benches select it as
    ``madgta-k@tip_per_agent=60``. Every other keyword is madgta-p's (``max_vacant``,
    ``passes``, ...) and madgta-r's.
    """

    name = "madgta-k"

    def __init__(self, rounds: int = 40, tip_per_agent: int | None = None,
                 **teamplan: object) -> None:
        super().__init__(**teamplan)  # type: ignore[arg-type]
        # madgta-r's own gate hands every decision before the end game to the sweep; its
        # other fallbacks (an end game with too few candidates) stay MADGTA
        self.sweep: PartSweep = PartSweep(rounds, tip_per_agent)


POLICIES[MadgtaK.name] = MadgtaK
