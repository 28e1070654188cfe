"""WMA-RRT construction (seed 004 §2): Main Root, Secondary Roots, n-branch RRT growth.

1. **Main Root M.** Convex hull of the start positions (obstacles ignored). A "diameter" is
   read as a *diagonal*: a segment between two non-adjacent hull vertices (sides meet only at
   agents' own positions, so they cannot be meant). Candidate pairs are diagonals that cross
   properly (four distinct vertices, interleaved around the hull), ranked by decreasing total
   length; M is the crossing of the first pair whose crossing is collision-free and sees
   every start (the segments start → M become the first part of each agent's path, so they
   must be free too). This is the paper's "replace the current longest diameters by the next
   two ones", made total: the literal "#3 and #4" is undefined when #1 and #2 share a vertex,
   which is common. Only the 40 longest diagonals are ranked (≥ 780 pairs; plenty for teams).
   Fallback — hull with fewer than 4 vertices (n ≤ 3, collinear or repeated starts), no
   crossing pair, or every crossing blocked: the centroid of the hull (its midpoint for a
   segment, the point itself for one start); if that is blocked or does not see all
   starts, the nearest point that is valid on rings of radius ε/4, ε/2, … around it. If none
   exists within twice the hull diameter + 4ε the starts are too scattered: InputError.
2. **Secondary Roots.** ``s_i = M + min(ε, |P_i − M|) · unit(P_i − M)``: at most ε from M
   along M → P_i (so M–s_i is free, being part of the free P_i–M). A start exactly at M gets
   the first free direction among angles 2πi/n + jπ/8. When two agents are collinear with M on
   the same side, the later root is pulled halfway back towards M (repeatedly) so roots stay
   distinct nodes.
3. **Growth.** RRT from all Secondary Roots at once (:func:`swarmex.planning.rrt.grow_rrt`),
   M excluded from nearest-neighbour search, so it is never expanded and keeps exactly n
   edges. ``K`` (``--nodes``) counts the Secondary Roots plus grown nodes; M is extra (so
   ``K ≥ n`` is the only constraint). Each extension steps exactly ε.

Node 0 is M, nodes 1..n the Secondary Roots; every other node's parent is an older node, so
edge ``v − 1`` is ``(parent[v], v)`` and branch k's first edge is edge k.
"""

from __future__ import annotations

from typing import cast

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from swarmex.errors import InputError
from swarmex.planning.roadmap import Roadmap
from swarmex.planning.rrt import grow_rrt
from swarmex.worlds.polygon import PolygonWorld

TOP_DIAGONALS = 40


def _valid_roots(world: PolygonWorld, cand: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Which candidate points are free and see every start along a free segment."""
    cand = np.asarray(cand, dtype=np.float64).reshape(-1, 2)
    ok = world.points_free(cand)
    if ok.any():
        idx = np.flatnonzero(ok)
        a = np.repeat(cand[idx], len(starts), axis=0)
        b = np.tile(starts, (len(idx), 1))
        seg_ok = world.segments_free(a, b).reshape(len(idx), len(starts)).all(axis=1)
        ok[idx] = seg_ok
    return ok


def _hull_vertices(starts: np.ndarray) -> tuple[np.ndarray, BaseGeometry]:
    # an (n, 2) array of coordinates makes one MultiPoint, not an array of them
    hull = shapely.convex_hull(cast(shapely.MultiPoint, shapely.multipoints(starts)))
    if isinstance(hull, shapely.Polygon):
        return np.asarray(hull.exterior.coords)[:-1], hull
    return np.zeros((0, 2)), hull


def crossing_candidates(verts: np.ndarray) -> list[tuple[np.ndarray, tuple[int, int, int, int]]]:
    """Crossings of properly crossing hull diagonals, by decreasing total diagonal length."""
    k = len(verts)
    if k < 4:
        return []
    diags = [(a, b) for a in range(k) for b in range(a + 2, k) if not (a == 0 and b == k - 1)]
    lengths = np.array([np.hypot(*(verts[b] - verts[a])) for a, b in diags])
    order = sorted(range(len(diags)), key=lambda i: (-lengths[i], diags[i]))[:TOP_DIAGONALS]
    pairs = []
    for x, i in enumerate(order):
        a, b = diags[i]
        for j in order[x + 1 :]:
            c, d = diags[j]
            if len({a, b, c, d}) < 4 or (a < c < b) == (a < d < b):
                continue  # shared vertex, or not interleaved around the hull: no crossing
            pairs.append((-(lengths[i] + lengths[j]), diags[i] + diags[j]))
    pairs.sort()
    out = []
    for _, (a, b, c, d) in pairs:
        p, r = verts[a], verts[b] - verts[a]
        q, s = verts[c], verts[d] - verts[c]
        qp = q - p
        t = (qp[0] * s[1] - qp[1] * s[0]) / (r[0] * s[1] - r[1] * s[0])  # never parallel
        out.append((p + t * r, (a, b, c, d)))
    return out


def main_root(world: PolygonWorld, starts: np.ndarray, step: float) -> tuple[np.ndarray, str]:
    """The Main Root and the rule that produced it ("diagonals" / "centroid" / "near-centroid")."""
    starts = np.asarray(starts, dtype=np.float64).reshape(-1, 2)
    verts, hull = _hull_vertices(starts)
    for point, _ in crossing_candidates(verts):
        if _valid_roots(world, point, starts)[0]:
            return point, "diagonals"
    centre = np.asarray(hull.centroid.coords[0]) if not hull.is_empty else starts[0]
    if _valid_roots(world, centre, starts)[0]:
        return centre, "centroid"
    diam = float(np.max(np.hypot(*(starts[:, None] - starts[None]).transpose(2, 0, 1))))
    reach = 2.0 * diam + 4.0 * step
    ring_step = step / 4.0
    for j in range(1, int(reach / ring_step) + 1):
        m = 8 * j
        ang = 2.0 * np.pi * np.arange(m) / m
        ring = centre + j * ring_step * np.column_stack([np.cos(ang), np.sin(ang)])
        ok = _valid_roots(world, ring, starts)
        if ok.any():
            return ring[int(np.flatnonzero(ok)[0])], "near-centroid"
    raise InputError(
        "no Main Root: no collision-free point near the start cluster sees every start "
        "(are the starts separated by walls?)"
    )


def secondary_roots(
    world: PolygonWorld, root: np.ndarray, starts: np.ndarray, step: float
) -> np.ndarray:
    n = len(starts)
    out = np.empty((n, 2))
    for i, p in enumerate(starts):
        d = p - root
        dist = float(np.hypot(*d))
        if dist > 1e-9 * max(1.0, step):
            s = root + min(step, dist) * d / dist
        else:
            s = None
            for j in range(16):
                a = 2.0 * np.pi * i / n + j * np.pi / 8.0
                c = root + step * np.array([np.cos(a), np.sin(a)])
                if world.segment_free(*root, *c):
                    s = c
                    break
            if s is None:
                raise InputError(f"start {i} sits on the Main Root and no direction is free")
        for _ in range(60):  # pull back along the ray while another root is in the way
            if i == 0 or np.min(np.hypot(*(out[:i] - s).T)) > 1e-9 * max(1.0, step):
                break
            s = root + 0.5 * (s - root)
        out[i] = s
    return out


def build_wma_rrt(
    world: PolygonWorld,
    starts: np.ndarray,
    n_nodes: int,
    step: float,
    rng: np.random.Generator,
    *,
    exact_step: bool = True,
    count_samples: bool = False,
) -> Roadmap:
    """The WMA-RRT with ``n_nodes`` accepted nodes (see the module docstring).

    Two other readings of seed 004 are options, for the study in the reproduction report:
    ``exact_step=False`` stops ``q_new`` at ``q_rand`` when it is nearer than ε, and
    ``count_samples=True`` reads ``n_nodes`` as the number of sample points drawn (Fig. 6's
    "number of sample points"), so rejected samples count too and the tree is smaller.
    """
    starts = np.asarray(starts, dtype=np.float64).reshape(-1, 2)
    n = len(starts)
    if n < 1:
        raise InputError("WMA-RRT needs at least one agent")
    if n_nodes < n:
        raise InputError(f"--nodes {n_nodes} is fewer than the {n} agents (one root each)")
    if not step > 0:
        raise InputError(f"--step must be positive, got {step}")
    root, rule = main_root(world, starts, step)
    sec = secondary_roots(world, root, starts, step)
    # counting draws: stop after n_nodes samples, however many were accepted
    total, draws = (n + n_nodes, n_nodes) if count_samples else (n_nodes, None)
    pos, par, lab, drawn = grow_rrt(world, sec, np.arange(n), total, step, rng,
                                    max_samples=draws, exact_step=exact_step)
    if not count_samples and len(pos) < total:
        # growth ran out of its draws (200 per node) with the tree short: a step this long
        # leaves the free space nearly every time, and the run would cover a stub and call it
        # complete
        xmin, ymin, xmax, ymax = world.bounds
        raise InputError(
            f"--step {step:g}: the WMA-RRT grew {len(pos) - n} of the {total - n} nodes it"
            f" needed beyond the {n} roots in {drawn:,} samples; steps this long seldom stay"
            f" in the free space of this {xmax - xmin:g} × {ymax - ymin:g} world (give a"
            " shorter --step)"
        )
    # shift by one so node 0 is the Main Root; Secondary Roots hang from it
    pos = np.vstack([root, pos])
    parent = np.concatenate([[-1], np.where(par < 0, 0, par + 1)])
    branch = np.concatenate([[-1], lab])
    v = np.arange(1, len(pos))
    edges = np.column_stack([parent[v], v])
    return Roadmap(
        kind="wma-rrt",
        pos=pos,
        edges=edges,
        starts=starts,
        entry_node=np.zeros(n, dtype=np.int64),
        parent=parent,
        branch=branch,
        first_edge=np.arange(n, dtype=np.int64),
        samples=drawn,
        info={"main_root_rule": rule, "requested_nodes": int(n_nodes)},
    )
