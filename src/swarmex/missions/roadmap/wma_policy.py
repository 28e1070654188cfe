"""A WMA-RRT agent (seed 004 §3.1–3.2): decides one move per step from the roadmap alone.

The agent knows only the shared board (:class:`~swarmex.missions.roadmap.blackboard.WMABoard`)
and its dedicated copy ``w_d`` of the branch it is in (zeroed on entry, bumped with every
traversal: weight 1 marks its own way back to the Main Root, 2 an edge it finished).

Edge choice at a node (how the paper's rule is resolved, spec ambiguities 7–10):

* At the Main Root the agent takes its branch's first edge (entering is a commitment).
* Elsewhere only edges it has not used since entering (``w_d == 0``) are candidates:
  a global weight 0 (unexplored) first; otherwise an edge of *odd* global weight — an odd
  count of traversals means an odd number of agents are still beneath it, i.e. another
  agent's unfinished frontier, which a helper joins (the minimum such weight); otherwise it
  returns along its dedicated weight-1 edge. With one agent this is exactly the paper's
  minimum-weight DFS (0 before the weight-1 way back); the paper's "use the dedicated copy
  when all incident weights are equal" is the special case where the return is forced,
  and the literal rule — descend into a subtree of weight 2 when the way back weighs 3 —
  would re-walk finished subtrees, the harm the paper itself warns of. Ties: uniform among
  equals, from the run's generator.
* Back at the Main Root with its first edge weighing 2 in its own copy, the agent leaves the
  branch (Sync − 1; the *last* one out marks it COMPLETE, since "when an agent returns to its
  origin" would wrongly close a branch another agent is still exploring), then helps the
  unfinished branch of least Weight (uniform among ties), not the one it just left unless that
  is all that remains — in which case it waits at the Main Root for it to complete.

Improved variant (``rule="takeover"``, planner ``wma-rrt-takeover``): two more counters on the
roadmap guide every choice — ``rem_sub[e]``, edges at or below e never traversed, and
``busy[e]``, agents beneath e. Candidates are child edges not yet used with ``rem_sub > 0``;
the one with the largest fair share ``rem_sub / (busy + 1)`` wins, so a helper walks straight
to the largest unexplored sub-branch nobody (or fewest) is working in, instead of trailing
the owner's frontier, and agents meeting at a fork split it. A free agent picks the branch of
largest share the same way, and waits at the Main Root when no branch has unexplored edges
left (the rest is agents walking home). Returning is the same dedicated-copy rule.

Fair-share variant (``rule="fairshare"``, planner ``wma-rrt-fairshare``, issue 17 item 4):
the takeover rule spends its first steps on the *largest* sub-branch even when an edge nobody
has walked is one step away, which is why it finds goals later than the paper (a goal is most
often seen from the frontier the owner is pushing). Fair-share keeps the paper's first
preference — an unexplored child edge (global weight 0), uniform among ties — and uses the
fair share ``rem_sub / (busy + 1)`` only where the paper would trail another agent's frontier
(no unexplored child): then the child with the largest share among those with
``rem_sub > 0``, else the way back. A free agent picks its branch by largest share, as
takeover does. Over 30 seeds of the study's rows it needs 0.70–0.74x WMA-RRT's coverage
steps and 0.52–0.88x its first-sighting step (docs/roadmap.md has the paired intervals).

Goal search (§3.2): at every node the agent checks Weight for ½. Then it stops exploring and
follows: at the anchor it takes the straight leg to the goal; if an edge of weight ½ leads away
from the Main Root it takes it; otherwise it climbs its own return path (weight 1 in its
dedicated copy). That is both of the paper's cases — same branch: up until the ½ path is met;
other branch: up to the Main Root, whose only ½ edge is the flagged branch's first edge.

Choices open to another policy (:meth:`WMAAgent.choice`, used by the PettingZoo environment):
inside a branch, any child edge the agent has not used since it entered it, and its way
back once no child edge is unexplored (global weight 0): whatever order a policy explores
in, a branch is COMPLETE only when every edge in it was travelled. Free at the Main Root:
the first edge of any branch that is not COMPLETE, or :data:`WAIT`. The seed rule above
picks one of them (:meth:`WMAAgent.seed_choice`), and :meth:`WMAAgent.carry_out` walks any.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmex.missions.roadmap.blackboard import COMPLETE, HALF, WMABoard

#: The option of waiting at the Main Root for a step (a free agent's "help or wait").
WAIT = -1


@dataclass(frozen=True)
class Choice:
    """A real choice an agent faces this step: ``kind`` and its ``options`` (edge ids).

    ``kind`` is "edge" (a WMA-RRT agent inside a branch), "branch" (a free WMA-RRT agent at
    the Main Root: a branch's first edge, or :data:`WAIT`) or "walk" (a PRM walker).
    """

    kind: str
    options: tuple[int, ...]


@dataclass
class Move:
    """One step: go to ``to``; ``edge`` is the roadmap edge used (-1 for a straight leg)."""

    to: np.ndarray
    edge: int = -1
    node: int = -1  # node reached (-1: not a node, e.g. on a goal leg)


class _GoalLegs:
    """The straight legs from the goal's anchor node to the goal, walked one a step: the
    same for a WMA-RRT agent and a PRM walker once they reach the anchor, so written once."""

    legs: list[np.ndarray]
    state: str

    def _start_legs(self, leg: list[np.ndarray]) -> Move:
        """At the anchor: take the board's ``leg`` and make its first step."""
        self.legs = list(leg)
        self.state = "leg"
        return self._next_leg()

    def _next_leg(self) -> Move:
        """The next leg's step; after the last one the agent is at the goal."""
        to = self.legs.pop(0)
        if not self.legs:
            self.state = "at-goal"
        return Move(to, -1, -1)


#: Edge-choice rules by planner name: the paper's, and the two that use the board's counters.
RULES = {"wma-rrt": "paper", "wma-rrt-takeover": "takeover", "wma-rrt-fairshare": "fairshare"}


class WMAAgent(_GoalLegs):
    def __init__(self, ident: int, start: np.ndarray, board: WMABoard, rule: str = "paper"):
        if rule not in RULES.values():
            raise ValueError(f"unknown WMA-RRT rule {rule!r}; choose one of "
                             f"{', '.join(RULES.values())}")
        self.id = ident
        self.xy = np.asarray(start, dtype=np.float64)
        self.board = board
        self.rule = rule
        self.branch = ident
        self.node = -1  # -1 until the entry leg reaches the Main Root
        self.w_d = np.zeros(board.rm.n_edges)
        self.state = "entry"  # entry | explore | free | wait | follow | leg | done | at-goal
        self.left = -1
        self.legs: list[np.ndarray] = []
        self.branches_entered = 1
        board.enter(ident)

    # --- helpers ----------------------------------------------------------------------------
    def _enter(self, k: int) -> None:
        self.board.enter(k)
        self.branch = k
        self.w_d[:] = 0.0  # the dedicated copy: the branch's roadmap with weights zeroed
        self.branches_entered += 1
        self.state = "explore"

    def _edge_move(self, e: int, bump_global: bool = True) -> Move:
        b = self.board
        u, v = b.rm.edges[e]
        to = int(v) if u == self.node else int(u)
        self.w_d[e] += 1
        b.traverse(e, bump_global, down=u == self.node)
        return Move(b.rm.pos[to], e, to)

    def _pick_branch(self, rng: np.random.Generator) -> int:
        b = self.board
        open_ = np.flatnonzero(b.weight != COMPLETE)
        if self.rule != "paper":
            fe = b.first_edge[open_]
            share = b.rem_sub[fe] / (b.busy[fe] + 1.0)
            if not len(open_) or share.max() <= 0:
                return -1
            best = open_[share == share.max()]
        else:
            if len(open_) > 1:
                open_ = open_[open_ != self.left]
            if not len(open_) or (len(open_) == 1 and open_[0] == self.left):
                return -1
            w = b.weight[open_]
            best = open_[w == w.min()]
        return int(best[rng.integers(len(best))]) if len(best) > 1 else int(best[0])

    def _choose_edge(self, rng: np.random.Generator) -> int:
        b = self.board
        if self.node == 0:
            return int(b.first_edge[self.branch])
        kids = [e for e in b.children[self.node] if self.w_d[e] == 0]
        if self.rule != "takeover":
            zero = [e for e in kids if b.w_g[e] == 0]
            if zero:
                return zero[rng.integers(len(zero))] if len(zero) > 1 else zero[0]
        if self.rule != "paper":
            cand = [e for e in kids if b.rem_sub[e] > 0]
            if cand:
                share = np.array([b.rem_sub[e] / (b.busy[e] + 1.0) for e in cand])
                best = [c for c, r in zip(cand, share, strict=True) if r == share.max()]
                return best[rng.integers(len(best))] if len(best) > 1 else best[0]
        else:
            odd = [e for e in kids if int(b.w_g[e]) % 2 == 1]
            if odd:
                w = np.array([b.w_g[e] for e in odd])
                best = [e for e, x in zip(odd, w, strict=True) if x == w.min()]
                return best[rng.integers(len(best))] if len(best) > 1 else best[0]
        return self.node - 1  # the way back: weight 1 in the dedicated copy

    # --- the choice, for a policy other than the seed's ----------------------------------
    def choice(self) -> Choice | None:
        """This step's choice, or None when the step is forced (one option, or none)."""
        b = self.board
        if self.state not in ("explore", "free", "wait") or b.anchor is not None:
            return None
        if self.state in ("free", "wait"):
            open_ = np.flatnonzero(b.weight != COMPLETE)
            if not len(open_):
                return None
            return Choice("branch", (*(int(e) for e in b.first_edge[open_]), WAIT))
        if self.node <= 0:
            return None  # at the Main Root inside a branch: its first edge, a commitment
        options = [int(e) for e in b.children[self.node] if self.w_d[e] == 0]
        if not any(b.w_g[e] == 0 for e in options):
            options.append(self.node - 1)  # the way back, once no child edge is unexplored
        return Choice("edge", tuple(options)) if len(options) > 1 else None

    def seed_choice(self, choice: Choice, rng: np.random.Generator) -> int:
        """The option the seed rule (or this agent's variant) takes; draws from ``rng``."""
        if choice.kind == "edge":
            return int(self._choose_edge(rng))
        k = self._pick_branch(rng)
        return WAIT if k < 0 else int(self.board.first_edge[k])

    def carry_out(self, choice: Choice, option: int) -> Move | None:
        """Take ``option`` (one of ``choice.options``): its move, or None to wait."""
        if option not in choice.options:
            raise ValueError(f"option {option} is not one of {choice.options}")
        if choice.kind == "branch":
            if option == WAIT:
                self.state = "wait"
                return None
            self._enter(int(self.board.branch_of_edge[option]))
        return self._edge_move(option)

    # --- one step (a critical section) ----------------------------------------------------
    def decide(self, t: int, rng: np.random.Generator) -> Move | None:
        b = self.board
        if self.state in ("done", "at-goal"):
            return None
        if self.state == "entry":
            self.node = 0
            self.state = "explore"
            return Move(b.rm.pos[0], -1, 0)
        if self.state == "leg":
            return self._next_leg()
        if b.anchor is not None:
            return self._follow()
        if self.state in ("free", "wait"):
            k = self._pick_branch(rng)
            if k < 0:
                self.state = "done" if b.all_complete() else "wait"
                return None
            self._enter(k)
        return self._edge_move(self._choose_edge(rng))

    def _follow(self) -> Move | None:
        b = self.board
        self.state = "follow"
        if self.node == b.anchor:
            return self._start_legs(b.leg)
        if self.node == 0:
            return self._edge_move(int(b.first_edge[b.flag_branch]), bump_global=False)
        for e in b.children[self.node]:
            if b.w_g[e] == HALF:
                return self._edge_move(e, bump_global=False)
        return self._edge_move(self.node - 1, bump_global=False)

    def arrive(self, move: Move, t: int) -> None:
        self.xy = np.asarray(move.to, dtype=np.float64)
        if move.node >= 0:
            self.node = move.node
        b = self.board
        if (self.state == "explore" and self.node == 0 and move.edge >= 0
                and self.w_d[b.first_edge[self.branch]] >= 2):
            # back at the origin over its first edge: the branch is done for this agent
            b.exit(self.branch, t)
            self.left = self.branch
            self.state = "free"

    def found_goal(self, p: np.ndarray, goal: np.ndarray, t: int) -> None:
        """Called after the step on which this agent's sensor first saw the goal from p."""
        b = self.board
        if b.anchor is not None:
            return
        path = np.flatnonzero(self.w_d == 1)  # its own way back: the path M → here
        leg = [np.asarray(p, dtype=np.float64), np.asarray(goal, dtype=np.float64)]
        if np.allclose(leg[0], self.xy):
            leg = leg[1:]
        b.flag_goal(self.branch, path, self.node, leg, self.id, t)
