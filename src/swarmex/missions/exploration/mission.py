"""The exploration mission (seed 003) behind the Mission contract.

``prepare`` loads the metric world of ``map`` or ``empty`` (at ``cell`` metres per cell) and
does every check that needs it — the laser against the cell size, the starts against the
walls, room for the team's default group start — before any tick runs; ``execute`` runs the
simulator and builds the record (:func:`~swarmex.missions.exploration.record.exploration_record`).

Frames are :class:`~swarmex.missions.exploration.frames.Snapshot` objects, one per tick. A
callback with a ``wants(t) -> bool`` method (as
:class:`~swarmex.missions.exploration.frames.FrameRecorder` has) is asked first, so no frame
is built that it would drop. Raising :class:`~swarmex.missions.base.StopRun` from the callback
ends the run at that tick.
"""

from __future__ import annotations

import math
import re
from collections.abc import Collection, Mapping
from dataclasses import dataclass, replace
from typing import Any

from swarmex.engine.record import MetricInfo, ResultRecord
from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, Mission, Outcome, ProgressSpec
from swarmex.missions.exploration.params import (
    Cell,
    ExplorationParams,
    default_starts,
    validate,
)
from swarmex.worlds.grid import GridWorld
from swarmex.worlds.mapfiles import is_ros_map
from swarmex.worlds.metric import DEFAULT_CELL, MetricGrid, empty_metric, load_metric


@dataclass
class ExplorationWorld:
    """A prepared exploration: the true metric grid and each robot's start cell."""

    grid: MetricGrid
    starts: tuple[Cell, ...]


def build_world(p: ExplorationParams) -> MetricGrid:
    """The metric grid of ``map`` or ``empty`` (``cell`` metres per cell; a ROS map or a
    MetricGrid has its own resolution, which ``cell`` may only repeat)."""
    if p.empty is not None:
        return empty_metric(*p.empty, DEFAULT_CELL if p.cell is None else p.cell)
    if p.map is None:
        p.check()  # names the missing option
    assert p.map is not None
    if isinstance(p.map, MetricGrid):  # a world object from Python, with its own cell size
        if p.cell is not None and not math.isclose(p.cell, p.map.cell, rel_tol=1e-9):
            raise InputError(
                f"--cell {p.cell:g}: the MetricGrid given as map has {p.map.cell:g} m cells"
                " (omit cell, or pass its GridWorld)"
            )
        return p.map
    if isinstance(p.map, GridWorld):
        return MetricGrid(p.map, DEFAULT_CELL if p.cell is None else p.cell)
    return load_metric(p.map, p.cell)


class ExplorationMission(Mission[ExplorationParams, ExplorationWorld]):
    name = "exploration"
    command = "explore"
    summary = "Explore an unknown world with a team of laser robots sharing scans over a mesh."
    params_type = ExplorationParams
    time_unit = "step"
    rerun_replaces = {"starts": ("robots", "map", "empty", "cell")}  # one per robot, in cells
    world_options = ("map", "empty")

    def rerun_values(self, record: ResultRecord, given: Collection[str] = ()) -> dict[str, Any]:
        """The world back from ``record.world`` (an ``--empty`` size or the map file; the
        record's params leave it out), and an infinite radio back from the record's None."""
        values = super().rerun_values(record, given)
        if "comm_range" in values and values["comm_range"] is None:
            values["comm_range"] = "inf"
        if not {"map", "empty"} & set(given):
            source = str(record.world.get("source", ""))
            size = re.fullmatch(r"empty (\S+)x(\S+) m", source)
            if size:
                values["empty"] = f"{size[1]}x{size[2]}"
            else:
                values["map"] = source
                if is_ros_map(source):
                    values.pop("cell", None)  # a ROS map brings its own resolution
        return values

    def team_metrics(self) -> Mapping[str, MetricInfo]:
        from swarmex.missions.exploration.record import TEAM_METRICS

        return TEAM_METRICS

    def progress(
        self, params: ExplorationParams, world: ExplorationWorld
    ) -> ProgressSpec | None:
        """Free cells the team has mapped, of those a robot can reach from the starts (the
        explored share's denominator): a run ends when no reachable frontier is left, so
        the bar ends at or near its total (cells seen past a gap count, up to it)."""
        from swarmex.missions.exploration.sim import reachable_free

        total = int(reachable_free(world.grid.free, world.starts).sum())
        return ProgressSpec(total, "free cells mapped",
                            lambda frame: min(total, int((frame.known == 1).sum())))

    def prepare(self, params: ExplorationParams) -> ExplorationWorld:
        grid = build_world(params)
        validate(params, grid)
        starts = params.starts or default_starts(grid, params.robots, params.robot_radius)
        return ExplorationWorld(grid, tuple(starts))

    def execute(
        self,
        params: ExplorationParams,
        world: ExplorationWorld,
        on_frame: FrameCallback | None = None,
        *,
        trace: bool = True,
    ) -> Outcome:
        from swarmex.engine.record import without_trace
        from swarmex.missions.exploration.record import exploration_record
        from swarmex.missions.exploration.sim import run_exploration

        hook = None if on_frame is None else _frame_hook(on_frame)
        # the starts prepare chose (the default group start is the same cells the run would
        # compute; the record lists the starts either way)
        run = run_exploration(
            world.grid,
            replace(params, starts=world.starts),
            on_frame=hook,
            frame_every=0 if hook is None else 1,
        )
        record = exploration_record(run)
        return Outcome(record if trace else without_trace(record), run, world.grid)


def _frame_hook(on_frame: FrameCallback) -> Any:
    """The simulator's ``(t, run)`` hook that hands ``on_frame`` the tick's Snapshot."""
    from swarmex.missions.exploration.frames import snapshot

    wants = getattr(on_frame, "wants", None)

    def hook(t: int, run: Any) -> None:
        if wants is None or wants(t):
            on_frame(snapshot(t, run))

    return hook


__all__ = ["ExplorationMission", "ExplorationWorld", "build_world"]
