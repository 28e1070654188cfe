"""Distance fields that follow a growing set of known obstacles without being recomputed.

MADGTA needs, at every decision, the travel distance from every agent's node to every
candidate vertex, on the graph minus the obstacles known so far. Agents discover obstacles
one by one, so naive caching would throw every field away at every discovery.
:class:`KnownGraph` instead keeps a log of discoveries and brings a cached field up to date
only when it is asked for. Two regimes, chosen by the graph:

* **uniform edge lengths** (grids): fields are stored as int32 hop counts in one 2-D array
  (a row per cached source, so kernels can read many fields in one call). A stale field is
  *repaired* (:func:`~swarmex.planning.distance.repair_hops`: only the vertices whose
  shortest paths ran through the new obstacles are re-derived), which is exact — hop counts
  have no rounding — so a repaired field equals a fresh one bit for bit and the cache policy
  cannot change any result. On a map whose walls are discovered cell by cell this turns
  most invalidations (about half of all field computations before) into small repairs.
* **other graphs**: float Dijkstra fields, checked by :func:`_still_exact` (a field is
  unchanged by blocking a set of vertices iff every vertex whose shortest path could run
  through them keeps another shortest-path predecessor) and recomputed when it fails. The
  check compares floats with a tolerance, so a kept field can differ from a fresh one in the
  last bits; this path therefore keeps its original LRU policy unchanged, so results stay
  reproducible run to run and release to release.

With ``prefetch=True`` (uniform graphs of some size) :meth:`KnownGraph.prefetch` starts the
hop field of a vertex on a background thread (numba kernels release the GIL, so it runs on
the second core): the traversal simulator calls it when an agent *decides* to move, and the
field is ready by the time anyone asks for it. The row is initialised from the obstacles
known at that moment and repaired on first use like any stale field, so the answer does not
depend on thread timing.
"""

from __future__ import annotations

import queue
import threading
from collections import OrderedDict
from collections.abc import Callable

import numba as nb
import numpy as np

from swarmex.planning.distance import (
    BLOCKED,
    UNREACHED,
    _bfs_hops_csr,
    _bfs_hops_lattice,
    _repair_hops,
    _shift_source_lattice,
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


#: below this many vertices a search is cheaper than handing it to a thread
PREFETCH_MIN_NODES = 4096


class _Job:
    """A field computation that the worker thread or, if it gets there first, the thread
    that needs the result runs (so a busy machine never leaves the caller waiting for a
    worker that has not been scheduled). ``run`` takes a dict of scratch queues by size."""

    __slots__ = ("lock", "run", "done", "error")

    def __init__(self, run: Callable[[dict], None]) -> None:
        self.lock = threading.Lock()
        self.run = run
        self.done = False
        self.error: BaseException | None = None

    def claim_and_run(self, scratch: dict) -> bool:
        """Run the job unless someone else has it; False if someone else does."""
        if not self.lock.acquire(blocking=False):
            return False
        try:
            if not self.done:
                self.run(scratch)
        except BaseException as exc:  # handed to whoever waits for the result
            self.error = exc
        finally:
            self.done = True
            self.lock.release()
        return True

    def wait(self, scratch: dict) -> None:
        if not self.done and not self.claim_and_run(scratch):
            with self.lock:  # the worker is on it
                pass
        if self.error is not None:
            raise self.error


_JOBS: queue.SimpleQueue[_Job] = queue.SimpleQueue()
_WORKER: threading.Thread | None = None
_WORKER_LOCK = threading.Lock()


def _worker_loop() -> None:
    scratch: dict = {}
    while True:
        _JOBS.get().claim_and_run(scratch)


def _submit(job: _Job) -> _Job:
    """Queue a job for the one shared worker thread (a daemon: nothing to shut down)."""
    global _WORKER
    if _WORKER is None:
        with _WORKER_LOCK:
            if _WORKER is None:
                _WORKER = threading.Thread(target=_worker_loop, name="swarmex-fields",
                                           daemon=True)
                _WORKER.start()
    _JOBS.put(job)
    return job


def _scratch_queue(scratch: dict, n: int) -> np.ndarray:
    q = scratch.get(n)
    if q is None:
        q = scratch[n] = np.empty(n, dtype=np.int32)
    return q


class KnownGraph:
    """A graph plus the obstacles someone knows about, with a cache of distance fields.

    ``blocked`` only ever gains vertices (obstacles are static), which is what makes the
    incremental updates sound. Counters: ``recomputed`` (full searches, ``prefetched`` of
    them on the worker thread), ``repaired`` (stale uniform fields fixed in place),
    ``reused`` (served as they were).
    """

    def __init__(self, graph: NodeGraph, capacity: int = 64, prefetch: bool = False) -> None:
        self.graph = graph
        self.blocked = np.zeros(graph.n_nodes, dtype=bool)
        self._log: list[int] = []
        self.capacity = capacity
        self.recomputed = 0
        self.reused = 0
        self.repaired = 0
        self.prefetched = 0
        self.uniform = bool(graph.uniform)
        # float fields (non-uniform graphs), keyed by source: (field, version)
        self._cache: OrderedDict[int, tuple[np.ndarray, int]] = OrderedDict()
        self._prefetch = False
        if self.uniform:
            n = graph.n_nodes
            self.step = step_length(graph)
            self._prefetch = prefetch and n >= PREFETCH_MIN_NODES
            # rows never move while a worker may write one, so then allocate them all now
            rows = max(4, capacity) if self._prefetch else 0
            self.hops = np.empty((rows, n), dtype=np.int32)
            self._slot: OrderedDict[int, int] = OrderedDict()  # source -> row, LRU order
            self._slot_version: list[int] = [-1] * rows
            self._free: list[int] = list(range(rows - 1, -1, -1))
            self._pending: dict[int, _Job] = {}  # row -> prefetch in flight
            self._float: dict[int, np.ndarray] = {}  # row -> float field, until it changes
            # scratch for the repair and BFS kernels (the worker has its own queue)
            self._state = np.zeros(n, dtype=np.int8)
            self._touched = np.empty(n, dtype=np.int32)
            self._work = np.empty(2 * n + 2, dtype=np.int32)
            self._key = np.empty(n, dtype=np.int32)
            self._queue = np.empty(n, dtype=np.int32)
            self._scratch = {n: self._queue}  # this thread's queues, when it runs a job
            self._repair_limit = max(1, n // 6)
            # what a fresh hop row starts as: UNREACHED, or BLOCKED for known obstacles
            self._template = np.full(n, UNREACHED, dtype=np.int32)
            self._width, self._nbmask = lattice_structure(graph)

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
        """Start computing ``source``'s field in the background (no-op unless enabled or
        when the field is cached already, fresh or stale: a repair is cheaper)."""
        source = int(source)
        if not self._prefetch or source in self._slot:
            return
        near = self._near_row(source)
        slot = self._alloc()
        self._slot[source] = slot
        self._slot_version[slot] = self.version
        row = self.hops[slot]
        self._float.pop(slot, None)
        # the row starts from what is known now; later obstacles are repaired on use
        n = row.shape[0]
        if near is not None:
            row[:] = self.hops[near]
            fn = self._shift
        else:
            row[:] = self._template
            fn = self._search
        self._pending[slot] = _submit(_Job(lambda sc: fn(source, row, _scratch_queue(sc, n))))
        self.recomputed += 1
        self.prefetched += 1
        self._trim(1)

    def close(self) -> None:
        """Wait for fields in flight (call before dropping a prefetching cache)."""
        for job in self._pending.values():
            job.wait(self._scratch)
        self._pending.clear()

    def _near_row(self, source: int) -> int | None:
        """Row of a cached, up-to-date field whose source is a neighbour of ``source`` at
        distance one, from which ``source``'s field follows by :meth:`_shift` (lattices)."""
        if not self._width or self.blocked[source]:
            return None
        for other in self.graph.neighbors(source).tolist():
            slot = self._slot.get(other)
            if slot is None or self.blocked[other] or slot in self._pending:
                continue
            slot = self._ensure(other)  # repairs it if stale (usually it is fresh)
            if self.hops[slot, source] == 1:
                return slot
        return None

    def _shift(self, source: int, row: np.ndarray, queue: np.ndarray) -> None:
        """``row`` holds the field of a neighbour of ``source``: make it ``source``'s."""
        _shift_source_lattice(self._width, self._nbmask, row, source, queue)

    def _search(self, source: int, row: np.ndarray, queue: np.ndarray) -> None:
        """Fresh single-source search into ``row``, which holds a copy of the template."""
        if self._width:
            _bfs_hops_lattice(self._width, self._nbmask, source, row, queue)
        else:
            _bfs_hops_csr(self.graph.indptr, self.graph.indices, source, row, queue)

    def _ensure(self, source: int) -> int:
        slot = self._slot.get(source)
        ver = self.version
        if slot is not None:
            self._slot.move_to_end(source)
            job = self._pending.pop(slot, None)
            if job is not None:
                job.wait(self._scratch)
            old = self._slot_version[slot]
            if old == ver:
                self.reused += 1
                return slot
            self._slot_version[slot] = ver
            g = self.graph
            new = np.asarray(self._log[old:], dtype=np.int64)
            changed = _repair_hops(
                g.indptr, g.indices, self.blocked, self.hops[slot], source, new,
                self._state, self._touched, self._work, self._key, self._repair_limit,
            )
            if changed == 0:
                self.reused += 1
                return slot
            self._float.pop(slot, None)
            if changed > 0:
                self.repaired += 1
                return slot
            row = self.hops[slot]
            row[:] = self._template
            self._search(source, row, self._queue)
        else:
            near = self._near_row(source)
            slot = self._alloc()
            self._slot[source] = slot
            self._slot_version[slot] = ver
            row = self.hops[slot]
            if near is not None:
                row[:] = self.hops[near]
                self._shift(source, row, self._queue)
            else:
                row[:] = self._template
                self._search(source, row, self._queue)
        self._float.pop(slot, None)
        self.recomputed += 1
        return slot

    def _alloc(self) -> int:
        if self._free:
            return self._free.pop()
        self.close()  # rows are about to move: no worker may be writing one
        rows, n = self.hops.shape
        grown = np.empty((max(4, 2 * rows), n), dtype=np.int32)
        grown[:rows] = self.hops
        self.hops = grown  # float fields are copies, so they stay valid
        self._slot_version.extend([-1] * (grown.shape[0] - rows))
        self._free.extend(range(grown.shape[0] - 1, rows, -1))
        return rows

    def _trim(self, keep: int) -> None:
        """Evict least recently used fields beyond capacity, sparing the last ``keep``."""
        limit = max(self.capacity, keep)
        while len(self._slot) > limit:
            _, slot = self._slot.popitem(last=False)
            job = self._pending.pop(slot, None)
            if job is not None:
                job.wait(self._scratch)
            self._float.pop(slot, None)
            self._free.append(slot)
