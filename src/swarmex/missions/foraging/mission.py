"""The foraging mission (seed 002) behind the Mission contract.

``prepare`` places the food: the ``food`` cell if given, else a cell drawn from
``numpy.random.default_rng(seed)`` in the ``food_distance`` band (or anywhere but the nest),
so a seed fixes the whole run. ``execute`` plays the pattern's timetable, the communication
phase and the transport (:func:`~swarmex.missions.foraging.run.run_forage`) and builds the
record, whose ``params`` are the grid, team, pattern, transport, communication rule, food cell,
units, nest, the ``food_distance`` as given and the seed.

Frames: ``on_frame`` is called once per round ``t = 0 … makespan`` with a
:class:`~swarmex.missions.foraging.sim.Frame` (robots' cells, who carries, who is informed,
units home and left), the state that row ``t`` of the record shows, as the run plays it. The
compiled transport loop then plays one round per call, so the record is the same as without
``on_frame``. Raising :class:`~swarmex.missions.base.StopRun` ends the run at that round with
``complete`` false (unless the k-th unit was already home).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from swarmex.engine.record import MetricInfo, ResultRecord
from swarmex.missions.base import FrameCallback, Mission, Outcome, Parser, ProgressSpec
from swarmex.missions.foraging.grid import Cell, nest_of
from swarmex.missions.foraging.params import ForagingParams, check_food
from swarmex.missions.foraging.sim import Frame


@dataclass(frozen=True)
class ForagingWorld:
    """A prepared foraging run: the g×g grid (every cell free), its nest and the food cell."""

    grid: int
    nest: Cell
    food: Cell

    @property
    def free(self) -> np.ndarray:
        return np.ones((self.grid, self.grid), dtype=bool)


def world_of(grid: Any, food: Any) -> ForagingWorld:
    """The world of a run whose food cell is known (a record's ``grid`` and ``food``), checked
    as ``--grid`` and ``--food`` are."""
    options = ForagingParams.options()
    parse_grid: Parser = options["grid"].parse
    parse_food: Parser = options["food"].parse
    g = int(parse_grid(grid, "--grid"))
    return ForagingWorld(g, nest_of(g), check_food(parse_food(food, "--food"), g))


class ForagingMission(Mission[ForagingParams, ForagingWorld]):
    name = "foraging"
    command = "forage"
    summary = "Find food on a g×g grid, spread the word, carry k units home (seed 002)."
    params_type = ForagingParams
    time_unit = "step"
    # the food cell was drawn from the seed on that grid unless given: draw it again
    rerun_replaces = {"food": ("food_distance", "grid"), "food_distance": ("food",)}

    def rerun_values(self, record: ResultRecord, given: Collection[str] = ()) -> dict[str, Any]:
        """A food band drawn again from the seed, not its drawn cell (the record has both)."""
        values = super().rerun_values(record, given)
        if values.get("food_distance") is not None and "food" not in given:
            values.pop("food", None)
        return values

    def team_metrics(self) -> Mapping[str, MetricInfo]:
        from swarmex.missions.foraging.run import TEAM_METRICS

        return TEAM_METRICS

    def prepare(self, params: ForagingParams) -> ForagingWorld:
        from swarmex.missions.foraging.food import sample_food

        g = params.grid
        if params.food is not None:
            food = params.food  # checked by ForagingParams.check
        else:
            rng = np.random.default_rng(params.seed)
            food = sample_food(g, params.food_distance or "random", rng)[0]
        return ForagingWorld(g, nest_of(g), food)

    def progress(self, params: ForagingParams, world: ForagingWorld) -> ProgressSpec | None:
        """Robots that know where the food is, then units home (``n + k`` in all).

        Why these two: the search is played from the pattern's timetable, fast even on
        1024² with 1,024 robots; the rounds that take the time are the word's spreading
        and the transport (compiled, one round per frame), and those are what the count
        follows.
        The number of rounds is not known before the run, so it cannot be the total."""
        return ProgressSpec(
            params.agents + params.food_units, "robots told, units home",
            lambda frame: int(frame.informed.sum()) + int(frame.delivered),
        )

    def execute(
        self,
        params: ForagingParams,
        world: ForagingWorld,
        on_frame: FrameCallback | None = None,
        *,
        trace: bool = True,
    ) -> Outcome:
        from swarmex.engine.collector import fewer_collections, no_collections
        from swarmex.engine.record import without_trace
        from swarmex.missions.foraging.run import run_forage, to_record

        p = params
        # a large swarm's run and record are millions of acyclic lists: the collector's
        # passes over them grew as their square (1,024 robots: 11.2 -> 6.8 s CPU)
        with fewer_collections():
            run = run_forage(
                p.algorithm, p.grid, p.agents, world.food, p.food_units, p.transport,
                record=trace, on_frame=on_frame, comm=p.comm, found=p.found,
            )  # fmt: skip
        with no_collections():
            record = to_record(run, p.seed, {"food_distance": p.food_distance, "seed": p.seed})
        if not trace:  # the run kept no per-round positions: a robot's moves are unknown
            record = without_trace(record, derived=("moves",))
        return Outcome(record, run, world)


__all__ = ["ForagingMission", "ForagingWorld", "Frame", "world_of"]
