"""Distance fields that follow a growing set of known obstacles without being recomputed.

MADGTA needs, at every decision, the travel distance from every agent's node to every
candidate vertex, on the graph minus the obstacles known so far. Agents discover obstacles
one by one, so naive caching would throw every field away at every discovery.
:class:`KnownGraph` instead keeps a log of discoveries and brings a cached field up to date
only when it is asked for. Two regimes, chosen by the graph:

* **uniform edge lengths** (grids): fields are int32 hop counts, one row per cached source
  in one 2-D array, so kernels read many fields in one call. Hop counts have no rounding, so
  every route to a field gives the same integers and the cache policy cannot change a
  result. That frees three shortcuts:

  - a stale field is *repaired* (``_repair_hops``: only the vertices whose shortest paths
    ran through the new obstacles are re-derived) instead of recomputed; on a map whose
    walls are discovered cell by cell that turns about half of all field computations
    into small repairs;
  - the field of a vertex next to a cached source is *derived* from it on a lattice
    (``_shift_source_lattice``: every distance moves by exactly one), which is what an
    agent stepping to a neighbour needs, at about half the cost of a search;
  - :meth:`KnownGraph.prefetch` (the simulator calls it when an agent decides to move)
    snapshots the row and queues the job; queued jobs run together, in parallel on all
    cores, when the first of them is needed. A queued row starts from the obstacles known
    when it was queued and is repaired on use like any stale field.

* **other graphs**: float Dijkstra fields, checked by :func:`_still_exact` (a field is
  unchanged by blocking a set of vertices iff every vertex whose shortest path could run
  through them keeps another shortest-path predecessor) and recomputed when it fails. The
  check compares floats with a tolerance, so a kept field can differ from a fresh one in the
  last bits; this path therefore keeps its original LRU policy unchanged, so results stay
  reproducible run to run and release to release.
"""

from __future__ import annotations

from collections import OrderedDict

import numba as nb
import numpy as np

from swarmex.planning.distance import (
    BLOCKED,
    UNREACHED,
    _hop_jobs,
    _hop_jobs_serial,
    _repair_hops,
    distance_field,
    lattice_structure,
    step_length,
)
from swarmex.worlds.nodegraph import NodeGraph


@nb.njit(cache=True, nogil=True)
def _still_exact(indptr, indices, weights, blocked, field, new_obstacles):  # pragma: no cover
    for o in new_obstacles:
        do = field[o]
        if not np.isfinite(do):
            continue
        for k in range(indptr[o], indptr[o + 1]):
            u = indices[k]
            if blocked[u]:
                continue
            du = field[u]
            if abs(du - (do + weights[k])) > 1e-9 * (1.0 + du):
                continue
            ok = False
            for j in range(indptr[u], indptr[u + 1]):
                x = indices[j]
                if blocked[x]:
                    continue
                if abs(field[x] + weights[j] - du) <= 1e-9 * (1.0 + du):
                    ok = True
                    break
            if not ok:
                return False
    return True


@nb.njit(cache=True, nogil=True)
def _gather(hops, slot, vertices, step, out):  # pragma: no cover - compiled
    row = hops[slot]
    for i in range(vertices.shape[0]):
        h = row[vertices[i]]
        out[i] = np.inf if h < 0 else h * step


class KnownGraph:
    """A graph plus the obstacles someone knows about, with a cache of distance fields.

    ``blocked`` only ever gains vertices (obstacles are static), which is what makes the
    incremental updates sound. Counters: ``recomputed`` (fields computed: full searches plus
    ``shifted`` derivations), ``repaired`` (stale uniform fields fixed in place), ``reused``
    (served as they were).
    """

    def __init__(self, graph: NodeGraph, capacity: int = 64, prefetch: bool = False) -> None:
        self.graph = graph
        self.blocked = np.zeros(graph.n_nodes, dtype=bool)
        self._log: list[int] = []
        self.capacity = capacity
        self.recomputed = 0
        self.reused = 0
        self.repaired = 0
        self.shifted = 0
        self.uniform = bool(graph.uniform)
        # float fields (non-uniform graphs), keyed by source: (field, version)
        self._cache: OrderedDict[int, tuple[np.ndarray, int]] = OrderedDict()
        self._prefetch = prefetch and self.uniform
        if self.uniform:
            n = graph.n_nodes
            self.step = step_length(graph)
            self.hops = np.empty((0, n), dtype=np.int32)  # grows by doubling
            self._slot: OrderedDict[int, int] = OrderedDict()  # source -> row, LRU order
            self._slot_version: list[int] = []
            self._free: list[int] = []
            self._queued: dict[int, tuple[int, bool]] = {}  # row -> (source, shift) to run
            self._float: dict[int, np.ndarray] = {}  # row -> float field, until it changes
            # scratch for the kernels
            self._state = np.zeros(n, dtype=np.int8)
            self._touched = np.empty(n, dtype=np.int32)
            self._work = np.empty(2 * n + 2, dtype=np.int32)
            self._key = np.empty(n, dtype=np.int32)
            self._queues = np.empty((nb.config.NUMBA_NUM_THREADS, n), dtype=np.int32)
            self._repair_limit = max(1, n // 6)
            # what a fresh hop row starts as: UNREACHED, or BLOCKED for known obstacles
            self._template = np.full(n, UNREACHED, dtype=np.int32)
            width, mask = lattice_structure(graph)
            self._width = width
            self._nbmask = mask if mask is not None else np.zeros(1, dtype=np.uint8)

    @property
    def version(self) -> int:
        return len(self._log)

    def add_obstacles(self, vertices) -> bool:
        """Mark vertices as known obstacles; returns True if any was new."""
        new = False
        for v in vertices:
            v = int(v)
            if not self.blocked[v]:
                self.blocked[v] = True
                self._log.append(v)
                if self.uniform:
                    self._template[v] = BLOCKED
                new = True
        return new

    # ------------------------------------------------------------------ float fields
    def field(self, source: int) -> np.ndarray:
        """Distance from ``source`` to every vertex on the graph minus known obstacles.

        The returned array is shared with the cache: read it, never write it. On uniform
        graphs it is valid until the next call that changes the field (a new obstacle).
        """
        if self.uniform:
            slot = self.slot(source)
            fld = self._float.get(slot)
            if fld is None:
                row = self.hops[slot]
                fld = row * self.step
                fld[row < 0] = np.inf
                fld.flags.writeable = False
                self._float[slot] = fld
            return fld
        hit = self._cache.get(source)
        if hit is not None:
            fld, ver = hit
            if ver == self.version:
                self._cache.move_to_end(source)
                self.reused += 1
                return fld
            g = self.graph
            new = np.asarray(self._log[ver:], dtype=np.int64)
            if _still_exact(g.indptr, g.indices, g.weights, self.blocked, fld, new):
                fld[new] = np.inf
                fld[source] = 0.0
                self._cache[source] = (fld, self.version)
                self._cache.move_to_end(source)
                self.reused += 1
                return fld
        fld = distance_field(self.graph, source, self.blocked)
        self.recomputed += 1
        self._cache[source] = (fld, self.version)
        self._cache.move_to_end(source)
        while len(self._cache) > self.capacity:
            self._cache.popitem(last=False)
        return fld

    def distances(self, source: int, vertices: np.ndarray) -> np.ndarray:
        """``field(source)[vertices]`` without building the whole float field."""
        vertices = np.asarray(vertices, dtype=np.int64)
        if not self.uniform:
            return self.field(source)[vertices]
        out = np.empty(vertices.size, dtype=np.float64)
        slot = self.slot(source)  # first: it may grow (replace) self.hops
        _gather(self.hops, slot, vertices, self.step, out)
        return out

    # ------------------------------------------------------------------ hop rows (uniform)
    def slot(self, source: int) -> int:
        """Row of ``self.hops`` holding the up-to-date hop field of ``source``.

        Uniform graphs only. The row stays valid until a later ``slot``/``slots``/``field``
        call evicts it (at least ``capacity`` distinct sources later) or repairs it.
        """
        s = self._ensure(int(source))
        self._trim(1)
        return s

    def slots(self, sources: np.ndarray) -> np.ndarray:
        """Rows for several sources at once, all valid together (see :meth:`slot`)."""
        out = np.empty(len(sources), dtype=np.int64)
        for i, s in enumerate(sources.tolist()):
            out[i] = self._ensure(s)
        self._trim(len(out))
        return out

    def prefetch(self, source: int) -> None:
        """Queue the field of ``source`` (no-op unless enabled, or if it is cached already,
        fresh or stale: a repair is cheaper). Queued fields are computed together, in
        parallel, when the first of them is needed."""
        source = int(source)
        if self._prefetch and source not in self._slot:
            self._queue_job(source)
            self._trim(1)

    def _queue_job(self, source: int) -> int:
        """Give ``source`` a row holding what its job starts from, and queue the job."""
        near = self._near_row(source)
        slot = self._alloc()
        self._slot[source] = slot
        self._slot_version[slot] = self.version
        self._float.pop(slot, None)
        row = self.hops[slot]
        if near is not None:
            row[:] = self.hops[near]
            self.shifted += 1
        else:
            row[:] = self._template
        self._queued[slot] = (source, near is not None)
        self.recomputed += 1
        return slot

    def _run_queued(self) -> None:
        jobs = self._queued
        if not jobs:
            return
        slots = np.fromiter(jobs.keys(), dtype=np.int64, count=len(jobs))
        sources = np.array([src for src, _ in jobs.values()], dtype=np.int64)
        shift = np.array([sh for _, sh in jobs.values()], dtype=np.bool_)
        g = self.graph
        run = _hop_jobs if len(jobs) > 1 else _hop_jobs_serial  # a lone job: no thread start
        run(self._width, self._nbmask, g.indptr, g.indices, self.hops, slots, sources, shift,
            self._queues)
        jobs.clear()

    def _near_row(self, source: int) -> int | None:
        """Row of a cached, computed field whose source is a neighbour of ``source`` at
        distance one: ``source``'s field then follows by a shift (lattices only)."""
        if not self._width or self.blocked[source]:
            return None
        for other in self.graph.neighbors(source).tolist():
            slot = self._slot.get(other)
            if slot is None or self.blocked[other] or slot in self._queued:
                continue
            slot = self._ensure(other)  # repairs it if stale (usually it is fresh)
            if self.hops[slot, source] == 1:
                return slot
        return None

    def _ensure(self, source: int) -> int:
        slot = self._slot.get(source)
        if slot is None:
            self._queue_job(source)
            self._run_queued()  # with whatever else is queued, in parallel
            return self._slot[source]
        self._slot.move_to_end(source)
        if slot in self._queued:
            self._run_queued()
        ver = self.version
        old = self._slot_version[slot]
        if old == ver:
            self.reused += 1
            return slot
        self._slot_version[slot] = ver
        self._float.pop(slot, None)
        g = self.graph
        new = np.asarray(self._log[old:], dtype=np.int64)
        changed = _repair_hops(
            g.indptr, g.indices, self.blocked, self.hops[slot], source, new,
            self._state, self._touched, self._work, self._key, self._repair_limit,
        )
        if changed == 0:
            self.reused += 1
        elif changed > 0:
            self.repaired += 1
        else:  # too much changed: a fresh search is cheaper
            self.hops[slot] = self._template
            self._queued[slot] = (source, False)
            self.recomputed += 1
            self._run_queued()
        return slot

    def _alloc(self) -> int:
        if self._free:
            return self._free.pop()
        rows, n = self.hops.shape
        grown = np.empty((max(4, 2 * rows), n), dtype=np.int32)
        grown[:rows] = self.hops  # queued jobs name rows by index, so they survive this
        self.hops = grown  # float fields are copies, so they stay valid
        self._slot_version.extend([-1] * (grown.shape[0] - rows))
        self._free.extend(range(grown.shape[0] - 1, rows, -1))
        return rows

    def _trim(self, keep: int) -> None:
        """Evict least recently used fields beyond capacity, sparing the last ``keep``."""
        limit = max(self.capacity, keep)
        while len(self._slot) > limit:
            _, slot = self._slot.popitem(last=False)
            self._queued.pop(slot, None)
            self._float.pop(slot, None)
            self._free.append(slot)
