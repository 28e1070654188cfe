"""Seed 004: coverage and goal search by a team on a WMA-RRT roadmap, against a PRM baseline.

Modules: :mod:`.blackboard` (the shared roadmap arrays), :mod:`.wma_policy` and
:mod:`.prm_policy` (what one agent decides per step), :mod:`.sim` (the run loop and sensing),
:mod:`.record` (the result record), :mod:`.replay` (independent checking of a record),
:mod:`.starts` (default start clusters, start and goal checks), :mod:`.params` and
:mod:`.mission` (the mission behind the contract: ``swarmex.run("roadmap", ...)``).
"""

from swarmex.missions.roadmap.blackboard import COMPLETE, HALF
from swarmex.missions.roadmap.record import build_record, run_metrics
from swarmex.missions.roadmap.replay import replay_problems
from swarmex.missions.roadmap.sim import PLANNERS, TASKS, RoadmapFrame, RoadmapRun, run_roadmap

__all__ = [
    "COMPLETE",
    "HALF",
    "PLANNERS",
    "TASKS",
    "RoadmapFrame",
    "RoadmapRun",
    "build_record",
    "replay_problems",
    "run_metrics",
    "run_roadmap",
]
