"""Variants of MADGTA beyond the seed (registered in ``POLICIES`` on import).

``madgta+`` (:class:`MadgtaPlus`)
=================================

What limits MADGTA's makespan
-----------------------------
MADGTA's agents are never idle, so every agent's ``total_time`` is close to the mission's
end, and the makespan is about ``(jobs × job time + moves × edge time) / m``. Jobs are fixed.
The lever is moves that do no job. Instrumenting MADGTA on the real maps gives the
following picture:

* Every such move is a trip through done vertices in branch 3 ("no vacant neighbour").
  Branch-2 moves never collide, because the C05 reservation prevents it.
* Almost every trip ends at a vertex that some agent *abandoned* earlier: it was a vacant
  neighbour the agent did not choose in branch 2.
* Trips pile up at the end of a mission. With 16 agents on random-32-32-20, the last tenth
  of the mission has about 20 jobs and 370 wasted moves. Idle agents keep chasing the
  few vacant vertices that sit next to a rival. Those rivals are about to take them, so
  the idle agents lose every race, one after another. Meanwhile the last large patch is
  worked by the one or two agents that own it.

Branch 2 (take an adjacent vacant vertex) is already good: moving away from the nearest
rival makes sweeping fronts that leave few holes. None of the alternatives tried did
better. These were Warnsdorff's fewest-onward-neighbours rule (as a weight, a filter or a
tie-break), clipping the advantage, claiming contested cells first, nearest-first, rivals
timed from their announced node, and a greedy agent–vertex matching for distant targets.
So ``madgta+`` keeps branches 1 and 2 exactly as in the thesis. It changes only how an
agent with no vacant neighbour chooses its distant target, which is Algorithm 1's lines
20–26.

The two changes, both computed from the agent's own belief
----------------------------------------------------------
1. **Leave a rival its doorstep.** Some vacant vertices lie within ``claim_radius`` edges of
   the node a rival last announced (``belief.next_loc``: its C05 next node or C07 job node),
   on the known graph. The rival is about to take them, so a trip there is a lost race.
   They are dropped from the distant candidates unless nothing else is left. MADGTA
   measures a rival from its last physical vertex and ignores where it is heading
   (spec §6.5).
2. **When you lose everywhere, help the busiest rival.** Suppose even the best remaining
   candidate has a negative max–min advantage. Algorithm 2 as written then sends the agent
   to the vertex where it loses by the least. In practice that is usually another rival's
   doorstep, so the race is lost again. ``madgta+`` instead estimates when a rival will
   *really* get to a vertex. A rival works through the vacant vertices of its own Voronoi
   cell (the ones it reaches before anyone else) roughly nearest-first. It therefore
   reaches ``v`` only after the cell's vertices nearer to it, and each of those costs about
   one job plus one edge::

       arrival_r(v) = SP_r(loc_r, v) + J_r + wait_r
                      + #{u in cell_r : SP_r(loc_r, u) < SP_r(loc_r, v)} · (J_r + T_r)

   ``wait_r = max(free_at_r − now, 0)`` is the rival's remaining job or travel time, from
   the eta that C05/C07 carry. Algorithm 2's max–min then runs on these arrival times. The
   idle agent is sent to the far side of the largest remaining patch, which the patch's
   owner would reach last, and not into a race it cannot win.

Rule 2 changes nothing while the agent has a positive advantage somewhere, that is, during
the dispersion phase the thesis relies on. Rule 1 only removes vertices next to a rival.
Both need nothing beyond what the §4.1/§4.2 messages already carry. The policy reads only
``belief``: ``status`` and ``reserved`` (through KM), ``loc``, ``next_loc``, ``free_at``,
``now``, the speeds and job times every agent knows, and distances on its own known graph.

The gain is small but consistent: about 0.3 % lower makespan over five real maps, agent
counts and nests pooled, and 1–3 % on crowded maps with 16 agents. There is no effect on a
large map with few agents per cell (ost003d). The figures are in
docs/traversal-variants.md and come from bench/compare_traversal_variants.py. MADGTA is
already within a few per cent of ``jobs × (J + T) / m`` on open maps, so there is little
left to gain there.
"""

from __future__ import annotations

import numpy as np

from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.missions.traversal.policies import (
    POLICIES,
    Decision,
    Madgta,
    _pick,
    get_best_node,
)


class MadgtaPlus(Madgta):
    """MADGTA with rival-aware distant targets (see the module docstring).

    ``claim_radius``: graph distance around a rival's announced node that counts as its
    doorstep (0 turns rule 1 off). ``workload``: use rule 2. ``workload_below``: apply rule
    2 when the best max–min advantage is at most this many of the agent's edge times (0:
    only when it loses everywhere).
    """

    name = "madgta+"

    def __init__(
        self,
        claim_radius: float = 2.0,
        workload: bool = True,
        workload_below: float = 0.0,
    ) -> None:
        if claim_radius < 0:
            raise ValueError(f"claim_radius must be >= 0, got {claim_radius}")
        self.claim_radius = claim_radius
        self.workload = workload
        self.workload_below = workload_below

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        here = belief.here
        nbrs = belief.graph.neighbors(here)
        if not belief.in_km(here) or not belief.km_at(nbrs).all():
            return super().decide(belief, rng)  # branches 1 and 2: Algorithms 1-2 unchanged
        known = belief.known
        vacant = np.nonzero(~belief.km_mask())[0]
        mine = known.distances(here, vacant)
        reachable = np.isfinite(mine)
        far, mine = vacant[reachable], mine[reachable]
        if far.size == 0:
            return Decision("finish")
        f = self.distant_target(belief, far, mine, rng)
        # line 26: a neighbour on a shortest path to f, drawn as MADGTA draws it
        d = known.distances(f, np.concatenate(([here], nbrs)))
        w = belief.graph.neighbor_weights(here)
        steps = nbrs[np.abs(d[1:] + w - d[0]) <= 1e-9 * (1.0 + d[0])]
        return Decision("move", _pick(steps, rng), f, 3)

    # ------------------------------------------------------------------ branch 3
    def distant_target(
        self,
        belief: TraversalBelief,
        far: np.ndarray,
        mine: np.ndarray,
        rng: np.random.Generator,
    ) -> int:
        """GetBestNode over the vacant vertices ``far`` (``mine``: my distances to them)."""
        me = belief.me
        tpu = belief.time_per_unit
        my_cost = mine * tpu[me] + belief.job_time[me]
        rivals = belief.rivals()
        if rivals.size == 0:
            return get_best_node(far, -my_cost[None, :], rng)
        # rivals' travel times to every vacant vertex, from the last vertex each reached (as
        # Algorithm 2 measures them; these fields are the ones MADGTA keeps cached)
        theirs = np.empty((rivals.size, far.size))
        for i, r in enumerate(rivals):
            theirs[i] = belief.known.distances(int(belief.loc[r]), far) * tpu[r]
        keep = self._off_doorsteps(belief, far, rivals)
        util = theirs[:, keep] + belief.job_time[rivals][:, None] - my_cost[keep]
        cands = far[keep]
        margin = self.workload_below * tpu[me]
        if self.workload and util.min(axis=0).max() <= margin:
            util += self._work_ahead(belief, rivals, mine * tpu[me], theirs)[:, keep]
        return get_best_node(cands, util, rng)

    def _off_doorsteps(
        self, belief: TraversalBelief, far: np.ndarray, rivals: np.ndarray
    ) -> np.ndarray:
        """Mask of ``far`` without the vertices near a rival's announced node (all if none).

        The doorstep is a breadth-first ball of ``claim_radius`` edges on the known graph,
        grown from the node each rival announced (C05/C07).
        """
        if self.claim_radius <= 0:
            return np.ones(far.size, dtype=bool)
        graph, blocked = belief.graph, belief.known.blocked
        ball = {self._rival_node(belief, int(r)) for r in rivals}
        frontier = {(v, 0.0) for v in ball}
        while frontier:
            nxt = set()
            for v, dv in frontier:
                for u, w in zip(
                    graph.neighbors(v).tolist(), graph.neighbor_weights(v).tolist(), strict=True
                ):
                    if dv + w <= self.claim_radius + 1e-9 and not blocked[u] and u not in ball:
                        ball.add(u)
                        nxt.add((u, dv + w))
            frontier = nxt
        near = np.isin(far, np.fromiter(ball, dtype=np.int64))
        return ~near if (~near).any() else np.ones(far.size, dtype=bool)

    @staticmethod
    def _rival_node(belief: TraversalBelief, r: int) -> int:
        """Where rival ``r`` will next be free: its announced node, else its last vertex."""
        nxt = int(belief.next_loc[r])
        return nxt if nxt >= 0 else int(belief.loc[r])

    @staticmethod
    def _work_ahead(
        belief: TraversalBelief, rivals: np.ndarray, mine: np.ndarray, theirs: np.ndarray
    ) -> np.ndarray:
        """Seconds of work each rival does before it can reach each vacant vertex.

        ``mine`` / ``theirs``: my and the rivals' travel times to the vacant vertices. A
        rival is busy until ``free_at`` (its announced job end or arrival), then works
        through the vacant vertices of its own Voronoi cell (those it reaches before anybody
        else) nearest first, one job and about one edge each; so at vertex ``v`` it arrives
        after the cell's vertices nearer to it than ``v`` are done.
        """
        tpu, jt = belief.time_per_unit[rivals], belief.job_time[rivals]
        wait = np.maximum(belief.free_at[rivals] - belief.now, 0.0)
        owner = np.argmin(np.vstack([mine[None, :], theirs]), axis=0)  # 0 = me
        extra = np.empty_like(theirs)
        for i in range(rivals.size):
            cell = np.sort(theirs[i][owner == i + 1])
            ahead = np.searchsorted(cell, theirs[i] - 1e-9, side="left")
            extra[i] = wait[i] + ahead * (jt[i] + tpu[i])
        return extra


POLICIES[MadgtaPlus.name] = MadgtaPlus
