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

from swarmex.missions.exploration.params import ExplorationParams, parse_starts
from swarmex.missions.exploration.sim import ExplorationRun, run_exploration
from swarmex.missions.exploration.strategies import STRATEGIES

__all__ = ["STRATEGIES", "ExplorationParams", "ExplorationRun", "parse_starts", "run_exploration"]
