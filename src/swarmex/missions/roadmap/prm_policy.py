"""A walker on the PRM baseline: the same minimum-weight rule, on a graph with cycles.

At each node the walker takes the incident edge of least global weight (uniform among ties)
and adds 1 to it, exactly the WMA-RRT coverage rule without branches, Sync or dedicated
copies (a graph has no "way back" to mark). On a tree that rule is a DFS that returns home;
on a graph with cycles the walker re-enters areas it has seen (Fig. 7), leaves regions
half-done (Figs. 8–9) and, with no COMPLETE flag, never knows it is finished — the
simulation stops it at the step budget.

Goal search: the finder marks its loop-erased walk (see
:class:`~swarmex.missions.roadmap.blackboard.PRMBoard`); a walker that steps onto a marked node
follows the marks to the anchor and then the leg to the goal; others keep walking.

Choices open to another policy (:meth:`PRMWalker.choice`): any edge at the walker's node,
except while it follows the marks or the goal leg.
"""

from __future__ import annotations

import numpy as np

from swarmex.missions.roadmap.blackboard import PRMBoard
from swarmex.missions.roadmap.wma_policy import Choice, Move, _GoalLegs


class PRMWalker(_GoalLegs):
    def __init__(self, ident: int, start: np.ndarray, entry: int, board: PRMBoard) -> None:
        self.id = ident
        self.xy = np.asarray(start, dtype=np.float64)
        self.board = board
        self.entry = int(entry)
        self.node = -1
        self.state = "entry" if entry >= 0 else "stuck"
        self.walk: list[tuple[int, int]] = []
        self.legs: list[np.ndarray] = []

    def decide(self, t: int, rng: np.random.Generator) -> Move | None:
        b = self.board
        if self.state in ("stuck", "at-goal"):
            return None
        if self.state == "entry":
            self.state = "walk"
            self.walk.append((self.entry, -1))
            return Move(b.rm.pos[self.entry], -1, self.entry)
        if self.state == "leg":
            return self._next_leg()
        if b.anchor is not None:
            if self.node == b.anchor:
                return self._start_legs(b.leg)
            if self.node in b.trail_next:
                v, e = b.trail_next[self.node]
                b.traversals[e] += 1
                return Move(b.rm.pos[v], e, v)
        if not b.rm.adjacency[self.node]:
            self.state = "stuck"  # an isolated node: nowhere to go
            return None
        return self.take(*self.choose(rng))

    def choice(self) -> Choice | None:
        """This step's choice of edge, or None when the step is forced."""
        b = self.board
        if self.state != "walk" or self.node < 0:
            return None
        if b.anchor is not None and (self.node == b.anchor or self.node in b.trail_next):
            return None
        nbrs = b.rm.adjacency[self.node]
        return Choice("walk", tuple(int(e) for _, e in nbrs)) if len(nbrs) > 1 else None

    def seed_choice(self, choice: Choice, rng: np.random.Generator) -> int:
        """The edge the least-weight rule takes; draws from ``rng``."""
        return int(self.choose(rng)[1])

    def carry_out(self, choice: Choice, option: int) -> Move:
        """Walk edge ``option`` (one of ``choice.options``)."""
        if option not in choice.options:
            raise ValueError(f"option {option} is not one of {choice.options}")
        u, v = self.board.rm.edges[option]
        return self.take(int(v) if int(u) == self.node else int(u), option)

    def choose(self, rng: np.random.Generator) -> tuple[int, int]:
        """The walk's rule at a node with neighbours: (next node, edge) of least weight."""
        nbrs = self.board.rm.adjacency[self.node]
        wg = self.board.w_g
        low = min(wg[e] for _, e in nbrs)
        best = [ve for ve in nbrs if wg[ve[1]] == low]
        return best[int(rng.integers(len(best)))] if len(best) > 1 else best[0]

    def take(self, v: int, e: int) -> Move:
        """Walk edge ``e`` to node ``v`` (a neighbour of the current node)."""
        b = self.board
        b.traverse(e)
        self.walk.append((v, e))
        return Move(b.rm.pos[v], e, v)

    def arrive(self, move: Move, t: int) -> None:
        self.xy = np.asarray(move.to, dtype=np.float64)
        if move.node >= 0:
            self.node = move.node

    def found_goal(self, p: np.ndarray, goal: np.ndarray, t: int) -> None:
        b = self.board
        if b.anchor is not None or self.node < 0:
            return
        leg = [np.asarray(p, dtype=np.float64), np.asarray(goal, dtype=np.float64)]
        if np.allclose(leg[0], self.xy):
            leg = leg[1:]
        b.flag_goal(self.walk, self.node, leg, self.id, t)
