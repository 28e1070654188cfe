"""Seed 003's exploration mission: robots with lasers map an unknown grid over a mesh.

* :mod:`.messages`, :mod:`.belief`, :mod:`.robot` — the policy side (what a robot knows,
  says and does); the networked runtime can drive the same objects;
* :mod:`.strategies` — goal choice: greedy, the thesis's greedy-exclusion, Burgard's
  utility, MinPos and Hungarian assignment, and ours, hungarian-exclusion and
  adaptive-exclusion;
* :mod:`.paths` — inflation, step fields and paths on one robot's map;
* :mod:`.params`, :mod:`.sim` — parameters (the Mission contract's Params) and the simulator
  (truth, lasers, radio, clock);
* :mod:`.record` — metrics and the DESIGN.md result record;
* :mod:`.frames` — the per-tick snapshots ``on_frame`` receives and animations draw;
* :mod:`.mission` — the mission behind the contract (world loading and checks, run, record).
"""

# exports load on first use (swarmex._lazy: the Params import without the simulator)
from typing import Any as _Any

from swarmex._lazy import lazy_attribute as _lazy_attribute

_EXPORTS = {
    "ExplorationParams": "params",
    "parse_starts": "params",
    "ExplorationRun": "sim",
    "run_exploration": "sim",
    "STRATEGIES": "strategies",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> _Any:
    return _lazy_attribute(__name__, _EXPORTS, name)
