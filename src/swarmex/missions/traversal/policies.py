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

Speed: on graphs with one edge length, :class:`Madgta` and :class:`Nearest` decide through
compiled kernels that read the hop-count rows of the field cache (branch 2 in one call,
branch 3 by tiles with bounds, :mod:`.fartiles`, rivals grouped by speed and job time;
on an open lattice by blocks with closed-form distances, :mod:`.lattice`). Every float is
computed with the same operations in the same order as the numpy code kept below for the
other cases (and for subclasses that override ``utilities`` or ``best``), so the choices,
and every draw from the generator, are the same bit for bit.
"""

from __future__ import annotations

import ast
import contextlib
import inspect
import math
import typing
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from swarmex._kernels import interpreting, kernel
from swarmex.errors import InputError
from swarmex.missions.traversal import lattice
from swarmex.missions.traversal.belief import TeamPlan, TraversalBelief
from swarmex.missions.traversal.fartiles import far_tiles
from swarmex.missions.traversal.selection import FAR as _FAR
from swarmex.missions.traversal.selection import JOB as _JOB
from swarmex.missions.traversal.selection import NUMPY as _NUMPY
from swarmex.missions.traversal.selection import PICK as _PICK
from swarmex.missions.traversal.selection import group_stats, select_top, vacant_neighbours
from swarmex.missions.traversal.selection import top_columns as _top_columns
from swarmex.planning.distance import on_path_neighbors, steps_towards


@dataclass(frozen=True)
class Decision:
    kind: str  # "job" (branch 1), "move" (branches 2 and 3) or "finish"
    node: int = -1  # where to do the job / the adjacent vertex to move to
    target: int = -1  # the vertex GetBestNode chose (== node in branches 1-2)
    branch: int = 0
    # a team plan the agent broadcasts with this decision (madgta-s), else None
    plan: TeamPlan | None = None


def _pick(candidates: np.ndarray, rng: np.random.Generator) -> int:
    if candidates.size == 1:
        return int(candidates[0])
    return int(np.sort(candidates)[rng.integers(candidates.size)])


def decision_towards(belief: TraversalBelief, target: int, rng: np.random.Generator) -> Decision:
    """MADGTA's decision once GetBestNode has chosen ``target`` (its three branches): the job
    here, a move onto an adjacent target, else a step along a shortest known path towards it,
    drawn from the candidates as the policy draws. One place for the rule, which the policy
    and the traversal env's actions (an agent choosing its target itself) both apply."""
    here = int(belief.here)
    if target == here:
        return Decision("job", here, here, 1)
    if np.any(belief.graph.neighbors(here) == target):
        return Decision("move", target, target, 2)
    steps = steps_towards(belief.graph, belief.known.field(target), here)
    return Decision("move", _pick(steps, rng), target, 3)


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


# ---------------------------------------------------------------- compiled fast path
# On graphs with one edge length the fields are exact hop counts (KnownGraph.hops), so the
# utilities can be read straight from the hop rows. Every float below is computed with the
# same operations in the same order as the numpy code of Madgta.utilities/get_best_node
# (numba does not contract a*b+c into a fused multiply-add), so decisions are bit-identical.


@kernel(cache=True, nogil=True)
def _util_matrix(
    hops: NDArray[np.signedinteger[Any]], me_slot: int, slots: NDArray[np.int64],
    cands: NDArray[np.int64], step: float, tpu_me: float, jt_me: float,
    tpu: NDArray[np.float64], jt: NDArray[np.float64], util: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Fills ``util[i, j]`` exactly as Madgta.utilities computes it."""
    for j in range(cands.shape[0]):
        c = cands[j]
        h = hops[me_slot, c]
        mine = (np.inf if h < 0 else h * step) * tpu_me
        mine = mine + jt_me
        for i in range(slots.shape[0]):
            h = hops[slots[i], c]
            theirs = (np.inf if h < 0 else h * step) * tpu[i]
            util[i, j] = theirs + jt[i] - mine


@kernel(cache=True, nogil=True)
def _tied_top(
    hops: NDArray[np.signedinteger[Any]], me_slot: int, cands: NDArray[np.int64], step: float,
    tpu_me: float, jt_me: float, g_slots: NDArray[np.int64], g_tpu: NDArray[np.float64],
    g_jt: NDArray[np.float64], counts: NDArray[np.int64],
) -> NDArray[np.int64]:  # pragma: no cover - compiled
    """``top_columns`` of the matrix :func:`_util_matrix` fills, without the matrix.

    Rivals come in groups of one hop row and one class (``g_slots``, ``g_tpu``, ``g_jt``;
    ``counts[g]`` rivals each): rivals on one vertex share a hop row, so their utilities are
    the same float, computed here once per group and summed by :func:`group_stats`. A crowd
    on one nest of a walled map ties about 40,000 vertices with 100 rivals on about 20
    vertices: writing the whole matrix (35 MB) and reading it back by columns cost more
    than the rest of the decision."""
    g = g_slots.shape[0]
    n = 0
    for u in range(g):
        n += counts[u]
    c = cands.shape[0]
    mins = np.empty(c)
    sums = np.empty(c)
    errs = np.empty(c)
    vals = np.empty(g)
    for j in range(c):
        v = cands[j]
        h = hops[me_slot, v]
        mine = (np.inf if h < 0 else h * step) * tpu_me
        mine = mine + jt_me
        for u in range(g):
            h = hops[g_slots[u], v]
            theirs = (np.inf if h < 0 else h * step) * g_tpu[u]
            vals[u] = theirs + g_jt[u] - mine
        if not group_stats(vals, counts, n, j, mins, sums, errs):
            return np.full(1, -1, dtype=np.int64)
    return select_top(mins, sums, errs)


@kernel(cache=True, nogil=True)
def _own_costs(
    hops: NDArray[np.signedinteger[Any]], me_slot: int, cands: NDArray[np.int64], step: float,
    tpu_me: float, jt_me: float, out: NDArray[np.float64],
) -> None:  # pragma: no cover
    for j in range(cands.shape[0]):
        h = hops[me_slot, cands[j]]
        mine = (np.inf if h < 0 else h * step) * tpu_me
        out[j] = mine + jt_me


@kernel(cache=True, nogil=True)
def _near_choice(
    hops: NDArray[np.signedinteger[Any]], me_slot: int, slots: NDArray[np.int64],
    indptr: NDArray[np.int64], indices: NDArray[np.int32], here: int, status: NDArray[np.int32],
    reserved: NDArray[np.int32], me: int, step: float, tpu_me: float, jt_me: float,
    tpu: NDArray[np.float64], jt: NDArray[np.float64],
) -> tuple[int, NDArray[np.int64]]:  # pragma: no cover - compiled
    """Branch 2 in one call: the vacant neighbours W of ``here`` (not in KM, sorted,
    unique), their utilities as Madgta.utilities computes them, and GetBestNode's choice.
    Returns ``(_FAR, [])`` when W is empty, ``(_PICK, tied)`` for the final draw, or
    ``(_NUMPY, W)`` when the sum tie-break must be left to numpy (see _top_columns)."""
    cands = vacant_neighbours(indptr, indices, here, status, reserved, me)
    c = cands.shape[0]
    if c == 0:
        return _FAR, cands
    r = slots.shape[0]
    util = np.empty((max(r, 1), c))
    if r == 0:  # no rival: minus the own cost (the generic code's -mine[None, :])
        for j in range(c):
            h = hops[me_slot, cands[j]]
            mine = (np.inf if h < 0 else h * step) * tpu_me
            util[0, j] = -(mine + jt_me)
    else:
        _util_matrix(hops, me_slot, slots, cands, step, tpu_me, jt_me, tpu, jt, util)
    top = _top_columns(util)
    if top[0] < 0:
        return _NUMPY, cands
    return _PICK, cands[top]


class Madgta:
    """Algorithm 1's COMPUTE with Algorithm 2's GetBestNode."""

    name = "madgta"
    #: whether a run's kernels simulate the mission (rollouts, team plans): interpreted, such
    #: a run takes minutes even on a small map, so it always pays to load numba for it
    simulates = False
    #: vertices the compiled branch-3 searches looked at, and how many such searches ran
    #: (operation counts for bench/ and tests/test_scale_growth.py)
    scanned = 0
    far_decisions = 0

    def decide(self, belief: TraversalBelief, rng: np.random.Generator) -> Decision:
        known = belief.known
        if known.open_lattice:
            kind = self._compiled_kind()
            if kind:  # no wall known yet: distances in closed form, no fields
                return self._decide_lattice(belief, rng, kind == "madgta")
        here = belief.here
        if not belief.in_km(here):
            return Decision("job", here, here, 1)
        fast = self._fast_rivals(belief)
        if fast is not None:
            return self._decide_compiled(belief, rng, *fast)
        nbrs = belief.graph.neighbors(here)
        vacant = nbrs[~belief.km_at(nbrs)]
        if vacant.size:
            v = self.best(belief, _sorted_unique(vacant), rng)
            return Decision("move", v, v, 2)
        mine = belief.known.field(here)
        far = np.nonzero(~belief.km_mask() & np.isfinite(mine))[0]
        if far.size == 0:
            return Decision("finish")
        return decision_towards(belief, self.best(belief, far, rng), rng)

    def best(self, belief: TraversalBelief, cands: np.ndarray, rng: np.random.Generator) -> int:
        return get_best_node(cands, self.utilities(belief, cands), rng)

    # ---- compiled path (same decisions; see _util_matrix)
    def _compiled_kind(self) -> str:
        """Which utilities the compiled kernels may stand in for: ``"madgta"``,
        ``"nearest"``, or ``""`` for a subclass that overrides ``utilities`` or ``best``
        (it gets the generic path, so variants stay correct). Also ``""`` while kernels run
        interpreted (a small one-shot run, :mod:`swarmex._kernels`): there the numpy code
        of the generic path is faster than the kernels' loops, with the same decisions."""
        if interpreting():
            return ""
        cls = type(self)
        if cls.best is not Madgta.best:
            return ""
        if cls.utilities is Madgta.utilities:
            return "madgta"
        if cls.utilities is Nearest.utilities:
            return "nearest"
        return ""

    def _fast_rivals(self, belief: TraversalBelief) -> tuple[np.ndarray, float] | None:
        """(rivals, own job time in the utility) when the compiled path applies (uniform
        graphs, the utilities defined here), else None."""
        kind = self._compiled_kind() if belief.known.uniform else ""
        if kind == "madgta":
            return belief.rivals(), float(belief.job_time[belief.me])
        if kind == "nearest":
            return _NO_RIVALS, 0.0
        return None

    def _hop_rows(
        self, belief: TraversalBelief, rivals: np.ndarray
    ) -> tuple[int, NDArray[np.int64]]:
        sources = np.empty(rivals.size + 1, dtype=np.int64)
        sources[0] = belief.here
        sources[1:] = belief.loc[rivals]
        rows = belief.known.slots(sources)
        return rows[0], rows[1:]

    def _utility_matrix(
        self, belief: TraversalBelief, cands: np.ndarray, rivals: np.ndarray, jt_me: float
    ) -> np.ndarray:
        me = belief.me
        known = belief.known
        me_slot, slots = self._hop_rows(belief, rivals)
        if rivals.size == 0:
            # no rival: util is minus the own cost (the generic code's -mine[None, :])
            own = np.empty(cands.size)
            _own_costs(known.hops, me_slot, cands, known.step, belief.time_per_unit[me],
                       jt_me, own)
            return -own[None, :]
        util = np.empty((rivals.size, cands.size))
        _util_matrix(known.hops, me_slot, slots, cands, known.step,
                     belief.time_per_unit[me], jt_me,
                     belief.time_per_unit[rivals], belief.job_time[rivals], util)
        return util

    def _scratch(self, n: int) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        """Reused work arrays of the branch-3 searches (fresh ones would page-fault each
        time): the candidates found and their max-min utilities."""
        buf = getattr(self, "_buffers", None)
        if buf is None or buf[0].size != n:
            buf = (np.empty(n, dtype=np.int64), np.empty(n))
            self._buffers = buf
        return buf

    def _decide_compiled(
        self, belief: TraversalBelief, rng: np.random.Generator, rivals: np.ndarray,
        jt_me: float,
    ) -> Decision:
        """Branches 2 and 3 from the hop rows; branch 2 in a single compiled call."""
        known = belief.known
        me = belief.me
        me_slot, slots = self._hop_rows(belief, rivals)
        g = belief.graph
        code, picks = _near_choice(
            known.hops, me_slot, slots, g.indptr, g.indices, belief.here, belief.status,
            belief.reserved, me, known.step, belief.time_per_unit[me], jt_me,
            belief.time_per_unit[rivals], belief.job_time[rivals],
        )
        if code == _FAR:
            return self._decide_far(belief, rng, rivals, jt_me, me_slot, slots)
        if code == _PICK:
            v = _pick(picks, rng)
        else:  # sums that numpy must add (see _top_columns): the generic selection
            v = get_best_node(picks, self._utility_matrix(belief, picks, rivals, jt_me), rng)
        return Decision("move", v, v, 2)

    def _decide_far(
        self, belief: TraversalBelief, rng: np.random.Generator, rivals: np.ndarray,
        jt_me: float, me_slot: int, slots: np.ndarray,
    ) -> Decision:
        """Branch 3 from the hop rows, by tiles with bounds (:mod:`.fartiles`)."""
        known = belief.known
        me = belief.me
        here = belief.here
        klass, ctpu, cjt = _rival_classes(belief.time_per_unit[rivals], belief.job_time[rivals])
        g_slots, g_klass, counts = _rival_groups(slots, klass, len(ctpu))
        unsigned, _, high = _unsigned_view(known.hops.dtype)
        far, mins = self._scratch(belief.status.size)
        rows = np.empty(g_slots.size + 1, dtype=np.int64)
        rows[0] = me_slot
        rows[1:] = g_slots
        lo, hi, slack = known.tile_bounds(rows)
        tiling = known.tiling
        dead = belief.scan_flags("field-tiles", tiling.n_tiles)
        found, nt, scanned = far_tiles(
            known.hops.view(unsigned), me_slot, g_slots, g_klass, ctpu, cjt, belief.status,
            belief.reserved, me, here, known.step, belief.time_per_unit[me], jt_me, far, mins,
            high, dead, tiling.ptr, tiling.verts, lo, hi, slack,
        )
        self.scanned += scanned
        self.far_decisions += 1
        if not found:
            return Decision("finish")
        if nt == 1:
            f = int(far[0])
        elif rivals.size == 0:
            tied = far[:nt].copy()
            f = _choose(tied, self._utility_matrix(belief, tied, rivals, jt_me), rng)
        else:
            tied = far[:nt].copy()
            top = _tied_top(known.hops, me_slot, tied, known.step, belief.time_per_unit[me],
                            jt_me, g_slots, ctpu[g_klass], cjt[g_klass], counts)
            if top[0] < 0:  # numpy must rank them (see _top_columns)
                f = get_best_node(tied, self._utility_matrix(belief, tied, rivals, jt_me), rng)
            else:
                f = _pick(tied[top], rng)
        # the next hop: walked back from f through my own row (no field of f needed);
        # the same set as steps_towards on f's field, and _pick sorts it
        steps = known.first_steps(me_slot, f)
        return Decision("move", _pick(steps, rng), f, 3)

    def _decide_lattice(
        self, belief: TraversalBelief, rng: np.random.Generator, with_rivals: bool
    ) -> Decision:
        """The decision on an open lattice (:mod:`.lattice`): the same utilities from
        lattice distances, branches 1-2 in one compiled call, branch 3 by bounded blocks."""
        known = belief.known
        width = known.open_lattice
        me, g = belief.me, belief.graph
        tpu, jt = belief.time_per_unit, belief.job_time
        step = known.step
        code, picks, rivals, sx, sy = lattice.decide_near(
            width, belief.loc, me, g.indptr, g.indices, belief.status, belief.reserved, step,
            tpu, jt, with_rivals,
        )
        if code == _PICK:
            v = _pick(picks, rng)
            return Decision("move", v, v, 2)
        here = int(belief.loc[me])
        if code == _JOB:
            return Decision("job", here, here, 1)
        tpu_me = float(tpu[me])
        jt_me = float(jt[me]) if with_rivals else 0.0
        tpu_r, jt_r = tpu[rivals], jt[rivals]
        if code == _NUMPY:
            util = lattice.util_matrix(width, sx, sy, picks, step, tpu_me, jt_me, tpu_r, jt_r)
            v = get_best_node(picks, util, rng)
            return Decision("move", v, v, 2)
        klass, ctpu, cjt = _rival_classes(tpu_r, jt_r)
        n = belief.status.size
        far, mins = self._scratch(n)
        height = n // width
        blocks = lattice.tree_nodes(width, height, lattice.BLOCK)
        found, nt, scanned = lattice.far_choice(
            width, height, sx, sy, klass, ctpu, cjt, belief.status, belief.reserved, me,
            step, tpu_me, jt_me, lattice.BLOCK, far, mins, belief.scan_flags("block-tree", blocks),
        )
        self.scanned += scanned
        self.far_decisions += 1
        if not found:
            return Decision("finish")
        if nt == 1:
            f = int(far[0])
        else:
            tied = far[:nt].copy()
            top = lattice.top_candidates(width, sx, sy, tied, step, tpu_me, jt_me, tpu_r, jt_r)
            if top[0] >= 0:
                f = _pick(tied[top], rng)
            else:
                util = lattice.util_matrix(width, sx, sy, tied, step, tpu_me, jt_me, tpu_r,
                                           jt_r)
                f = get_best_node(tied, util, rng)
        nbrs = g.neighbors(here)
        d = lattice.distances(width, f, np.concatenate(([here], nbrs)), step)
        steps = on_path_neighbors(g, here, d[0], d[1:])
        return Decision("move", _pick(steps, rng), f, 3)

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


_NO_RIVALS = np.zeros(0, dtype=np.int64)


def _sorted_unique(v: np.ndarray) -> np.ndarray:
    """np.unique for the few neighbours of a vertex (CSR order is usually sorted already)."""
    items = v.tolist()
    if all(a < b for a, b in zip(items, items[1:], strict=False)):
        return v
    return np.unique(v)


_Unsigned = tuple[np.dtype[Any], np.unsignedinteger[Any], np.unsignedinteger[Any]]
_UNSIGNED: dict[np.dtype[Any], _Unsigned] = {}


def _unsigned_view(dtype: np.dtype[Any]) -> _Unsigned:
    """(unsigned twin of a signed hop type, its maximum, its high bit), cached."""
    hit = _UNSIGNED.get(dtype)
    if hit is None:
        unsigned = np.dtype(dtype.str.replace("i", "u"))
        full = np.iinfo(unsigned).max
        hit = _UNSIGNED[dtype] = (unsigned, unsigned.type(full), unsigned.type(full // 2 + 1))
    return hit


def _rival_classes(
    tpu: np.ndarray, jt: np.ndarray
) -> tuple[NDArray[np.int64], np.ndarray, np.ndarray]:
    """Group rivals by (time per unit, job time): (class of each rival, class values)."""
    if tpu.size == 0:
        return _NO_RIVALS, tpu, jt
    if (tpu == tpu[0]).all() and (jt == jt[0]).all():
        return np.zeros(tpu.size, dtype=np.int64), tpu[:1].copy(), jt[:1].copy()
    pairs, klass = np.unique(np.stack([tpu, jt], axis=1), axis=0, return_inverse=True)
    return klass.ravel().astype(np.int64), pairs[:, 0].copy(), pairs[:, 1].copy()


def _rival_groups(
    slots: NDArray[np.int64], klass: NDArray[np.int64], classes: int
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """Rivals grouped by (hop row, class): each group's row, class and rival count.

    Rivals on one vertex share a hop row, so a group's utilities are one float: branch 3
    reads each row once per vertex instead of once per rival (a crowd leaving one nest:
    about 20 groups of 100 rivals), and the max-min and the sums are unchanged."""
    _, first, of = np.unique(slots * (classes + 1) + klass, return_index=True,
                             return_inverse=True)
    return slots[first], klass[first], np.bincount(of.ravel(), minlength=first.size)


def each_rival_alone(
    slots: NDArray[np.int64], klass: NDArray[np.int64], classes: int
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """The reference for :func:`_rival_groups`: every rival its own group (the route
    before it; bench/traversal_crowd.py and the tests compare the two)."""
    return slots, klass, np.ones(slots.size, dtype=np.int64)


def tied_top_by_matrix(
    hops: NDArray[np.signedinteger[Any]], me_slot: int, cands: NDArray[np.int64], step: float,
    tpu_me: float, jt_me: float, g_slots: NDArray[np.int64], g_tpu: NDArray[np.float64],
    g_jt: NDArray[np.float64], counts: NDArray[np.int64],
) -> NDArray[np.int64]:
    """The reference for :func:`_tied_top`: the whole utility matrix, one row per rival,
    then ``top_columns`` (the route before it)."""
    slots = np.repeat(g_slots, counts)
    tpu = np.repeat(g_tpu, counts)
    jt = np.repeat(g_jt, counts)
    util = np.empty((slots.size, cands.size))
    _util_matrix(hops, me_slot, slots, cands, step, tpu_me, jt_me, tpu, jt, util)
    return _top_columns(util)


def _choose(cands: np.ndarray, util: np.ndarray, rng: np.random.Generator) -> int:
    """get_best_node, compiled when the result is provably the same (see _top_columns)."""
    top = _top_columns(util)
    if top[0] < 0:
        return get_best_node(cands, util, rng)
    return _pick(cands[top], rng)


POLICIES: dict[str, type[Madgta]] = {"madgta": Madgta, "nearest": Nearest}


def make_policy(algorithm: str) -> Madgta:
    """The policy an algorithm spec names: ``NAME`` or ``NAME@KEY=VALUE,...``
    (:func:`parse_algorithm`); :class:`InputError` for anything it cannot build."""
    name, options = parse_algorithm(algorithm)
    try:
        return POLICIES[name](**options)
    except ValueError as exc:  # the class's own range checks
        raise InputError(f"algorithm {algorithm!r}: {exc}") from None


def parse_algorithm(algorithm: str) -> tuple[str, dict[str, Any]]:
    """``NAME`` or ``NAME@KEY=VALUE,...`` -> (name, options), each option checked against
    the keywords and type hints of the policy's constructor (:func:`policy_options`).

    The spec is one string so that every surface that carries an algorithm name (the CLI,
    TOML, sweeps, a record, the networked mission data, the environments) carries a
    policy's settings with it, unchanged. Values: ``true``/``false``, ``none``, numbers,
    or bare text (``follow=walls``)."""
    name, at, rest = algorithm.strip().partition("@")
    if name == "optimal":  # a plan of the whole mission, not a policy an agent runs
        raise InputError("'optimal' is the exact MILP plan of the whole mission, not an online"
                         " policy: run it with swarmex.run('traversal', algorithm='optimal')"
                         " or swarmex traverse --algorithm optimal")
    if name not in POLICIES:
        known = ", ".join(sorted(POLICIES))
        raise InputError(f"unknown traversal algorithm {name!r} (choose from {known}; "
                         "or optimal, the exact plan, in swarmex.run and swarmex traverse)")
    if not at:
        return name, {}
    accepted = policy_options(POLICIES[name])
    listed = ", ".join(accepted) or "none"
    options: dict[str, Any] = {}
    for item in rest.split(","):
        key, eq, text = (part.strip() for part in item.partition("="))
        if not eq or not key:
            raise InputError(f"algorithm {algorithm!r}: expected KEY=VALUE after '@', "
                             f"got {item.strip()!r}")
        if key not in accepted:
            raise InputError(f"algorithm {algorithm!r}: {name} has no option {key!r} "
                             f"(its options: {listed})")
        if key in options:
            raise InputError(f"algorithm {algorithm!r}: option {key!r} given twice")
        options[key] = _option_value(algorithm, key, text, accepted[key])
    return name, options


def canonical_algorithm(algorithm: str) -> str:
    """The spec with its options in the constructor's order and values spelled one way, so
    that equal settings give equal records (``madgta-f@keep=False,ils=60`` ->
    ``madgta-f@ils=60,keep=false``)."""
    name, options = parse_algorithm(algorithm)
    if not options:
        return name
    order = list(policy_options(POLICIES[name]))
    items = sorted(options.items(), key=lambda kv: order.index(kv[0]))
    return name + "@" + ",".join(f"{k}={_spell(v)}" for k, v in items)


def policy_options(cls: type[Madgta]) -> dict[str, tuple[Any, ...]]:
    """The keywords a policy class takes -> the types each accepts (empty: any), its own
    constructor's first, then those its ``**options`` hand to a parent's. Cached: a class's
    signature does not change, and every spec read (each record, each episode) asks."""
    if cls not in _OPTIONS:
        _OPTIONS[cls] = _read_options(cls)
    return _OPTIONS[cls]


_OPTIONS: dict[type[Madgta], dict[str, tuple[Any, ...]]] = {}


def _read_options(cls: type[Madgta]) -> dict[str, tuple[Any, ...]]:
    accepted: dict[str, tuple[Any, ...]] = {}
    for klass in cls.__mro__:
        init = klass.__dict__.get("__init__")
        if init is None:
            continue
        hints = typing.get_type_hints(init)
        passes_on = False
        for key, param in list(inspect.signature(init).parameters.items())[1:]:
            if param.kind is param.VAR_KEYWORD:
                passes_on = True
            elif param.kind is not param.VAR_POSITIONAL:
                hint = hints.get(key)
                accepted.setdefault(key, (typing.get_args(hint) or (hint,)) if hint else ())
        if not passes_on:
            break
    return accepted


def _option_value(algorithm: str, key: str, text: str, types: tuple[Any, ...]) -> Any:
    """``text`` read as the value of option ``key`` (one of ``types``)."""
    lowered = text.lower()
    value: Any
    if lowered in ("true", "false"):
        value = lowered == "true"
    elif lowered == "none":
        value = None
    else:
        try:
            value = ast.literal_eval(text)
        except (ValueError, SyntaxError):
            value = text  # bare text: follow=walls
    if isinstance(value, int) and not isinstance(value, bool) and float in types:
        value = float(value)
    if isinstance(value, str) and float in types:  # nan, inf: numbers, but not finite ones
        with contextlib.suppress(ValueError):
            value = float(value)
    if isinstance(value, float) and not math.isfinite(value):  # 1e400 reads as inf
        raise InputError(f"algorithm {algorithm!r}: option {key!r} must be a finite number, "
                         f"got {text!r}")
    if types and not any(_is(value, t) for t in types) and str in types:
        value = text  # idle=-1: the class's own check names the words it takes
    if types and not any(_is(value, t) for t in types):
        wanted = " or ".join("none" if t is type(None) else t.__name__ for t in types)
        raise InputError(f"algorithm {algorithm!r}: option {key!r} must be {wanted}, "
                         f"got {text!r}")
    return value


def _is(value: Any, kind: Any) -> bool:
    if kind is type(None):
        return value is None
    if kind in (int, float) and isinstance(value, bool):
        return False
    return isinstance(kind, type) and isinstance(value, kind)


def _spell(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "none"
    return value if isinstance(value, str) else repr(value)
