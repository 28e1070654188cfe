"""What one traversal agent knows (Algorithm 1's KM, UN, O and loc(a′)).

* ``status[v]``: 0 not known done, -1 known obstacle, ``k > 0`` done (or conditionally
  accomplished: job started, C07) by agent ``k``; :data:`DONE_BY_UNKNOWN` when a done-nodes
  list said it is done without saying by whom.
* ``reserved[v]``: the agent id that announced ``v`` as its next node (C05), 0 if none.
* ``loc[k]``: the last vertex agent ``k`` physically reached (-1 until heard from).
* ``known``: the graph minus known obstacles, with its distance-field cache.
* ``orphaned``: vertices reverted to not done because the rival doing their job left.
* ``plan``: the newest end-game team plan this agent made or heard (``plan`` messages of
  madgta-s, :class:`TeamPlan`), or None.

KM (Algorithm 1) is ``status != 0`` plus vertices reserved by *other* agents. Beliefs are
updated only by the agent's own sensing and by messages; policies read nothing else.

A simulated team under a perfect broadcast keeps its beliefs as rows of one
:class:`BeliefTable`, so a broadcast updates every receiver in one compiled call
(:func:`deliver`); each belief still only ever sees its own rows.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.planning.fieldcache import KnownGraph
from swarmex.worlds.nodegraph import NodeGraph

DONE_BY_UNKNOWN = np.int32(2**30)


class TeamPlan(NamedTuple):
    """An end-game team plan as it travels in a ``plan`` message (madgta-s): when it was
    made, and each agent's route, row ``a`` of ``routes`` being agent ``a``'s first
    ``lens[a]`` vertices to do, in order (row 0 unused)."""

    t: float
    routes: NDArray[np.int64]
    lens: NDArray[np.int64]


def route_cells(lens: NDArray[np.int64], width: int) -> NDArray[np.bool_]:
    """The cells of a routes array (:class:`TeamPlan`'s ``routes``, ``width`` columns) that
    hold a route's vertices: row ``a``'s first ``lens[a]``. Read in C order they are the
    routes concatenated."""
    return np.arange(width)[None, :] < np.asarray(lens)[:, None]


class BeliefTable:
    """The arrays of a whole team's beliefs, one row per agent id (row 0 unused).

    Each :class:`TraversalBelief` built with ``table=`` works on its own rows (views), so a
    perfect broadcast can update every receiver in one compiled call (:func:`deliver`)
    instead of one Python call per receiver.
    """

    def __init__(self, n_agents: int, n_nodes: int) -> None:
        rows = n_agents + 1
        self.status = np.zeros((rows, n_nodes), dtype=np.int32)
        self.reserved = np.zeros((rows, n_nodes), dtype=np.int32)
        self.loc = np.full((rows, rows), -1, dtype=np.int64)
        self.reservation = np.full((rows, rows), -1, dtype=np.int64)
        self.next_loc = np.full((rows, rows), -1, dtype=np.int64)
        self.free_at = np.zeros((rows, rows), dtype=np.float64)
        self.revived = np.zeros(rows, dtype=np.int64)  # jobs undone, per belief


class TraversalBelief:
    def __init__(
        self,
        me: int,
        n_agents: int,
        known: KnownGraph,
        time_per_unit: np.ndarray,
        job_time: np.ndarray,
        table: BeliefTable | None = None,
    ) -> None:
        n = known.graph.n_nodes
        self.me = me  # 1-based id, as in the thesis
        self.known = known
        if table is None:
            self.status = np.zeros(n, dtype=np.int32)
            self.reserved = np.zeros(n, dtype=np.int32)
            self.loc = np.full(n_agents + 1, -1, dtype=np.int64)  # index by id; 0 unused
            self.reservation = np.full(n_agents + 1, -1, dtype=np.int64)  # vertex, by id
            # when each agent will next be free, and where (C05/C07 timing): madgta+ uses it
            self.next_loc = np.full(n_agents + 1, -1, dtype=np.int64)
            self.free_at = np.zeros(n_agents + 1, dtype=np.float64)
            self.revived = np.zeros(1, dtype=np.int64)
        else:  # this agent's rows of the team table (views: the table sees every write)
            self.status = table.status[me]
            self.reserved = table.reserved[me]
            self.loc = table.loc[me]
            self.reservation = table.reservation[me]
            self.next_loc = table.next_loc[me]
            self.free_at = table.free_at[me]
            self.revived = table.revived[me : me + 1]
        # how many times a done vertex of this belief went back to not done (mark_not_done,
        # deliver): the policy's cached "nothing left here" flags are stale after one
        self._flags: dict[str, tuple[np.ndarray, int]] = {}
        self.now = 0.0
        self.intent = -1  # the vertex this agent announced it will do the job at (C05)
        # vertices reverted to not done because the rival doing their job left the mission:
        # a done-nodes list may not mark them done again, only a C07 (agent.merge_done_list)
        self.orphaned: set[int] = set()
        self.time_per_unit = time_per_unit  # seconds per length unit, by id
        self.job_time = job_time  # seconds per job, by id
        self.plan: TeamPlan | None = None  # the newest team plan made or heard (madgta-s)

    @property
    def graph(self) -> NodeGraph:
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

    def scan_flags(self, name: str, size: int) -> np.ndarray:
        """Per-region flags a policy keeps in this belief (uint8, ``size`` of them): set
        for a region that has nothing left to scan. They can only become stale when a done
        vertex returns to not done, so they are cleared then."""
        hit = self._flags.get(name)
        revived = int(self.revived[0])
        if hit is None or hit[0].size != size or hit[1] != revived:
            hit = self._flags[name] = (np.zeros(size, dtype=np.uint8), revived)
        return hit[0]

    def rivals(self) -> np.ndarray:
        """Ids of the other agents whose position is known."""
        ids = np.nonzero(self.loc >= 0)[0]
        return ids[ids != self.me]

    # ---- updates (sensing and messages)
    def hear_plan(self, plan: TeamPlan) -> None:
        """Keep ``plan`` unless the one held was made later (a late, delayed plan is stale).
        Receivers share the plan's arrays: nobody writes them."""
        if self.plan is None or plan.t >= self.plan.t:
            self.plan = plan

    def see_obstacles(self, vertices: Iterable[int]) -> None:
        vs = list(vertices)
        if vs:
            self.status[vs] = -1
            self.known.add_obstacles(vs)

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
            self.revived[0] += 1

    def announce_move(self, v: int) -> bool:
        """Record this agent's own C05 for ``v``; True when it intends to do ``v``'s job.

        The intent is kept apart from ``reserved`` because a later C05 from a rival for the
        same vertex (a rival passing through, or one that had not yet heard ours under loss
        or delay) overwrites the reservation there.
        """
        intends = not self.in_km(v)
        self.intent = v if intends else -1
        if intends:
            self.reserve(v, self.me)
        return intends

    def job_on_arrival(self, v: int) -> bool:
        """Whoever first reaches a vertex does its job (seed 000 §1.3).

        The agent does it unless it knows the vertex is done, or it is only passing through a
        vertex a rival announced. An agent that announced ``v`` itself does the job even if a
        rival's C05 for ``v`` came later: otherwise two agents racing for one vertex could each
        leave it to the other, and it would never be done.
        """
        if self.status[v] != 0:
            return False
        return self.intent == v or not self.in_km(v)

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


#: message kinds understood by :func:`deliver` (the simulator's C01/C07/C05 and "undone")
POS, JOB, NEXT, UNDONE = 1, 2, 3, 4


@kernel(cache=True, nogil=True)
def deliver(
    kind: int, sender: int, node: int, obstacles: NDArray[np.int64], eta: float,
    status: NDArray[np.int32], reserved: NDArray[np.int32], loc: NDArray[np.int64],
    reservation: NDArray[np.int64], next_loc: NDArray[np.int64], free_at: NDArray[np.float64],
    revived: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """Apply one message to every belief of a :class:`BeliefTable` except the sender's.

    Row for row the same updates, in the same order, as
    :func:`swarmex.missions.traversal.agent.apply_message` for a message without a done list
    (the agent core's rule for a received message): position (and
    release of the sender's reservation), job start (conditionally accomplished), next node
    (reservation) or job failure. Obstacles must already be in the shared known graph.
    """
    for r in range(1, status.shape[0]):
        if r == sender:
            continue
        st = status[r]
        rs = reserved[r]
        rv = reservation[r]
        for o in obstacles:
            st[o] = -1
        if kind == JOB:
            loc[r, sender] = node
            if st[node] >= 0:  # mark_done(node, sender)
                st[node] = sender
            holder = rs[node]
            if holder != 0:
                rs[node] = 0
                rv[holder] = -1
            next_loc[r, sender] = node
            free_at[r, sender] = eta
        elif kind == UNDONE:
            if st[node] > 0:  # mark_not_done(node)
                st[node] = 0
                revived[r] += 1
        elif kind != 0:  # POS or NEXT: both release the sender's reservation first
            if kind == POS:
                loc[r, sender] = node
            old = rv[sender]
            if old >= 0:
                if rs[old] == sender:
                    rs[old] = 0
                rv[sender] = -1
            if kind == NEXT:
                if st[node] == 0:  # reserve(node, sender)
                    rs[node] = sender
                    rv[sender] = node
                next_loc[r, sender] = node
                free_at[r, sender] = eta
