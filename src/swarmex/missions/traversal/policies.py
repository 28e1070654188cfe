"""Decision rules for the traversal mission: MADGTA (seed 000, Algorithms 1–2) and variants.

A policy is pure decision code: ``decide(belief, rng)`` reads one agent's
:class:`~swarmex.missions.traversal.belief.TraversalBelief` and returns a :class:`Decision`.
The simulator (:mod:`swarmex.missions.traversal.sim`) and the networked agent both call it.

How the thesis's open points are read here (spec §6; docs/traversal.md repeats this):

1. KM holds vertices known done, known obstacles, and vertices a rival has *announced* as
   its next node (C05). The agent's own position is not added by LOOK (that would skip the
   nest job). A vertex becomes done ("conditionally accomplished") when its job starts (C07).
2. Obstacles seen by any agent are merged into every belief (the message carries them).
3. SP uses each agent's own speed on the graph minus known obstacles; unknown obstacles count
   as free. Costs are real seconds.
4. The max-min of Algorithm 2 runs over W (the thesis writes adj(loc(a))). Ties go to the
   sum over rivals, then to a uniform draw from the run's generator over the tied vertices
   in ascending vertex order. The "arbitrary" next hop of branch 3 is drawn the same way.
5. A rival's distance is measured from the last vertex it physically reached.
8. Termination: the agent stops when no vacant vertex is reachable on its known graph.
9. With no known rival (one agent, or before anyone else has started), util is minus the
   agent's own cost: it goes to the nearest vacant vertex.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.traversal.belief import TraversalBelief
from swarmex.planning.distance import steps_towards


@dataclass(frozen=True)
class Decision:
    kind: str  # "job" (branch 1), "move" (branches 2 and 3) or "finish"
    node: int = -1  # where to do the job / the adjacent vertex to move to
    target: int = -1  # the vertex GetBestNode chose (== node in branches 1-2)
    branch: int = 0


def _pick(candidates: np.ndarray, rng: np.random.Generator) -> int:
    if candidates.size == 1:
        return int(candidates[0])
    return int(np.sort(candidates)[rng.integers(candidates.size)])


def get_best_node(
    candidates: np.ndarray, util: np.ndarray, rng: np.random.Generator
) -> int:
    """Algorithm 2's selection from a utility matrix ``util[rival, candidate]``.

    Max over candidates of the min over rivals; ties broken by the max of the sum over
    rivals; remaining ties by a seeded uniform draw.
    """
    if util.shape[0] == 0:
        raise ValueError("util needs at least one row")
    mins = util.min(axis=0)
    best = mins.max()
    tied = _close(mins, best)
    if tied.sum() == 1:
        return int(candidates[np.argmax(tied)])
    sums = util[:, tied].sum(axis=0)
    tied_idx = np.nonzero(tied)[0]
    top = tied_idx[_close(sums, sums.max())]
    return _pick(candidates[top], rng)


def _close(values: np.ndarray, best: float) -> np.ndarray:
    if np.isinf(best):
        return values == best
    return np.abs(values - best) <= 1e-9 * (1.0 + abs(best))


class Madgta:
    """Algorithm 1's COMPUTE with Algorithm 2's GetBestNode."""

    name = "madgta"

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        here = belief.here
        if not belief.in_km(here):
            return Decision("job", here, here, 1)
        nbrs = belief.graph.neighbors(here)
        vacant = nbrs[~belief.km_at(nbrs)]
        if vacant.size:
            v = self.best(belief, np.unique(vacant), rng)
            return Decision("move", v, v, 2)
        mine = belief.known.field(here)
        far = np.nonzero(~belief.km_mask() & np.isfinite(mine))[0]
        if far.size == 0:
            return Decision("finish")
        f = self.best(belief, far, rng)
        steps = steps_towards(belief.graph, belief.known.field(f), here)
        return Decision("move", _pick(steps, rng), f, 3)

    def best(self, belief: TraversalBelief, cands: np.ndarray, rng) -> int:
        return get_best_node(cands, self.utilities(belief, cands), rng)

    def utilities(self, belief: TraversalBelief, cands: np.ndarray) -> np.ndarray:
        me = belief.me
        mine = belief.known.field(belief.here)[cands] * belief.time_per_unit[me]
        mine = mine + belief.job_time[me]
        rivals = belief.rivals()
        if rivals.size == 0:
            return -mine[None, :]
        util = np.empty((rivals.size, cands.size))
        for i, r in enumerate(rivals):
            theirs = belief.known.field(int(belief.loc[r]))[cands] * belief.time_per_unit[r]
            util[i] = theirs + belief.job_time[r] - mine
        return util


class Nearest(Madgta):
    """Baseline: the nearest vertex nobody has done or claimed, rivals ignored."""

    name = "nearest"

    def utilities(self, belief: TraversalBelief, cands: np.ndarray) -> np.ndarray:
        mine = belief.known.field(belief.here)[cands] * belief.time_per_unit[belief.me]
        return -mine[None, :]


POLICIES: dict[str, type[Madgta]] = {"madgta": Madgta, "nearest": Nearest}


def make_policy(name: str) -> Madgta:
    try:
        return POLICIES[name]()
    except KeyError:
        known = ", ".join(sorted([*POLICIES, "optimal"]))
        raise InputError(f"unknown traversal algorithm {name!r} (choose from {known})") from None
