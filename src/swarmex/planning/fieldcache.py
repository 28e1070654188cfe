"""Distance fields that follow a growing set of known obstacles without being recomputed.

MADGTA needs, at every decision, the travel distance from every agent's node to every
candidate vertex, on the graph minus the obstacles known so far. Agents discover obstacles
one by one, so naive caching would throw every field away at every discovery.
:class:`KnownGraph` instead keeps a log of discoveries and brings a cached field up to date
only when it is asked for. Two regimes, chosen by the graph:

* **uniform edge lengths** (grids): fields are hop counts, one row per cached source in one
  2-D table, so kernels read many fields in one call. The table holds 16-bit integers (half
  the memory traffic of every kernel) and is widened to 32 bits the first time a distance
  would not fit. Hop counts have no rounding, so every route to a field gives the same
  integers and the cache policy cannot change a result. That frees three shortcuts:

  - a stale field is *repaired* (``_repair_hops``: only the vertices whose shortest paths
    ran through the new obstacles are re-derived) instead of recomputed; on a map whose
    walls are discovered cell by cell that turns about half of all field computations
    into small repairs;
  - the field of a vertex next to a cached source is *derived* from it on a lattice
    (``_shift_lattice``: every distance moves by exactly one, so only the smaller side of
    the split has to be searched), which is what an agent stepping to a neighbour needs,
    at about a third of the cost of a search;
  - rows are recycled in least-recently-used order, and the row of a source that has just
    been left (an agent stepped away) is shifted in place rather than copied.

  With ``prefetch=True`` the simulator's :meth:`KnownGraph.prefetch` hands the shift of
  a moving agent's next field to a worker thread (the kernels release the GIL), and
  whoever needs a field first runs it if the worker has not: results never depend on the
  thread's timing. It pays only when a second core is idle; on a busy machine the
  hand-offs cost a few per cent, which is why the simulator leaves it off by default.

* **other graphs**: float Dijkstra fields, checked by :func:`_still_exact` (a field is
  unchanged by blocking a set of vertices iff every vertex whose shortest path could run
  through them keeps another shortest-path predecessor) and recomputed when it fails. The
  check compares floats with a tolerance, so a kept field can differ from a fresh one in the
  last bits; this path therefore keeps its original LRU policy unchanged, so results stay
  reproducible run to run and release to release.
"""

from __future__ import annotations

import queue
import threading
from collections import OrderedDict
from collections.abc import Callable, Iterable

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import kernel
from swarmex.planning.distance import (
    _bfs_hops_csr,
    _bfs_hops_lattice,
    _first_steps,
    distance_field,
    free_counts,
    lattice_structure,
    max_hop_of,
    step_length,
)
from swarmex.planning.hop_repair import _repair_hops
from swarmex.planning.hop_shift import _shift_lattice
from swarmex.planning.kernel_arrays import (
    BLOCKED,
    UNREACHED,
    Field,
    Hops,
    Indices,
    Indptr,
    Mask,
    Vertices,
    Weights,
)
from swarmex.planning.tiles import Tiling, raise_tile_max, tile_range, tile_range_lattice
from swarmex.worlds.nodegraph import NodeGraph


@kernel(cache=True, nogil=True)
def _still_exact(
    indptr: Indptr, indices: Indices, weights: Weights, blocked: Mask, field: Field,
    new_obstacles: Vertices,
) -> bool:  # pragma: no cover
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


@kernel(cache=True, nogil=True)
def _gather(
    hops: Hops, slot: int, vertices: Vertices, step: float, out: NDArray[np.float64]
) -> None:  # pragma: no cover - compiled
    row = hops[slot]
    for i in range(vertices.shape[0]):
        h = row[vertices[i]]
        out[i] = np.inf if h < 0 else h * step


class _Scratch:
    """Work arrays of one thread for the shift kernels: search queue and visit marks (the
    marks carry a fresh epoch per search, so they never need clearing)."""

    __slots__ = ("queue", "mark", "epoch")

    def __init__(self, n: int) -> None:
        self.queue = np.empty(n, dtype=np.int32)
        self.mark = np.zeros(n, dtype=np.int32)
        self.epoch = 0

    def next_epoch(self) -> int:
        self.epoch += 1
        if self.epoch >= 2**31 - 1:
            self.mark[:] = 0
            self.epoch = 1
        return self.epoch


class _Job:
    """A field computation that the worker thread runs, or the thread that needs its result
    if that one gets there first (so nobody ever waits for a worker the OS has not run)."""

    __slots__ = ("lock", "run", "done", "error")

    def __init__(self, run: Callable[[_Scratch], None]) -> None:
        self.lock = threading.Lock()
        self.run = run  # run(scratch): the kernel call, given the runner's _Scratch
        self.done = False
        self.error: BaseException | None = None

    def claim_and_run(self, scratch: _Scratch) -> bool:
        """Run it unless someone else has; False if someone else has it."""
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

    def wait(self, scratch: _Scratch) -> None:
        if not self.done and not self.claim_and_run(scratch):
            with self.lock:  # the worker is on it: its kernel releases the GIL
                pass
        if self.error is not None:
            raise self.error


#: below this many vertices a shift is cheaper than handing it to a thread
PREFETCH_MIN_NODES = 4096

_JOBS: queue.SimpleQueue[tuple[_Job, int]] = queue.SimpleQueue()
_WORKER: threading.Thread | None = None
_WORKER_LOCK = threading.Lock()


def _worker_loop() -> None:
    scratch: dict[int, _Scratch] = {}
    while True:
        job, n = _JOBS.get()
        sc = scratch.get(n)
        if sc is None:
            sc = scratch[n] = _Scratch(n)
        job.claim_and_run(sc)


def _submit(job: _Job, n: int) -> None:
    """Queue a job for the shared worker thread (a daemon: nothing to shut down)."""
    global _WORKER
    if _WORKER is None:
        with _WORKER_LOCK:
            if _WORKER is None:
                _WORKER = threading.Thread(target=_worker_loop, name="swarmex-fields",
                                           daemon=True)
                _WORKER.start()
    _JOBS.put((job, n))


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
        self.capacity = max(1, capacity)
        self.recomputed = 0
        self.reused = 0
        self.repaired = 0
        self.shifted = 0
        self.uniform = bool(graph.uniform)
        # float fields (non-uniform graphs), keyed by source: (field, version)
        self._cache: OrderedDict[int, tuple[np.ndarray, int]] = OrderedDict()
        self._prefetch = False
        if self.uniform:
            n = graph.n_nodes
            self.step = step_length(graph)
            # one row per cached source; 16-bit hop counts halve the memory traffic of every
            # kernel, and the table is widened to 32 bits if a distance ever needs it
            self.hops = np.empty((0, n), dtype=np.int16)
            self._max_hop = max_hop_of(np.int16)
            self._row_max = np.empty(0, dtype=np.int64)  # row -> bound on its largest hop
            # bookkeeping in arrays, so a request for many fields is a few numpy operations
            self._row_of = np.full(n, -1, dtype=np.int64)  # source -> row
            self._source = np.empty(0, dtype=np.int64)  # row -> source (-1: free)
            self._version = np.empty(0, dtype=np.int64)  # row -> obstacles it knows
            self._used = np.empty(0, dtype=np.int64)  # row -> clock of last use
            self._clock = 0
            self._float: dict[int, np.ndarray] = {}  # row -> float field, until it changes
            # scratch for the kernels
            self._state = np.zeros(n, dtype=np.int8)
            self._touched = np.empty(n, dtype=np.int32)
            self._work = np.empty(2 * n + 2, dtype=np.int32)
            self._key = np.empty(n, dtype=np.int32)
            self._scratch = _Scratch(n)
            self._max_degree = int(np.diff(graph.indptr).max()) if n else 0
            self._queue = self._scratch.queue
            self._repair_limit = max(1, n // 6)
            # what a fresh hop row starts as: UNREACHED, or BLOCKED for known obstacles
            self._template = np.full(n, UNREACHED, dtype=self.hops.dtype)
            width, mask = lattice_structure(graph)
            self._width = width
            self._nbmask = mask if mask is not None else np.zeros(1, dtype=np.uint8)
            # vertices not known blocked per grid column / row: a shift guesses from them
            # how big its cone is (the guess picks the faster search, never a value)
            self._col_free, self._row_free = free_counts(
                np.ones(n if width else 0, dtype=bool), max(width, 1))
            # background shifts (see prefetch): row -> job writing it / jobs reading it
            self._prefetch = prefetch and width > 0 and n >= PREFETCH_MIN_NODES
            self._pending: dict[int, _Job] = {}
            self._reading: dict[int, list[_Job]] = {}
            # per-tile bounds of each row (see tile_bounds), built on first use
            self._tiling: Tiling | None = None
            self._tlo = np.empty((0, 0), dtype=np.int32)
            self._thi = np.empty((0, 0), dtype=np.int32)
            self._slack = np.empty(0, dtype=np.int64)  # row -> drift of its bounds, -1: none

    @property
    def version(self) -> int:
        return len(self._log)

    @property
    def open_lattice(self) -> int:
        """The lattice's width while the graph is a full 4-connected lattice with no
        obstacle known (every distance is then the lattice distance ``|dx| + |dy|`` hops,
        no field needed), else 0."""
        return self._width if self.uniform and not self._log else 0

    def add_obstacles(self, vertices: Iterable[int] | np.ndarray) -> bool:
        """Mark vertices as known obstacles; returns True if any was new."""
        new = False
        for v in vertices:
            v = int(v)
            if not self.blocked[v]:
                self.blocked[v] = True
                self._log.append(v)
                if self.uniform:
                    self._template[v] = BLOCKED
                    if self._width:
                        y, x = divmod(v, self._width)
                        self._col_free[x] -= 1
                        self._row_free[y] -= 1
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

    def first_steps(self, slot: int, target: int) -> np.ndarray:
        """The neighbours of row ``slot``'s source on a shortest path to ``target``
        (uniform graphs; ``slot`` as :meth:`slot` returns it), in no particular order:
        what :func:`~swarmex.planning.distance.steps_towards` gives on ``field(target)``,
        found by walking back from ``target`` through the source's own row, so ``target``
        needs no field (it is no agent's position: its field would be a fresh search, kept
        and repaired only for the few steps that head for it)."""
        sc = self._scratch
        out = np.empty(self._max_degree, dtype=np.int64)
        found = _first_steps(self.graph.indptr, self.graph.indices, self.hops[slot],
                             int(target), sc.mark, sc.next_epoch(), sc.queue, out)
        return out[:found]

    # ------------------------------------------------------------------ hop rows (uniform)
    def slot(self, source: int) -> int:
        """Row of ``self.hops`` holding the up-to-date hop field of ``source``.

        Uniform graphs only. The row stays valid until a later ``slot``/``slots``/``field``
        call recycles it (``capacity`` other sources later, or when its source is left for
        a neighbour) or repairs it.
        """
        self._clock += 1
        return self._ensure(int(source))

    def slots(self, sources: np.ndarray) -> np.ndarray:
        """Rows for several sources at once, all valid together (see :meth:`slot`)."""
        self._clock += 1
        if self._pending:
            self._prune()
        rows = self._row_of[sources]
        ok = rows >= 0
        ok[ok] = self._version[rows[ok]] == self.version
        if self._pending:
            ok &= np.array([r not in self._pending for r in rows.tolist()], dtype=bool)
        self._used[rows[ok]] = self._clock  # first, so making the others cannot evict them
        self.reused += int(ok.sum())
        if not ok.all():
            for i in np.flatnonzero(~ok).tolist():
                rows[i] = self._ensure(int(sources[i]))
        return rows

    def prefetch(self, source: int, near: int) -> None:
        """Start deriving ``source``'s field from that of its neighbour ``near`` on the
        worker thread (no-op unless enabled with ``prefetch=True``, or when ``source`` is
        cached already or ``near`` is not). The simulator calls this when an agent decides
        to move from ``near`` to ``source``: the field is ready when others first ask.

        The new row knows the obstacles ``near``'s row knew; later ones are repaired on
        first use, so results do not depend on the thread's timing.
        """
        if not self._prefetch:
            return
        source, near = int(source), int(near)
        if self._row_of[source] >= 0 or self._row_of[near] < 0 or self.blocked[source]:
            return
        self._prune()
        self._clock += 1
        src = self._ensure(near)  # up to date (and settled: no job writes it)
        if self.hops[src, source] != 1 or self.blocked[near]:
            return
        if self._row_max[src] + 1 > self._max_hop:
            self._widen()
        dst = self._free_row()
        self._row_max[dst] = self._row_max[src] + 1
        self._row_of[source] = dst
        self._source[dst] = source
        self._version[dst] = self._version[src]
        self._used[dst] = self._clock
        self._float.pop(dst, None)
        self._shift_bounds(src, dst)
        hops, width, mask = self.hops, self._width, self._nbmask
        near_source, top = near, int(self._row_max[src])
        col_free, row_free = self._col_free.copy(), self._row_free.copy()

        def run(sc: _Scratch) -> None:
            _shift_lattice(width, mask, hops[src], hops[dst], source, near_source, col_free,
                           row_free, sc.mark, sc.next_epoch(), sc.queue, top)

        job = _Job(run)
        self._pending[dst] = job
        self._reading.setdefault(src, []).append(job)
        self.shifted += 1
        self.recomputed += 1
        _submit(job, hops.shape[1])

    def _prune(self) -> None:
        """Forget finished background jobs (surfacing any error they raised)."""
        for slot in [k for k, job in self._pending.items() if job.done]:
            self._pending.pop(slot).wait(self._scratch)
        for slot in list(self._reading):
            left = [job for job in self._reading[slot] if not job.done]
            if left:
                self._reading[slot] = left
            else:
                for job in self._reading.pop(slot):
                    job.wait(self._scratch)

    def _settle(self, slot: int) -> None:
        """Finish the background jobs that write or read row ``slot``."""
        job = self._pending.pop(slot, None)
        if job is not None:
            job.wait(self._scratch)
        for job in self._reading.pop(slot, ()):
            job.wait(self._scratch)

    def _settle_all(self) -> None:
        for slot in list(self._pending) + list(self._reading):
            self._settle(slot)

    def _ensure(self, source: int) -> int:
        """Row of ``source``, computed, repaired or reused; marked as used now."""
        slot = int(self._row_of[source])
        if slot < 0:
            return self._compute(source)
        self._used[slot] = self._clock
        if self._pending:
            job = self._pending.pop(slot, None)
            if job is not None:  # a background shift: wait for it (or do it here)
                job.wait(self._scratch)
        old = int(self._version[slot])
        ver = self.version
        if old == ver:
            self.reused += 1
            return slot
        if self._reading:
            self._settle(slot)  # a background shift still reads this row
        self._version[slot] = ver
        self._float.pop(slot, None)
        g = self.graph
        new = np.asarray(self._log[old:], dtype=np.int64)
        changed, top, affected = _repair_hops(
            g.indptr, g.indices, self.blocked, self.hops[slot], source, new,
            self._state, self._touched, self._work, self._key, self._repair_limit,
            self._max_hop,
        )
        if changed == 0:
            self.reused += 1
        elif changed > 0:
            self.repaired += 1
            self._row_max[slot] = max(self._row_max[slot], top)
            if self._slack[slot] >= 0:  # repairs only raise values: raise the tiles' maxima
                raise_tile_max(self.hops[slot], self._key, affected,
                               self._tiling.tile_of, self._thi[slot])  # type: ignore[union-attr]
        else:  # too much changed (a fresh search is cheaper), or too far for the type
            if changed == -2:
                self._widen()
            self._search(source, slot)
        return slot

    def _compute(self, source: int) -> int:
        """A row for a source not cached: shifted from a neighbour's field if one is cached
        (in place when that neighbour is not in the current request), else searched."""
        near = self._near_row(source)
        near_source = int(self._source[near]) if near is not None else -1
        if near is not None:
            bound = int(self._row_max[near]) + 1  # a shift adds at most one hop
            if bound > self._max_hop:
                self._widen()
        if near is not None and self._used[near] != self._clock:
            slot = near  # the neighbour's field is not wanted now: recycle its row
            if self._reading:
                self._settle(slot)
            self._row_of[self._source[slot]] = -1
        else:
            slot = self._free_row()
        self._row_of[source] = slot
        self._source[slot] = source
        self._version[slot] = self.version
        self._used[slot] = self._clock
        self._float.pop(slot, None)
        if near is None:
            self._search(source, slot)
        else:
            sc = self._scratch
            _shift_lattice(self._width, self._nbmask, self.hops[near], self.hops[slot], source,
                           near_source, self._col_free, self._row_free, sc.mark,
                           sc.next_epoch(), sc.queue, bound - 1)
            self._row_max[slot] = bound
            self._shift_bounds(near, slot)
            self.shifted += 1
            self.recomputed += 1
        return slot

    def _search(self, source: int, slot: int) -> None:
        while True:
            row = self.hops[slot]
            row[:] = self._template
            if self._width:
                top = _bfs_hops_lattice(self._width, self._nbmask, source, row, self._queue,
                                        self._max_hop)
            else:
                top = _bfs_hops_csr(self.graph.indptr, self.graph.indices, source, row,
                                    self._queue, self._max_hop)
            if top >= 0:
                break
            self._widen()  # a distance does not fit the table's type
        self._row_max[slot] = top
        self._drop_bounds(slot)
        self.recomputed += 1

    def _widen(self) -> None:
        """Switch the hop table to 32-bit integers (values are kept; nothing is redone)."""
        if self.hops.dtype == np.int32:
            raise OverflowError("hop counts beyond 32-bit integers")
        self._settle_all()
        self.hops = self.hops.astype(np.int32)
        self._template = self._template.astype(np.int32)
        self._max_hop = max_hop_of(np.int32)

    def _near_row(self, source: int) -> int | None:
        """Row of a cached field whose source is a neighbour of ``source`` at distance one
        (brought up to date first): ``source``'s field then follows by a shift. Lattices
        only, where the shift is exact; neither source may be an obstacle."""
        if not self._width or self.blocked[source]:
            return None
        for other in self.graph.neighbors(source).tolist():
            if self._row_of[other] < 0 or self.blocked[other]:
                continue
            if int(self._row_of[other]) in self._pending:
                continue  # being derived in the background
            keep = self._used[self._row_of[other]]
            slot = self._ensure(other)  # repairs it if stale (usually it is fresh)
            self._used[slot] = keep  # looking at it is not using it
            if self.hops[slot, source] == 1:
                return slot
        return None

    def _free_row(self) -> int:
        """An unused row, or the least recently used one not used by the current request,
        or a new row (the table grows by doubling)."""
        rows = self.hops.shape[0]
        free = np.flatnonzero(self._source < 0)
        if free.size:
            return int(free[0])
        if rows >= self.capacity:
            never = np.iinfo(np.int64).max
            old = np.where(self._used == self._clock, never, self._used)
            for busy in (*self._pending, *self._reading):
                old[busy] = never  # rows a background job writes or reads
            slot = int(np.argmin(old))
            if old[slot] != never:
                self._row_of[self._source[slot]] = -1
                self._source[slot] = -1
                self._float.pop(slot, None)
                return slot
        self._settle_all()  # rows are about to move
        grown = max(rows + 1, min(max(4, 2 * rows), self.capacity))
        hops = np.empty((grown, self.hops.shape[1]), dtype=self.hops.dtype)
        hops[:rows] = self.hops
        self.hops = hops  # float fields are copies, so they stay valid
        self._row_max = np.concatenate([self._row_max, np.zeros(grown - rows, np.int64)])
        self._source = np.concatenate([self._source, np.full(grown - rows, -1, np.int64)])
        self._version = np.concatenate([self._version, np.zeros(grown - rows, np.int64)])
        self._used = np.concatenate([self._used, np.zeros(grown - rows, np.int64)])
        self._slack = np.concatenate([self._slack, np.full(grown - rows, -1, np.int64)])
        if self._tiling is not None:
            extra = np.empty((grown - rows, self._tiling.n_tiles), dtype=np.int32)
            self._tlo = np.concatenate([self._tlo, extra])
            self._thi = np.concatenate([self._thi, extra])
        return rows

    # ------------------------------------------------------------------ tile bounds (uniform)
    #: bounds that drifted by more than this many shifts are recomputed on their next use
    MAX_SLACK = 4

    @property
    def tiling(self) -> Tiling:
        """The tiles of the graph (:mod:`swarmex.planning.tiles`), made on first use."""
        if self._tiling is None:
            self._tiling = Tiling(self.graph.n_nodes, self._width)
            rows, t = self.hops.shape[0], self._tiling.n_tiles
            self._tlo = np.empty((rows, t), dtype=np.int32)
            self._thi = np.empty((rows, t), dtype=np.int32)
            self._slack[:] = -1
        return self._tiling

    def tile_bounds(self, slots: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per-tile bounds of the hop rows ``slots`` (rows as :meth:`slots` returns them):
        ``(lo, hi, slack)``, tables of all rows, such that every reachable vertex ``v`` of a
        tile ``t`` of row ``s`` has ``lo[s, t] - slack[s] <= hops[s, v] <= hi[s, t] +
        slack[s]``. ``lo`` NONE_LO and ``hi`` NONE_HI mark a tile the row reaches nowhere
        (and never will: shifts and repairs never make a vertex reachable); a tile that a
        repair cut off keeps its old, still valid, bounds. Costs nothing for a row whose
        bounds are current, one pass over the row otherwise."""
        tiling = self.tiling
        self._settle_pending(slots)
        for s in slots.tolist():
            slack = self._slack[s]
            if slack < 0 or slack > self.MAX_SLACK:
                if tiling.width:
                    tile_range_lattice(self.hops[s], tiling.width, self._tlo[s], self._thi[s])
                else:
                    tile_range(self.hops[s], tiling.tile_of, self._tlo[s], self._thi[s])
                self._slack[s] = 0
        return self._tlo, self._thi, self._slack

    def _settle_pending(self, slots: np.ndarray) -> None:
        if self._pending:
            for s in slots.tolist():
                job = self._pending.pop(s, None)
                if job is not None:
                    job.wait(self._scratch)

    def _drop_bounds(self, slot: int) -> None:
        """Row ``slot`` was rewritten: its tile bounds are recomputed on next use."""
        self._slack[slot] = -1

    def _shift_bounds(self, src: int, dst: int) -> None:
        """Row ``dst`` now holds row ``src``'s field shifted by one edge: every value moved
        by one, so ``src``'s bounds widened by one hold for it."""
        slack = self._slack[src]
        if slack < 0:
            self._slack[dst] = -1
            return
        if dst != src:
            self._tlo[dst] = self._tlo[src]
            self._thi[dst] = self._thi[src]
        self._slack[dst] = slack + 1
