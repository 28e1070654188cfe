"""The shared roadmap the agents read and write: seed 004's only communication channel.

WMA-RRT (§3.1): the global copy of each branch's edge weights ``w_g`` (one array: edge ids
are global, ``branch_of_edge`` says which ``Branch[k]`` an edge belongs to), ``Sync[k]``
(agents active in branch k) and ``Weight[k]`` (the first edge's weight, or the flags
COMPLETE = 10000 and HALF = ½). Agents keep their *dedicated* copies themselves.

Besides the paper's arrays the board keeps ``rem_sub[e]`` — how many edges at or below edge
e were never traversed — and ``busy[e]`` — how many agents are beneath edge e (Sync, per
sub-branch), which only the improved planner reads (the baseline ignores both), and
the goal anchor/leg: the node where the finder stood when it flagged the goal and the straight
leg from there to the goal, which followers need once the ½ edges have led them to the anchor.

One agent's step is one critical section (the simulation runs agents one at a time in a
seeded order), which is the paper's per-edge locking with the races of Fig. 4 excluded.
"""

from __future__ import annotations

import numpy as np

from swarmex.planning.roadmap import Roadmap

COMPLETE = 10000.0
HALF = 0.5


class WMABoard:
    def __init__(self, roadmap: Roadmap, n_agents: int) -> None:
        assert (roadmap.parent is not None and roadmap.branch is not None
                and roadmap.first_edge is not None)
        self.rm = roadmap
        self.n = n_agents
        e_count = roadmap.n_edges
        self.w_g = np.zeros(e_count)
        self.traversals = np.zeros(e_count, dtype=np.int64)
        self.sync = np.zeros(n_agents, dtype=np.int64)
        self.weight = np.zeros(n_agents)
        self.first_edge = roadmap.first_edge
        child = roadmap.edges[:, 1]
        self.branch_of_edge = roadmap.branch[child]
        # edge of node v is v - 1; its parent edge is parent[v] - 1 (-1 at the Main Root)
        self.up_edge = np.where(roadmap.parent[child] > 0, roadmap.parent[child] - 1, -1)
        self.children: list[list[int]] = [[] for _ in range(roadmap.n_nodes)]
        for e, (u, _) in enumerate(roadmap.edges.tolist()):
            self.children[u].append(e)
        size = np.ones(e_count, dtype=np.int64)
        for e in range(e_count - 1, -1, -1):  # children have larger ids than their parents
            if self.up_edge[e] >= 0:
                size[self.up_edge[e]] += size[e]
        self.subtree_size = size
        self.rem_sub = size.copy()
        self.busy = np.zeros(e_count, dtype=np.int64)  # agents currently beneath each edge
        self.completed_at = np.full(n_agents, -1, dtype=np.int64)
        self.anchor: int | None = None
        self.leg: list[np.ndarray] = []
        self.flag_branch = -1
        self.found_step = -1
        self.found_by = -1

    # --- the paper's operations -----------------------------------------------------------
    def enter(self, k: int) -> None:
        self.sync[k] += 1

    def exit(self, k: int, t: int) -> None:
        """Leave branch k; the last agent out marks it COMPLETE (Sync makes that safe)."""
        self.sync[k] -= 1
        if self.sync[k] == 0 and self.weight[k] != HALF:
            self.weight[k] = COMPLETE
            self.completed_at[k] = t

    def traverse(self, e: int, bump_global: bool = True, down: bool = True) -> None:
        self.traversals[e] += 1
        self.busy[e] += 1 if down else -1
        if not bump_global or self.w_g[e] == HALF:
            return  # ½ edges are a message: nobody overwrites them
        if self.w_g[e] == 0:
            f = e
            while f >= 0:
                self.rem_sub[f] -= 1
                f = self.up_edge[f]
        self.w_g[e] += 1
        k = self.branch_of_edge[e]
        if e == self.first_edge[k] and self.weight[k] not in (COMPLETE, HALF):
            self.weight[k] = self.w_g[e]

    def flag_goal(self, k: int, path_edges: np.ndarray, anchor: int, leg: list[np.ndarray],
                  agent: int, t: int) -> None:
        """§3.2: the finder's weight-1 edges become ½ (its own path M → anchor) and so does
        Weight[k]; the anchor and the final straight leg are left beside them."""
        self.w_g[path_edges] = HALF
        self.weight[k] = HALF
        self.flag_branch = k
        self.anchor = anchor
        self.leg = leg
        self.found_step = t
        self.found_by = agent

    def flagged(self) -> bool:
        return bool(np.any(self.weight == HALF))

    def all_complete(self) -> bool:
        return bool(np.all(self.weight == COMPLETE))


class PRMBoard:
    """Edge weights of the multiple-query roadmap plus the finder's trail (its ½ marks).

    On a graph with cycles "the weight-1 edges" do not form a path, so the finder marks the
    loop-erased version of its own walk (entry node → anchor) with a direction per node;
    walkers that step onto it follow it to the anchor.
    """

    def __init__(self, roadmap: Roadmap) -> None:
        self.rm = roadmap
        # plain lists: walkers read single weights thousands of times per run
        self.w_g: list[float] = [0.0] * roadmap.n_edges
        self.traversals: list[int] = [0] * roadmap.n_edges
        self.trail_next: dict[int, tuple[int, int]] = {}
        self.anchor: int | None = None
        self.leg: list[np.ndarray] = []
        self.found_step = -1
        self.found_by = -1

    def traverse(self, e: int) -> None:
        self.traversals[e] += 1
        self.w_g[e] += 1

    def flag_goal(self, walk: list[tuple[int, int]], anchor: int, leg: list[np.ndarray],
                  agent: int, t: int) -> None:
        """``walk``: the finder's (node, edge-used-to-reach-it) sequence from its entry node."""
        path: list[tuple[int, int]] = []
        where: dict[int, int] = {}
        for node, edge in walk:  # loop erasure: cut back to the first visit of a node
            if node in where:
                del path[where[node] + 1 :]
                where = {nd: i for i, (nd, _) in enumerate(path)}
            else:
                where[node] = len(path)
                path.append((node, edge))
        for (u, _), (v, e) in zip(path[:-1], path[1:], strict=True):
            self.trail_next[u] = (v, e)
            self.w_g[e] = HALF
        self.anchor = anchor
        self.leg = leg
        self.found_step = t
        self.found_by = agent
