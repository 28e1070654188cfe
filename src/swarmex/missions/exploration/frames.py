"""Frames of an exploration run: what ``on_frame`` receives, ``--render`` animates and the
reproduction's Fig. 4.3 panels show.

A :class:`Snapshot` is the team's knowledge at one tick (any robot's map) plus where each
robot is and where it is heading. It lives with the mission, not in ``viz``, because the
mission hands frames to its callers (``swarmex.run(..., on_frame=)``); ``viz`` draws them.

:class:`FrameRecorder` is the frame callback behind animations: it keeps at most ``limit``
evenly spaced frames, halving the rate when full, and says through :meth:`~FrameRecorder.wants`
which ticks it would keep, so the mission builds no frame it would throw away.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from swarmex.missions.exploration.sim import ExplorationRun


@dataclass
class Snapshot:
    """The team's knowledge at one tick: 0 unknown, 1 free, 2 occupied (any robot's map)."""

    t: int
    known: np.ndarray  # uint8 (rows, cols)
    positions: list[tuple[int, int]]
    goals: list[tuple[int, int] | None]


def snapshot(t: int, run: ExplorationRun) -> Snapshot:
    known = np.zeros(run.grid.shape, dtype=np.uint8)
    known[run.team_free()] = 1
    known[run.team_occupied()] = 2
    return Snapshot(t, known, [r.pos for r in run.robots], [r.goal for r in run.robots])


class FrameRecorder:
    """Keeps at most ``limit`` evenly spaced snapshots, halving the rate when full."""

    def __init__(self, limit: int = 200) -> None:
        self.limit = limit
        self.every = 1
        self.frames: list[Snapshot] = []

    def wants(self, t: int) -> bool:
        """Whether the frame of tick ``t`` would be kept (the mission skips the others)."""
        return t % self.every == 0 and not (self.frames and self.frames[-1].t == t)

    def __call__(self, frame: Snapshot) -> None:
        if not self.wants(frame.t):
            return
        self.frames.append(frame)
        if len(self.frames) > self.limit:
            self.every *= 2
            self.frames = [f for f in self.frames if f.t % self.every == 0]

    def finish(self, run: ExplorationRun) -> None:
        """Add the run's last tick if the rate skipped it."""
        if not self.frames or self.frames[-1].t != run.makespan:
            self.frames.append(snapshot(run.makespan, run))


__all__ = ["FrameRecorder", "Snapshot", "snapshot"]
