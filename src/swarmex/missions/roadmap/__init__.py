"""Seed 004: coverage and goal search by a team on a WMA-RRT roadmap, against a PRM baseline.

Modules: :mod:`.blackboard` (the shared roadmap arrays), :mod:`.wma_policy` and
:mod:`.prm_policy` (what one agent decides per step), :mod:`.sim` (the run loop and sensing),
:mod:`.record` (the result record), :mod:`.replay` (independent checking of a record),
:mod:`.starts` (default start clusters, start and goal checks), :mod:`.scenario` (a run
from keyword arguments, as the reproduction calls it), :mod:`.params` and
:mod:`.mission` (the mission behind the contract: ``swarmex.run("roadmap", ...)``).
"""

# exports load on first use (swarmex._lazy: the Params import without the simulator)
from typing import Any as _Any

from swarmex._lazy import lazy_attribute as _lazy_attribute

_EXPORTS = {
    "COMPLETE": "blackboard",
    "HALF": "blackboard",
    "build_record": "record",
    "run_metrics": "record",
    "replay_problems": "replay",
    "PLANNERS": "sim",
    "TASKS": "sim",
    "RoadmapFrame": "sim",
    "RoadmapRun": "sim",
    "run_roadmap": "sim",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> _Any:
    return _lazy_attribute(__name__, _EXPORTS, name)
