"""What one traversal agent knows (Algorithm 1's KM, UN, O and loc(a′)).

* ``status[v]``: 0 not known done, -1 known obstacle, ``k > 0`` done (or conditionally
  accomplished: job started, C07) by agent ``k``; :data:`DONE_BY_UNKNOWN` when a done-nodes
  list said it is done without saying by whom.
* ``reserved[v]``: the agent id that announced ``v`` as its next node (C05), 0 if none.
* ``loc[k]``: the last vertex agent ``k`` physically reached (-1 until heard from).
* ``known``: the graph minus known obstacles, with its distance-field cache.

KM (Algorithm 1) is ``status != 0`` plus vertices reserved by *other* agents. Beliefs are
updated only by the agent's own sensing and by messages; policies read nothing else.
"""

from __future__ import annotations

import numpy as np

from swarmex.planning.fieldcache import KnownGraph

DONE_BY_UNKNOWN = np.int32(2**30)


class TraversalBelief:
    def __init__(
        self,
        me: int,
        n_agents: int,
        known: KnownGraph,
        time_per_unit: np.ndarray,
        job_time: np.ndarray,
    ) -> None:
        n = known.graph.n_nodes
        self.me = me  # 1-based id, as in the thesis
        self.known = known
        self.status = np.zeros(n, dtype=np.int32)
        self.reserved = np.zeros(n, dtype=np.int32)
        self.loc = np.full(n_agents + 1, -1, dtype=np.int64)  # index by id; slot 0 unused
        self.reservation = np.full(n_agents + 1, -1, dtype=np.int64)  # vertex reserved, by id
        # when each agent will next be free, and where (from C05/C07 timing): madgta+ uses it
        self.next_loc = np.full(n_agents + 1, -1, dtype=np.int64)
        self.free_at = np.zeros(n_agents + 1, dtype=np.float64)
        self.now = 0.0
        self.time_per_unit = time_per_unit  # seconds per length unit, by id
        self.job_time = job_time  # seconds per job, by id

    @property
    def graph(self):
        return self.known.graph

    @property
    def here(self) -> int:
        return int(self.loc[self.me])

    def km_mask(self) -> np.ndarray:
        """Algorithm 1's KM as a boolean mask (done, obstacle, or claimed by a rival)."""
        return (self.status != 0) | ((self.reserved != 0) & (self.reserved != self.me))

    def km_at(self, vertices: np.ndarray) -> np.ndarray:
        r = self.reserved[vertices]
        return (self.status[vertices] != 0) | ((r != 0) & (r != self.me))

    def in_km(self, v: int) -> bool:
        return bool(self.status[v] != 0 or (self.reserved[v] not in (0, self.me)))

    def rivals(self) -> np.ndarray:
        """Ids of the other agents whose position is known."""
        ids = np.nonzero(self.loc >= 0)[0]
        return ids[ids != self.me]

    # ---- updates (sensing and messages)
    def see_obstacles(self, vertices) -> None:
        vertices = list(vertices)
        if vertices:
            self.status[vertices] = -1
            self.known.add_obstacles(vertices)

    def mark_done(self, v: int, by: int) -> None:
        if self.status[v] >= 0:
            self.status[v] = by
        holder = self.reserved[v]
        if holder != 0:
            self.reserved[v] = 0
            self.reservation[holder] = -1

    def mark_not_done(self, v: int) -> None:
        if self.status[v] > 0:
            self.status[v] = 0

    def reserve(self, v: int, by: int) -> None:
        self.release(by)
        if self.status[v] == 0:
            self.reserved[v] = by
            self.reservation[by] = v

    def release(self, by: int) -> None:
        old = self.reservation[by]
        if old >= 0:
            if self.reserved[old] == by:
                self.reserved[old] = 0
            self.reservation[by] = -1
