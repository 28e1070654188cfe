"""Seed 003's exploration mission: robots with lasers map an unknown grid over a mesh.

* :mod:`.messages`, :mod:`.belief`, :mod:`.robot` — the policy side (what a robot knows,
  says and does); the networked runtime can drive the same objects;
* :mod:`.strategies` — goal choice: greedy, the thesis's greedy-exclusion, and Burgard's
  utility, MinPos and Hungarian assignment;
* :mod:`.paths` — inflation, step fields and paths on one robot's map;
* :mod:`.params`, :mod:`.sim` — parameters (the Mission contract's Params) and the simulator
  (truth, lasers, radio, clock);
* :mod:`.record` — metrics and the DESIGN.md result record;
* :mod:`.frames` — the per-tick snapshots ``on_frame`` receives and animations draw;
* :mod:`.mission` — the mission behind the contract (world loading and checks, run, record).
"""

# Exports load on first use (PEP 562), so that importing one module of this package (its
# Params, for the command line's options) does not import the simulator and its kernels.
from importlib import import_module as _import_module
from typing import Any as _Any

_EXPORTS = {
    "ExplorationParams": "params",
    "parse_starts": "params",
    "ExplorationRun": "sim",
    "run_exploration": "sim",
    "STRATEGIES": "strategies",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> _Any:
    if name in _EXPORTS:
        return getattr(_import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
