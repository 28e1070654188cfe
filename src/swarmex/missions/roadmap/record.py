"""RoadmapRun → the DESIGN.md result record (mission "roadmap", world kind "polygons").

Besides the common fields the record carries the roadmap itself (nodes, edges, branches, the
entry and goal legs) and the per-edge traversal counts, so that an independent checker can
replay every trajectory (see :mod:`swarmex.missions.roadmap.replay`) and see the PRM's
components and loops for itself.

Metric definitions: ``coverage`` = seen free raster cells / free raster cells; ``steps`` = the
step at which the run ended; ``edge_revisits`` = Σ over edges of traversals beyond the two of
a depth-first search (down and back), so a lone WMA-RRT agent scores 0 and every extra pass —
a helper re-walking, a PRM loop — counts; ``cycles`` = E − V + components of the roadmap.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from swarmex.engine.record import AgentRecord, MetricInfo, ResultRecord
from swarmex.missions.roadmap.blackboard import PRMBoard, WMABoard
from swarmex.missions.roadmap.sim import RoadmapRun


def legs(run: RoadmapRun) -> list[list[list[float]]]:
    """Every straight segment agents may use besides roadmap edges."""
    rm, b = run.roadmap, run.board
    out = [[p.tolist(), rm.pos[e].tolist()] for p, e in zip(rm.starts, rm.entry_node,
                                                             strict=True) if e >= 0]
    if b.anchor is not None:
        pts = [rm.pos[b.anchor], *b.leg]
        out += [[a.tolist(), c.tolist()] for a, c in zip(pts[:-1], pts[1:], strict=True)]
    return out


#: The team metrics of a roadmap record (``record.metrics``); lengths in world units, times
#: in steps. The ``branch*`` and ``main_root_rule`` metrics are WMA-RRT's, ``edges_reachable``
#: and ``agents_off_roadmap`` PRM's. A test holds this equal to what the runs write.
TEAM_METRICS: dict[str, MetricInfo] = {
    "coverage": MetricInfo("share of the free area the agents' sensors swept"),
    "goal_found": MetricInfo("search: whether the goal was sighted"),
    "goal_unreachable": MetricInfo("search: every branch ended without a sighting"),
    "steps": MetricInfo("steps the run took"),
    "path_length": MetricInfo("length walked, all agents"),
    "path_length_max": MetricInfo("the longest agent's walk"),
    "tree_nodes": MetricInfo("roadmap nodes"),
    "tree_edges": MetricInfo("roadmap edges"),
    "components": MetricInfo("connected components of the roadmap"),
    "cycles": MetricInfo("independent cycles of the roadmap (E − V + C; 0 for a tree)"),
    "edge_revisits": MetricInfo("edge traversals beyond two per edge"),
    "edges_traversed": MetricInfo("edges walked at least once"),
    "samples": MetricInfo("random samples drawn to build the roadmap"),
    "found_step": MetricInfo("search: step of the first sighting (-1: none)"),
    "found_by": MetricInfo("search: the agent that sighted the goal (-1: none)"),
    "all_at_goal_step": MetricInfo("search: step when every agent stood at the goal (-1: never)"),
    "step_budget": MetricInfo("the run's step limit"),
    "budget_exhausted": MetricInfo("whether the run stopped at the step limit"),
    "branches": MetricInfo("WMA-RRT: branches of the tree (one per agent)"),
    "branches_completed": MetricInfo("WMA-RRT: branches finished"),
    "branch_edges": MetricInfo("WMA-RRT: edges per branch", numeric=False),
    "main_root_rule": MetricInfo("WMA-RRT: how the Main Root was placed", numeric=False),
    "edges_reachable": MetricInfo("PRM: edges in the components the agents can enter"),
    "agents_off_roadmap": MetricInfo("PRM: agents with no visible roadmap node to enter"),
}


def run_metrics(run: RoadmapRun) -> dict[str, Any]:
    rm, b = run.roadmap, run.board
    trav = np.asarray(b.traversals)
    m: dict[str, Any] = {
        "coverage": round(run.raster.coverage(), 6),
        "goal_found": run.goal_found,
        "goal_unreachable": run.goal_unreachable,
        "steps": run.steps,
        "path_length": round(float(run.path_length.sum()), 6),
        "path_length_max": round(float(run.path_length.max()), 6) if len(run.path_length) else 0,
        "tree_nodes": rm.n_nodes,
        "tree_edges": rm.n_edges,
        "components": rm.components,
        "cycles": rm.cycles,
        "edge_revisits": int(np.maximum(trav - 2, 0).sum()),
        "edges_traversed": int((trav > 0).sum()),
        "samples": rm.samples,
        "found_step": b.found_step,
        "found_by": b.found_by,
        "all_at_goal_step": run.all_at_goal_step,
        "step_budget": run.step_budget,
        "budget_exhausted": run.budget_exhausted,
    }
    if isinstance(b, WMABoard):
        m["branches"] = len(b.weight)
        m["branches_completed"] = int((b.completed_at >= 0).sum())
        m["branch_edges"] = np.bincount(b.branch_of_edge, minlength=len(b.weight)).tolist()
        m["main_root_rule"] = rm.info.get("main_root_rule")
    else:
        reach = set(rm.component_labels[rm.entry_node[rm.entry_node >= 0]].tolist())
        in_reach = np.isin(rm.component_labels[rm.edges[:, 0]], list(reach))
        m["edges_reachable"] = int(in_reach.sum())
        m["agents_off_roadmap"] = int((rm.entry_node < 0).sum())
    return m


def build_record(run: RoadmapRun, params: dict[str, Any], seed: int,
                 wall_seconds: float) -> ResultRecord:
    rm, b = run.roadmap, run.board
    agents = []
    for i, a in enumerate(run.agents):
        am: dict[str, Any] = {
            "path_length": round(float(run.path_length[i]), 6),
            "moves": int(run.moves[i]),
            "final_state": a.state,
            "reached_goal": a.state == "at-goal",
        }
        if hasattr(a, "branches_entered"):
            am["branches_entered"] = a.branches_entered
        agents.append(AgentRecord(id=i, metrics=am, trajectory=run.trajectories[i]))
    board: dict[str, Any] = {"edge_traversals": np.asarray(b.traversals).tolist(),
                             "edge_weights": np.asarray(b.w_g).tolist()}
    if isinstance(b, WMABoard):
        board.update({"Weight": b.weight.tolist(), "Sync": b.sync.tolist(),
                      "completed_at": b.completed_at.tolist()})
    elif isinstance(b, PRMBoard):
        board["trail"] = {str(k): v[0] for k, v in sorted(b.trail_next.items())}
    roadmap = rm.to_record()
    roadmap["legs"] = legs(run)
    world = run.world.describe()
    world["free_cells"] = run.raster.free_cells
    world["raster"] = run.raster.describe()
    curve = run.raster.curve(run.steps)
    return ResultRecord(
        mission="roadmap",
        algorithm=run.planner,
        params=params,
        seed=seed,
        world=world,
        complete=run.complete,
        makespan=float(run.steps),
        time_unit="step",
        metrics=run_metrics(run),
        agents=agents,
        wall_seconds=wall_seconds,
        extra={
            "roadmap": roadmap,
            "board": board,
            "goal": None if run.goal is None else run.goal.tolist(),
            "coverage_curve": [round(c, 5) for c in curve],
        },
    )


def range_label(r: float) -> str | float:
    return "inf" if math.isinf(r) else r
