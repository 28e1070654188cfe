"""What one exploring robot knows: its map, its scans archive, and what neighbours said.

The thesis's shared structures (§3.3.1) are the *map* (occupancy grid), the *current plan*
and the *scans archive*; this module holds the first and the last plus the neighbours' goals
and positions heard in ``GOAL`` and heartbeat messages. The robot's own plan lives with the
policy (:mod:`swarmex.missions.exploration.robot`). Nothing here ever sees the true world.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field

from swarmex.missions.exploration.messages import ScanRecord
from swarmex.sensing.occupancy import OccupancyGrid

Cell = tuple[int, int]


HELD, ADDED, ADDED_GAP = 0, 1, 2  # what ScanArchive.admit did


class ScanArchive:
    """Every scan a robot knows (own and received), by key ``(origin, seq)``.

    What the archive holds is its sorted seqs per origin; the records themselves are looked
    up in :attr:`scans`, a dict of its own or — in a simulated team, :meth:`share` — one
    dict for the whole team. A key names one scan whoever holds it, so the team's dict maps
    it to the same record every archive would: n robots that all hear every scan keep one
    entry per scan rather than n (a 100-robot run's archives held 7 M entries), and adding
    a scan in seq order is a list append.
    """

    def __init__(self) -> None:
        self.scans: dict[tuple[int, int], ScanRecord] = {}
        self._seqs: dict[int, list[int]] = {}  # origin -> sorted seqs held
        self._n = 0  # keys held
        self._shared = False

    def share(self, store: dict[tuple[int, int], ScanRecord]) -> None:
        """Look records up in ``store``, a team's dict (before anything was added)."""
        if self._n:
            raise ValueError("an archive shares a store before it holds anything")
        self.scans = store
        self._shared = True

    def __len__(self) -> int:
        return self._n

    def __contains__(self, key: tuple[int, int]) -> bool:
        seqs = self._seqs.get(key[0])
        if not seqs:
            return False
        i = bisect.bisect_left(seqs, key[1])
        return i < len(seqs) and seqs[i] == key[1]

    def add(self, rec: ScanRecord) -> bool:
        """Archive ``rec``; False if its key was held."""
        return self.admit(rec) != HELD

    def admit(self, rec: ScanRecord) -> int:
        """:meth:`add`, telling the caller :meth:`has_gap` of the scan's origin too:
        ``HELD`` (nothing added), ``ADDED``, or ``ADDED_GAP`` (added, and some seq of that
        origin below its highest is missing). A team of n adds every scan n times, and scans
        mostly come in seq order: appended without a search, the gap read off the list."""
        seq = rec.seq
        seqs = self._seqs.get(rec.origin)
        if seqs is None:
            self._seqs[rec.origin] = [seq]
        elif seqs[-1] < seq:
            seqs.append(seq)
        else:
            i = bisect.bisect_left(seqs, seq)
            if i < len(seqs) and seqs[i] == seq:
                return HELD
            seqs.insert(i, seq)
        self._n += 1
        if self._shared:
            self.scans.setdefault(rec.key, rec)
        else:
            self.scans[rec.key] = rec
        if seqs is None:
            return ADDED if seq == 0 else ADDED_GAP
        return ADDED if len(seqs) == seqs[-1] + 1 else ADDED_GAP

    def has_gap(self, origin: int) -> bool:
        """True if some seq of ``origin`` below the highest one held is missing (an
        origin numbers its scans 0, 1, 2, …)."""
        seqs = self._seqs.get(origin)
        if not seqs:
            return False
        return len(seqs) != seqs[-1] + 1

    def summary(self) -> tuple[tuple[int, int, int], ...]:
        """Runs ``(origin, first, last + 1)`` of consecutive seqs held: NEED_MAP's content.

        An origin whose seqs have no hole (the usual case) is one run, found from the ends of
        its sorted list without walking it: a summary costs O(origins + holes), not
        O(archive), which matters when every new neighbour in a large team asks for one.
        """
        runs: list[tuple[int, int, int]] = []
        for origin in sorted(self._seqs):
            seqs = self._seqs[origin]
            if seqs[-1] - seqs[0] + 1 == len(seqs):  # sorted and distinct: no hole
                runs.append((origin, seqs[0], seqs[-1] + 1))
                continue
            start = prev = seqs[0]
            for s in seqs[1:]:
                if s != prev + 1:
                    runs.append((origin, start, prev + 1))
                    start = s
                prev = s
            runs.append((origin, start, prev + 1))
        return tuple(runs)

    def missing_for(self, have: tuple[tuple[int, int, int], ...]) -> list[ScanRecord]:
        """The scans this archive holds that a peer with summary ``have`` lacks, in key order.

        ``have`` is normally a :meth:`summary`: per origin, sorted runs that do not overlap.
        Then each origin's sorted seqs are cut at the runs' ends by bisection, so the cost is
        O(runs · log + answer) rather than a pass over the whole archive per request. Any
        other ``have`` (overlapping runs, from a foreign peer) takes the seq-by-seq rule.
        """
        runs: dict[int, list[tuple[int, int]]] = {}
        for origin, lo, hi in have:
            runs.setdefault(origin, []).append((lo, hi))
        for spans in runs.values():
            spans.sort()
        if not all(a[1] <= b[0] for spans in runs.values()
                   for a, b in zip(spans, spans[1:], strict=False)):
            return self._missing_slow(runs)
        scans = self.scans
        out: list[ScanRecord] = []
        for origin in sorted(self._seqs):
            seqs = self._seqs[origin]
            pos = 0
            for lo, hi in runs.get(origin, ()):
                a = bisect.bisect_left(seqs, lo, pos)
                out.extend(scans[(origin, s)] for s in seqs[pos:a])
                pos = max(pos, bisect.bisect_left(seqs, hi, a))
            out.extend(scans[(origin, s)] for s in seqs[pos:])
        return out

    def _missing_slow(self, runs: dict[int, list[tuple[int, int]]]) -> list[ScanRecord]:
        """:meth:`missing_for` seq by seq: a seq is held if the last run starting at or below
        it contains it."""
        out = []
        for origin in sorted(self._seqs):
            r = runs.get(origin)
            for seq in self._seqs[origin]:
                if r:
                    i = bisect.bisect_right(r, (seq, float("inf"))) - 1
                    if i >= 0 and r[i][0] <= seq < r[i][1]:
                        continue
                out.append(self.scans[(origin, seq)])
        return out


@dataclass
class Heard:
    """The latest word from one neighbour."""

    pos: Cell
    t: int
    goal: Cell | None = None
    priority: float = float("inf")
    goal_t: int = -(10**9)


@dataclass
class ExplorationBelief:
    shape: tuple[int, int]
    pos: Cell
    grid: OccupancyGrid = field(init=False)
    archive: ScanArchive = field(default_factory=ScanArchive)
    heard: dict[int, Heard] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.grid = OccupancyGrid(self.shape)

    def integrate(self, rec: ScanRecord) -> bool:
        """Archive a scan and apply it to the map, once per key."""
        if not self.archive.add(rec):
            return False
        self.grid.apply(rec.local)
        return True

    def hear_position(self, rid: int, pos: Cell, t: int) -> None:
        h = self.heard.get(rid)
        if h is None:
            self.heard[rid] = Heard(pos, t)
        else:
            h.pos, h.t = pos, t

    def hear_goal(self, rid: int, goal: Cell | None, priority: float, t: int) -> None:
        h = self.heard.setdefault(rid, Heard((-1, -1), -(10**9)))
        h.goal, h.priority, h.goal_t = goal, priority, t

    def hear_all(
        self, rid: int, pos: Cell, goal: Cell | None, priority: float, t: int
    ) -> None:
        """:meth:`hear_position` then :meth:`hear_goal` (a ``GOAL`` message), in one lookup."""
        h = self.heard.get(rid)
        if h is None:
            h = self.heard[rid] = Heard(pos, t)
        else:
            h.pos, h.t = pos, t
        h.goal, h.priority, h.goal_t = goal, priority, t

    def forget(self, rid: int) -> None:
        self.heard.pop(rid, None)

    def team_goals(self, t: int, ttl: int) -> dict[int, Cell]:
        return {
            r: h.goal for r, h in self.heard.items() if h.goal is not None and t - h.goal_t <= ttl
        }

    def team_positions(self, t: int, ttl: int) -> dict[int, Cell]:
        return {r: h.pos for r, h in self.heard.items() if h.pos[0] >= 0 and t - h.t <= ttl}
