"""Foraging (seed 002, Azad 2015): n robots find food on a g×g grid, tell each other, and
carry k units to the nest. See docs/foraging.md for every modelling choice."""

from swarmex.missions.foraging.patterns import ALGORITHMS, THESIS_ALGORITHMS, build_plan
from swarmex.missions.foraging.replay import replay
from swarmex.missions.foraging.run import ForageRun, run_forage, to_record
from swarmex.missions.foraging.timed import timed_plan
from swarmex.missions.foraging.transport import TRANSPORTS

__all__ = [
    "ALGORITHMS",
    "THESIS_ALGORITHMS",
    "TRANSPORTS",
    "ForageRun",
    "build_plan",
    "replay",
    "run_forage",
    "timed_plan",
    "to_record",
]
