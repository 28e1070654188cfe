"""The roadmap mission's run loop: rounds of one move per agent, in a seeded order.

Time is counted in steps; in step t every agent makes at most one move (one roadmap edge, the
entry leg from its start onto the roadmap, or one segment of the leg to the goal), and the
agents act one after another in an order drawn from the run's generator: each agent's step is
a critical section, so two agents at one node can never take the same 0-weight edge (Fig. 4).

Where agents begin (the paper's agents start at the "origin", the Main Root, yet stand at
P_i): each agent first walks its entry leg P_i → Main Root (one step, sensed, recorded as a
leg), registered in its own branch from t = 0 (Fig. 2: Sync[i] = 1); PRM walkers walk to the
nearest node they can see.

The engine owns the truth: after a move it sweeps the agent's sensor along the segment
(coverage raster, line of sight, range R; an edge is swept once, a second pass sees nothing
new) and, in goal search, checks whether the goal came into view, then tells the agent.

Ends: WMA-RRT coverage when every branch is COMPLETE; WMA-RRT search when every agent stands on
the goal, or when every branch is COMPLETE with no ½ flag (the agents have established that the
goal is unreachable from where they are, Figs. 14–16). PRM agents have no such knowledge, so
their runs end at the step budget (or, in search, when all stand on the goal).

Frames: with ``on_frame`` the loop hands a :class:`RoadmapFrame` to the callback after the
initial sensing (step 0) and after every step; a callback that raises
:class:`~swarmex.missions.base.StopRun` ends the run there (incomplete, unless that very step
had met the end condition). Without it the loop does exactly the same work as before.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from swarmex.errors import InputError
from swarmex.missions.base import StopRun
from swarmex.missions.roadmap.blackboard import PRMBoard, WMABoard
from swarmex.missions.roadmap.params import GRAPH_PLANNERS, PLANNERS, TASKS
from swarmex.missions.roadmap.prm_policy import PRMWalker
from swarmex.missions.roadmap.wma_policy import RULES, Move, WMAAgent
from swarmex.planning.prm import build_prm
from swarmex.planning.roadmap import Roadmap
from swarmex.planning.rrt_wma import build_wma_rrt
from swarmex.sensing.coverage_raster import DEFAULT_CELLS, CoverageRaster
from swarmex.worlds.polygon import PolygonWorld

__all__ = ["PLANNERS", "TASKS", "RoadmapFrame", "RoadmapRun", "build_roadmap", "run_roadmap"]


@dataclass(frozen=True)
class RoadmapFrame:
    """One moment of a roadmap run, as it happens: what a live view needs to draw it.

    ``roadmap`` is the run's roadmap (the same object in every frame; with the world it is
    the static part of the picture); the arrays are copies, safe to keep.
    """

    step: int  # 0 after the initial sensing, then t after step t
    positions: np.ndarray  # (n, 2) every agent's position
    states: tuple[str, ...]  # each agent's state (entry, explore, free, ..., at-goal)
    moved: tuple[int, ...]  # the agents that moved in this step, in the order they acted
    edge_traversals: np.ndarray  # (E,) traversals of each roadmap edge so far
    coverage: float  # seen free raster cells / free raster cells
    goal_found: bool
    roadmap: Roadmap


def _frame(t: int, agents: list[Any], moved: list[int], board: WMABoard | PRMBoard,
           raster: CoverageRaster, rm: Roadmap) -> RoadmapFrame:
    return RoadmapFrame(
        step=t,
        positions=np.array([a.xy for a in agents], dtype=np.float64).reshape(-1, 2),
        states=tuple(str(a.state) for a in agents),
        moved=tuple(moved),
        edge_traversals=np.array(board.traversals, copy=True),
        coverage=raster.coverage(),
        goal_found=board.anchor is not None,
        roadmap=rm,
    )


@dataclass
class RoadmapRun:
    world: PolygonWorld
    roadmap: Roadmap
    task: str
    planner: str
    sensor_range: float
    goal: np.ndarray | None
    raster: CoverageRaster
    board: WMABoard | PRMBoard
    agents: list[Any]
    trajectories: list[list[list[float]]]
    path_length: np.ndarray
    moves: np.ndarray
    steps: int
    complete: bool
    goal_found: bool
    goal_unreachable: bool
    all_at_goal_step: int
    step_budget: int
    budget_exhausted: bool
    build_seconds: float
    sim_seconds: float
    extra: dict[str, Any] = field(default_factory=dict)


def build_roadmap(world: PolygonWorld, planner: str, starts: np.ndarray, nodes: int,
                  step: float, rng: np.random.Generator) -> Roadmap:
    if planner == "prm":
        return build_prm(world, starts, nodes, step, rng)
    if planner == "ompl-prm":  # the same node budget; OMPL's PRM has no step
        from swarmex.planning.ompl import build_ompl_prm

        return build_ompl_prm(world, starts, nodes, rng)
    return build_wma_rrt(world, starts, nodes, step, rng)


def run_roadmap(
    world: PolygonWorld,
    starts: np.ndarray,
    *,
    task: str = "coverage",
    planner: str = "wma-rrt",
    nodes: int = 400,
    step: float = 20.0,
    sensor_range: float = float("inf"),
    goal: np.ndarray | None = None,
    seed: int = 0,
    step_budget: int | None = None,
    raster_cells: int = DEFAULT_CELLS,
    roadmap: Roadmap | None = None,
    on_frame: Callable[[RoadmapFrame], Any] | None = None,
    raster: CoverageRaster | None = None,
    decide: Callable[[Any, int, np.random.Generator], Move | None] | None = None,
) -> RoadmapRun:
    """Build the roadmap (unless given) and run the behaviour; one generator from ``seed``.

    ``on_frame`` (optional) is called with a :class:`RoadmapFrame` at step 0 and after every
    step; raising StopRun from it ends the run after that step. ``raster`` (optional) is a
    fresh :class:`CoverageRaster` to sense into instead of one made here (whoever passes it can
    read the coverage as the run goes). ``decide`` (optional, the envs' decision hook) is
    called as ``decide(agent, t, rng)`` in place of ``agent.decide(t, rng)``, for every agent
    in every step, and returns that agent's move for the step (what ``agent.decide`` would
    return, or another move open to the agent).
    """
    if task not in TASKS:
        raise InputError(f"--task must be one of {', '.join(TASKS)}, got {task!r}")
    if planner not in PLANNERS:
        raise InputError(f"--planner must be one of {', '.join(PLANNERS)}, got {planner!r}")
    if task == "search" and goal is None:
        raise InputError("--task search needs a goal (--goal x,y or 'goal' in the file)")
    rng = np.random.default_rng(seed)
    starts = np.asarray(starts, dtype=np.float64).reshape(-1, 2)
    t0 = time.perf_counter()
    rm = roadmap if roadmap is not None else build_roadmap(world, planner, starts, nodes, step,
                                                           rng)
    t1 = time.perf_counter()
    n = len(starts)
    if raster is None:
        raster = CoverageRaster(world, sensor_range, raster_cells)
    board: WMABoard | PRMBoard
    if planner in GRAPH_PLANNERS:  # the same walkers on the project's PRM and on OMPL's
        board = PRMBoard(rm)
        agents: list[Any] = [PRMWalker(i, starts[i], rm.entry_node[i], board) for i in range(n)]
        budget = 2 * max(nodes, rm.n_nodes) if step_budget is None else int(step_budget)
    else:
        board = WMABoard(rm, n)
        agents = [WMAAgent(i, starts[i], board, RULES[planner])
                  for i in range(n)]
        # a safety net only: a tree DFS needs at most 2E moves per entry, n entries per agent
        budget = (2 * rm.n_edges + 4) * (n + 1) + 10 if step_budget is None else step_budget
    goal_xy = None if goal is None else np.asarray(goal, dtype=np.float64)
    sensed = np.zeros(rm.n_edges, dtype=bool)
    traj = [[[0.0, float(p[0]), float(p[1])]] for p in starts]
    length = np.zeros(n)
    moves = np.zeros(n, dtype=np.int64)
    for a in agents:  # t = 0: what each agent sees where it stands
        raster.sense_segment(a.xy, a.xy, 0)
    t = 0
    ended = False
    unreachable = False
    all_at_goal = -1
    stopped = False
    wants = getattr(on_frame, "wants", None)
    if on_frame is not None:
        try:
            on_frame(_frame(0, agents, [], board, raster, rm))
        except StopRun:
            stopped = True
    while t < budget and not ended and not stopped:
        t += 1
        moved: list[int] = []
        for i in rng.permutation(n):
            a = agents[i]
            mv = a.decide(t, rng) if decide is None else decide(a, t, rng)
            if mv is None:
                continue
            src = a.xy
            fresh = mv.edge < 0 or not sensed[mv.edge]
            sight = -1.0
            if fresh:
                if mv.edge >= 0:
                    sensed[mv.edge] = True
                raster.sense_segment(src, mv.to, t)
                if task == "search" and goal_xy is not None and board.anchor is None:
                    sight = raster.sighting(src, mv.to, goal_xy)
            a.arrive(mv, t)
            length[i] += math.hypot(mv.to[0] - src[0], mv.to[1] - src[1])
            moves[i] += 1
            moved.append(int(i))
            traj[i].append([float(t), float(mv.to[0]), float(mv.to[1])])
            if sight >= 0:
                a.found_goal(src + sight * (mv.to - src), goal_xy, t)
        at_goal = board.anchor is not None and all(a.state == "at-goal" for a in agents)
        if task == "search" and at_goal:
            all_at_goal = t
            ended = True
        if isinstance(board, WMABoard) and board.all_complete():  # WMA-RRT planners
            unreachable = task == "search" and board.anchor is None
            ended = True
            for a in agents:  # free agents at the Main Root have nothing left to help
                if a.state in ("free", "wait"):
                    a.state = "done"
        # a callback that only watches (a progress bar) says which steps it wants: a frame
        # copies every edge's count, a cost on large roadmaps
        if on_frame is not None and (wants is None or ended or wants(t)):
            try:
                on_frame(_frame(t, agents, moved, board, raster, rm))
            except StopRun:
                stopped = True
    t2 = time.perf_counter()
    goal_found = task == "search" and board.anchor is not None
    complete = all_at_goal >= 0 if planner in GRAPH_PLANNERS else ended
    return RoadmapRun(
        world=world, roadmap=rm, task=task, planner=planner, sensor_range=sensor_range,
        goal=goal_xy, raster=raster, board=board, agents=agents, trajectories=traj,
        path_length=length, moves=moves, steps=t, complete=bool(complete),
        goal_found=bool(goal_found), goal_unreachable=bool(unreachable),
        all_at_goal_step=all_at_goal, step_budget=int(budget),
        budget_exhausted=bool(not ended and t >= budget), build_seconds=t1 - t0,
        sim_seconds=t2 - t1,
    )
