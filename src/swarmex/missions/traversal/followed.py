"""``madgta-f``: madgta-k whose agents, once a wall is known, follow their own end-game team
plan, improved by ruin and recreate and kept from one decision to the next.

Idea
----
madgta-k (:mod:`.partition`) sweeps the known graph by parts and ends with madgta-p's end
game (:mod:`.teamplan`), where the team plan's first vertex is one candidate of a MADGTA
rollout. On walled maps a better plan is worth more when it is followed than when the
rollout judges it (docs/traversal-variants.md §5), so in the end game madgta-f:

1. **plans as madgta-p does** (MADGTA's simulated routes, then the min-max local search);
2. **brings its previous plan up to date** (``keep``): the vertices still to do keep their
   routes and order, new ones go where they end a route soonest, and after the local search
   it replaces the plan from MADGTA's routes if it is better;
3. **runs 30 rounds of ruin and recreate** (``ils``) on it, so the rounds add up from one
   decision to the next;
4. **goes to its own route's first vertex** (``follow="walls"``) once a wall is known. On a
   lattice with no wall known the decision is madgta-k's rollout, unchanged: there the
   rollout already does well and a followed plan lost.

Before the end game it is madgta-k with the size gate (``tip_per_agent=60``): MADGTA with the
dead-end tip rule while much is vacant, then madgta-k's partition sweep.

Why this combination, and what it costs: see docs/traversal-variants.md §7 (results on the
five real maps, 16 agents, 8 seeds, both nest modes, against MADGTA and madgta-k). No message
is added: the plan is made from the agent's belief alone.
"""

from __future__ import annotations

from swarmex.missions.traversal.partition import MadgtaK
from swarmex.missions.traversal.policies import POLICIES


class MadgtaF(MadgtaK):
    """madgta-k with the size gate and a followed, kept, searched end-game plan (see the
    module docstring). Keywords are madgta-k's and madgta-p's; the defaults are the
    measured method, other values are for the benches (``madgta-f@ils=60``)."""

    name = "madgta-f"

    def __init__(self, tip_per_agent: int | None = 60, follow: bool | str = "walls",
                 ils: int = 30, keep: bool = True, **options: object) -> None:
        super().__init__(tip_per_agent=tip_per_agent, follow=follow, ils=ils, keep=keep,
                         **options)  # type: ignore[arg-type]


POLICIES[MadgtaF.name] = MadgtaF
