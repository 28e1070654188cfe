"""``madgta-h``: MADGTA with heterogeneity-aware claiming by insertion cost.

Why
---
The thesis's objective (seed 000 §3.1) is the *sum* of the agents' travel and job times,
``total_time_all``. With identical agents, MADGTA comes within 2.5 % of the exact optimum on
the 32 small instances of ``bench/gap_traversal_optimal.py``. With mixed speeds and job times
it is 16 % above it (up to 37 %). The sum-optimal plan lets the cheap agents (fast, short
jobs) do nearly everything. MADGTA's "whoever finishes a vertex first takes it" instead
spreads the jobs over the whole team, slow agents included (docs/traversal-optimal.md).

Idea: insertion-cost claiming
-----------------------------
Each agent compares what a vacant vertex ``v`` costs the team if *it* does the job with what
it would cost if a *cheaper* rival did it instead:

* my cost: ``J_me + tpu_me · d_me(v)``, my job plus my travel there (``tpu``: seconds per
  length unit, ``d``: distance on my known graph);
* a rival's insertion cost: ``J_r + tpu_r · (step + g_r(v) / K(v))``. The rival sweeps its
  *cell* anyway: its last vertex plus the vacant vertices it reaches before anyone else
  (arrival plus job time, measured as Algorithm 2 measures it). Taking ``v`` costs it a job,
  one edge (``step``, the shortest edge), and its share of the detour ``g_r(v)`` from its
  cell to ``v``. That detour is paid once for the whole patch around ``v``, so it is split
  over ``K(v)``, the number of vacant vertices in ``v``'s own cell.

A rival is *cheaper* when its cost per vertex, ``J_r + tpu_r · step``, is below mine. The
agent keeps ``v`` as a candidate when

    my cost(v) <= (1 + rho) · min over cheaper rivals of their insertion cost(v)

Algorithm 1 then runs on the kept vertices only: branch 2 over the kept vacant neighbours
with MADGTA's max-min utility, branch 3 with ``madgta+``'s distant-target rule
(:class:`~swarmex.missions.traversal.variants.MadgtaPlus`).

If no vertex is kept, the agent *retires* (hands over), but only when a cheaper rival is
sure to reach it (:meth:`MadgtaH.reached_for_sure`). Otherwise it keeps all of them (a
vertex no cheaper rival can reach has an infinite insertion cost, so it is always kept: no
vertex kept means every one is within a cheaper rival's reach).

A retiring agent broadcasts one ``leave`` message
(:data:`swarmex.missions.traversal.agent.LEAVE`, 14 bytes, counted in ``messages`` and
``message_bytes``). Receivers drop it as a rival. Without that message the others would keep
counting on it, in their utilities and in this very test. Every policy that has
``announce_leave`` sends it when it finishes, so a plain finish (nothing vacant left) is
announced too: one message per agent.

What an agent must know
-----------------------
Only its belief. The speeds and job times of all agents are in every belief
(``TraversalBelief.time_per_unit`` and ``job_time``). The thesis's agents get them before
the start: the server's reply to C22 carries every rival's job and travel speed. So no new
announcement is needed for speeds. Rivals' positions come from C04/C05/C07, as in MADGTA.
The one extra message is ``leave``.

Choices, and why
----------------
* **A sure handover, not an optimistic one.** Paths on the known graph treat unknown
  vertices as free. A test of "every vertex I can reach, a cheaper rival can reach too" on
  that graph is therefore not safe. A wall that nobody has seen yet may cut a part of the
  map off from the rival, and once I have stopped nobody would do that part. A test found
  exactly this (``test_a_component_no_cheaper_rival_can_reach_is_never_given_up``).
  - The handover therefore needs a path from a cheaper rival to *my* vertex through vertices
    known to be free: the done ones and their neighbours that are not obstacles, all of
    which an agent has sensed.
  - The rival can then reach everything I can reach, through me. It does not stop while any
    of it is vacant in its belief. The cheapest agent never retires.
  - On the gap instances this made no measurable difference to the sum. It does cost the
    optimum on a corridor with the two agents at its ends: the slow agent works until the
    fast one's known cells reach it.
* **rho = 0.25.** This trades the sum against the makespan on mixed teams. The table gives
  the mixed-agent gaps to the optimum on the 32 gap instances:

  | setting | sum gap | makespan gap | seeds |
  |---|---|---|---|
  | rho 0.2 | 6.1 % | 49 % | 3, exploratory |
  | rho 0.25 | 7.8 % | 37 % | 5, bench |
  | rho 0.3 | 8.7 % | 31 % | 3, exploratory |
  | rho 0.5 | 11.5 % | 13 % | 5, bench |
  | rho 0.7 | 14.8 % | 5.2 % | 5, bench |
  | MADGTA | 16.0 % | 4.8 % | 5, bench |

  0.25 is the smallest makespan cost that meets the issue's target of 8 % for the sum.
  - The exact optimum itself cannot do much better. Among all plans whose makespan is
    within 2 % of the optimal makespan, the least sum gap on these mixed instances is
    12.5 %. Within 10 % it is 11.6 %. Within 25 % it is 8.7 %. Within 50 % it is 5.3 %.
    (This comes from the MILP's set-partition model with a makespan cap; see
    docs/traversal-variants.md §3.)
  - So no method can meet both "sum <= 8 %" and "makespan <= 2 %" on mixed teams.
  - ``MadgtaH(rho=...)`` picks another point of the trade-off.
  - On real maps the price grows with the team. On five MovingAI maps with mixed fleets,
    the sum falls by 19 % (in 100 of 100 paired runs), while the makespan is 4.6× MADGTA's
    with 8 agents and 7.6× with 16: the cheapest agent does most of the map alone. A fleet
    that must finish soon should use madgta/madgta+ or a large rho.
* **Capping the hand-over by the team's balanced finish.** The agent would keep whatever
  would make a cheaper rival finish later than (1 + kappa) × the balanced finishing time of
  the whole team. This changed nothing (sum gap 15.7 %, makespan 4.8 %, kappa 0.25–1). The
  arrival-time cells of MADGTA are already balanced in time, so it leaves no spare time to
  give away. It was dropped.
* **The amortised detour.** Two other estimates of the rival's cost land on the same
  trade-off curve within noise:
  - a flat per-vertex comparison, ``g = 0``: rho 0.3 gives a sum gap of 7.4 % with a makespan
    gap of 44 %, rho 0.4 gives 9.8 % and 27 %;
  - the full detour per vertex, ``J_r + tpu_r · max(step, g_r(v))``: rho 0.3 gives 7.9 % and
    37 %, rho 0.4 gives 9.8 % and 26 %.

  The amortised form is kept because it reads right on a long patch, where the rival's way
  in is paid once, and it is no worse on the gap instances.
* **Only cheaper rivals count, with a strict inequality.** On a team of identical agents
  nobody is cheaper, so the policy is ``madgta+``: the same paths, with one ``leave``
  message more per agent (tested).

Cost
----
On identical teams, that of ``madgta+``. On mixed teams, each decision takes the rivals'
distances to the vacant vertices and one multi-source distance field per cheaper rival:
O(rivals · n) per decision, where MADGTA's compiled path is about O(n). When nothing is kept
there is one more field, over the known-free vertices. That is fine for the maps of the
benches; den520d-sized mixed teams would want the compiled kernels.

What was tried for the makespan on identical teams, and did not help
--------------------------------------------------------------------
The issue also asks for a makespan 3 % below MADGTA's on real maps with 16 agents. That
target is not reached, and ``madgta-h`` behaves there like ``madgta+``. The attempts, each
on empty-16-16, random-32-32-20 and room-32-32-4 with 16 agents, 2 seeds, both nest modes,
compared with MADGTA's makespan (``madgta+`` on the same runs: -1.2 %):

* *End-phase team plan.* Once at most 4 vacant vertices per agent remain, each agent plans
  list scheduling (earliest finish first) for the whole team from its belief and heads for
  its own first vertex: -0.8 %. With 8 per agent: 0.0 %.
* *Whole-team planning on small instances,* with local search (relocate moves) on
  makespan + λ·sum: the identical-agent makespan gap on the 32 instances rose from 3.2 % to
  7–8 %.
* *Claimed distant targets.* The branch-3 target is announced in the C05 (4 bytes), rivals
  exclude it, and the claimer sticks to it: -1.0 to -1.2 %. Half of the branch-3 trips still
  end at a vertex that someone else did, mostly a sweeping agent that took it as a
  neighbour.
* *madgta+ with rule 2 always on,* or a doorstep of radius 4: -1.25 % and -1.3 %.
* *Quitting when hopeless* (retire in branch 3 when every rival arrives sooner, work ahead
  included): the identical-agent sum gap fell from 2.5 % to 1.9 %, but the makespan gap rose
  from 2.7 % to 3.6 %.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.missions.traversal.policies import (
    POLICIES,
    Decision,
    Madgta,
    _pick,
    get_best_node,
)
from swarmex.missions.traversal.variants import MadgtaPlus
from swarmex.planning.distance import distance_field, on_path_neighbors


@dataclass(frozen=True)
class Claims:
    """What one decision knows about who should do which vacant vertex.

    ``vacant``: the vacant vertices the agent can reach (sorted), ``mine``: its distances
    to them; ``keep``: the ones it keeps; ``covered``: the ones a cheaper rival can reach on
    the known graph (unknown vertices taken as free); ``cheaper``: ids of the cheaper rivals;
    ``handover``: see :meth:`MadgtaH.reached_for_sure`.
    """

    vacant: np.ndarray
    mine: np.ndarray
    keep: np.ndarray
    covered: np.ndarray
    cheaper: np.ndarray
    #: nothing kept, and a cheaper rival is sure to reach my vertex (so everything I reach)
    handover: bool = False

    @property
    def retire(self) -> bool:
        return self.handover


class MadgtaH(MadgtaPlus):
    """madgta+ with heterogeneity-aware claiming by insertion cost (see the module docstring).

    ``rho``: how much dearer than a cheaper rival's insertion cost a vertex may be for the
    agent to still take it (0: never dearer; larger values trade the sum for the makespan).
    The other arguments are :class:`MadgtaPlus`'s.
    """

    name = "madgta-h"
    #: the agent core broadcasts ``leave`` when this policy's agent finishes
    announce_leave = True
    #: branch 2 may differ from MADGTA's (the environment must ask this policy every time)
    madgta_branch2 = False

    def __init__(
        self,
        rho: float = 0.25,
        claim_radius: float = 2.0,
        workload: bool = True,
        workload_below: float = 0.0,
    ) -> None:
        if not rho >= 0:
            raise ValueError(f"rho must be >= 0, got {rho}")
        super().__init__(claim_radius, workload, workload_below)
        self.rho = float(rho)
        self._step: tuple[int, float] = (-1, 1.0)

    # ------------------------------------------------------------------ costs
    def step(self, belief: TraversalBelief) -> float:
        """The shortest edge of the graph: the least a rival's insertion can add."""
        graph = belief.graph
        if self._step[0] != id(graph):
            w = graph.weights
            self._step = (id(graph), float(w.min()) if w.size else 1.0)
        return self._step[1]

    def unit_costs(self, belief: TraversalBelief) -> np.ndarray:
        """Each agent's cost per vertex in a sweep (one job plus one shortest edge), by id."""
        return belief.job_time + belief.time_per_unit * self.step(belief)

    def cheaper_rivals(self, belief: TraversalBelief) -> np.ndarray:
        """Rivals (still in the mission) whose cost per vertex is strictly below mine."""
        c = self.unit_costs(belief)
        rivals = belief.rivals()
        return rivals[c[rivals] < c[belief.me] * (1.0 - 1e-9)]

    def claims(self, belief: TraversalBelief) -> Claims:
        """The insertion-cost test over every vacant vertex I can reach."""
        known = belief.known
        me = belief.me
        vacant = np.nonzero(~belief.km_mask())[0]
        mine = known.distances(belief.here, vacant)
        ok = np.isfinite(mine)
        vacant, mine = vacant[ok], mine[ok]
        cheaper = self.cheaper_rivals(belief)
        keep = np.ones(vacant.size, dtype=bool)
        covered = np.zeros(vacant.size, dtype=bool)
        if cheaper.size == 0 or vacant.size == 0:
            return Claims(vacant, mine, keep, covered, cheaper)
        tpu, jt = belief.time_per_unit, belief.job_time
        rivals = belief.rivals()
        # arrival plus job time of every agent still in the mission: whose cell each vertex is
        arrival = np.empty((rivals.size + 1, vacant.size))
        arrival[0] = mine * tpu[me] + jt[me]
        for i, r in enumerate(rivals):
            arrival[i + 1] = known.distances(int(belief.loc[r]), vacant) * tpu[r] + jt[r]
        owner = np.argmin(arrival, axis=0)  # 0: me, i + 1: rivals[i]
        size = np.bincount(owner, minlength=rivals.size + 1)[owner]  # of each vertex's cell
        step = self.step(belief)
        best = np.full(vacant.size, np.inf)
        for i, r in enumerate(rivals):
            if r not in cheaper:
                continue
            covered |= np.isfinite(arrival[i + 1])
            cell = np.concatenate(([int(belief.loc[r])], vacant[owner == i + 1]))
            detour = distance_field(belief.graph, cell, known.blocked)[vacant]
            ins = jt[r] + tpu[r] * (step + detour / size)
            best = np.minimum(best, ins)
        keep = arrival[0] <= (1.0 + self.rho) * best
        handover = False
        if not keep.any():
            handover = self.reached_for_sure(belief, cheaper)
            if not handover:  # nobody cheaper is sure to get here: keep it all. (A vertex
                # no cheaper rival reaches has best = inf and is kept above, so here every
                # vacant vertex is covered; "keep what they cannot reach" would keep nothing.)
                keep = np.ones(vacant.size, dtype=bool)
        return Claims(vacant, mine, keep, covered, cheaper, handover)

    def reached_for_sure(self, belief: TraversalBelief, cheaper: np.ndarray) -> bool:
        """Whether a cheaper rival can walk to my vertex through vertices known to be free.

        Then it can reach everything I can reach (through me), whatever walls are still
        unknown, and it does not stop while any of it is vacant in its belief. An
        optimistic test (unknown vertices taken as free, as for paths) is not enough. It
        could hand over a part of the map that a wall nobody has seen yet cuts off from the
        rival, and nobody would ever do that part."""
        sure = distance_field(belief.graph, belief.here, ~self.known_free(belief))
        return bool(np.isfinite(sure[belief.loc[cheaper]]).any())

    @staticmethod
    def known_free(belief: TraversalBelief) -> np.ndarray:
        """Vertices known to be free: the done ones and their neighbours that are not known
        obstacles. An agent did every done vertex's job there, and the sensor reports every
        obstacle around the vertex an agent stands on, so those neighbours are known. Any
        other vertex may still be a wall nobody has seen."""
        g = belief.graph
        done = belief.status > 0
        out = done.copy()
        out[g.indices[np.repeat(done, np.diff(g.indptr))]] = True
        out &= belief.status != -1
        return out

    # ------------------------------------------------------------------ deciding
    def retires(self, belief: TraversalBelief) -> bool:
        """Whether the agent stops now although vacant vertices remain (no generator draw).

        The traversal environment asks this before it asks for an action."""
        if not belief.in_km(belief.here) or self.cheaper_rivals(belief).size == 0:
            return False
        return self.claims(belief).retire

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        here = belief.here
        if not belief.in_km(here):
            return Decision("job", here, here, 1)
        if self.cheaper_rivals(belief).size == 0:
            return super().decide(belief, rng)  # nobody cheaper: madgta+ itself
        c = self.claims(belief)
        if c.vacant.size == 0 or c.retire:
            return Decision("finish")
        vacant, mine = c.vacant[c.keep], c.mine[c.keep]
        nbrs = belief.graph.neighbors(here)
        near = np.isin(vacant, nbrs)
        if near.any():  # branch 2 over the kept vacant neighbours, MADGTA's utilities
            cands = vacant[near]
            v = get_best_node(cands, Madgta.utilities(self, belief, cands), rng)
            return Decision("move", v, v, 2)
        f = self.distant_target(belief, vacant, mine, rng)  # branch 3, madgta+'s rule
        d = belief.known.distances(f, np.concatenate(([here], nbrs)))
        steps = on_path_neighbors(belief.graph, here, d[0], d[1:])
        return Decision("move", _pick(steps, rng), f, 3)


POLICIES[MadgtaH.name] = MadgtaH

__all__ = ["Claims", "MadgtaH"]
