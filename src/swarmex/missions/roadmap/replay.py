"""Independent replay of a roadmap result record against its world.

Uses only the JSON record and the world's STRtree route (not the prepared union the planners
use), and checks: every trajectory starts at its agent's start with t = 0 and strictly
increasing integer steps; every segment is collision-free and is either a roadmap edge or one
of the listed legs (entry legs, goal legs); and that the claims hold — a complete WMA-RRT
coverage traversed every edge (counted from the trajectories, not from the board), a complete
search left every agent on the goal, a found goal was reached by someone.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from swarmex.missions.roadmap.params import GRAPH_PLANNERS
from swarmex.worlds.polygon import PolygonWorld

TOL = 1e-6


def _key(a: np.ndarray, b: np.ndarray) -> tuple:
    pa, pb = tuple(np.round(a / TOL).astype(np.int64)), tuple(np.round(b / TOL).astype(np.int64))
    return (pa, pb) if pa <= pb else (pb, pa)


def replay_problems(record: dict[str, Any], world: PolygonWorld) -> list[str]:
    problems: list[str] = []
    rm = record["roadmap"]
    nodes = np.asarray(rm["nodes"], dtype=np.float64)
    edges = np.asarray(rm["edges"], dtype=np.int64).reshape(-1, 2)
    edge_of = {_key(nodes[u], nodes[v]): e for e, (u, v) in enumerate(edges.tolist())}
    leg_keys = {_key(np.asarray(a), np.asarray(b)) for a, b in rm.get("legs", [])}
    starts = record["params"].get("starts")
    counts = np.zeros(len(edges), dtype=np.int64)
    seg_a, seg_b, where = [], [], []
    for ag in record["agents"]:
        tr = np.asarray(ag["trajectory"], dtype=np.float64).reshape(-1, 3)
        i = ag["id"]
        if not len(tr) or tr[0, 0] != 0:
            problems.append(f"agent {i}: trajectory does not start at t=0")
            continue
        if starts is not None and np.hypot(*(tr[0, 1:] - starts[i])) > TOL:
            problems.append(f"agent {i}: first position is not its start")
        if np.any(np.diff(tr[:, 0]) <= 0) or np.any(tr[:, 0] != np.round(tr[:, 0])):
            problems.append(f"agent {i}: steps are not strictly increasing integers")
        for j in range(1, len(tr)):
            a, b = tr[j - 1, 1:], tr[j, 1:]
            k = _key(a, b)
            if k in edge_of:
                counts[edge_of[k]] += 1
            elif k not in leg_keys:
                problems.append(f"agent {i}: step {int(tr[j, 0])} is neither an edge nor a leg")
            seg_a.append(a)
            seg_b.append(b)
            where.append((i, int(tr[j, 0])))
    if seg_a:
        ok = world.segments_free_by_tree(np.array(seg_a), np.array(seg_b))
        for (i, t) in np.asarray(where)[~ok]:
            problems.append(f"agent {i}: step {t} collides with an obstacle")
    m = record["metrics"]
    task = record["params"].get("task")
    goal = record.get("goal")
    finals = [np.asarray(ag["trajectory"][-1][1:]) for ag in record["agents"]]
    at_goal = [goal is not None and np.hypot(*(f - goal)) <= TOL for f in finals]
    if record["complete"] and task == "coverage" and record["algorithm"] not in GRAPH_PLANNERS:
        missing = int((counts == 0).sum())
        if missing:
            problems.append(f"complete coverage claimed but {missing} edges never traversed")
    if record["complete"] and task == "search" and m["goal_found"] and not all(at_goal):
        problems.append("complete search claimed but not every agent ends on the goal")
    if m.get("goal_found") and not any(at_goal):
        problems.append("goal_found claimed but no agent reached the goal")
    return problems
