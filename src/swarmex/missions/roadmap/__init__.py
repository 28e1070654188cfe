"""Seed 004: coverage and goal search by a team on a WMA-RRT roadmap, against a PRM baseline.

Modules: :mod:`.blackboard` (the shared roadmap arrays), :mod:`.wma_policy` and
:mod:`.prm_policy` (what one agent decides per step), :mod:`.sim` (the run loop and sensing),
:mod:`.record` (the result record), :mod:`.replay` (independent checking of a record),
:mod:`.starts` (default start clusters, start and goal checks), :mod:`.params` and
:mod:`.mission` (the mission behind the contract: ``swarmex.run("roadmap", ...)``).
"""

# Exports load on first use (PEP 562), so that importing one module of this package (its
# Params, for the command line's options) does not import the simulator and its kernels.
from importlib import import_module as _import_module
from typing import Any as _Any

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
    if name in _EXPORTS:
        return getattr(_import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
