"""Draw a finished run, whatever its mission: the one entry ``--render`` and
:func:`swarmex.render` share.

Why one place: each mission draws from different things (traversal from its record's paths
and the run's frames, exploration from the run's final maps or up to 200 frames, roadmap
from the roadmap its frames rebuild), and the command line used to know each of those
itself, so Python had no way to draw a run. Here a caller needs only the mission's name:
:func:`frame_recorder` gives the ``on_frame`` callback to keep what the drawing needs, and
:func:`draw` writes the picture (``.png``) or the animation (``.gif``, ``.mp4``) from the
run's :class:`~swarmex.missions.base.Outcome` and those frames. The drawing modules (and
matplotlib) load only here, on first use.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, FrameList, Outcome
from swarmex.viz.animation import ANIMATION_SUFFIXES, check_suffix

#: the missions this module can draw (a plugin mission without a drawing is refused)
DRAWN = ("exploration", "foraging", "roadmap", "traversal")


def frame_recorder(mission: str, path: str | Path) -> FrameCallback | None:
    """The ``on_frame`` callback that keeps what :func:`draw` needs for ``path``, or None
    when the drawing needs no frames (an exploration picture is the run's final maps).
    Exploration keeps up to 200 evenly spaced frames, since a frame is a whole map."""
    _check(mission)
    if mission == "exploration":
        if Path(path).suffix.lower() not in ANIMATION_SUFFIXES:
            return None
        from swarmex.missions.exploration.frames import FrameRecorder

        return FrameRecorder()
    if mission == "roadmap":
        return PathFrames()
    return FrameList()


class PathFrames(FrameList):
    """A roadmap run's frames as its drawing reads them (step, positions, who moved:
    :func:`~swarmex.viz.roadmap_plot.run_from_frames`), without each frame's copy of the
    edge traversals. Why: that copy is one number per roadmap edge per step, so keeping
    whole frames took 3.4 GB to draw a 20,000-node roadmap that runs in 224 MB."""

    def __call__(self, frame: Any) -> None:
        self.append(SimpleNamespace(step=frame.step, positions=frame.positions,
                                    moved=frame.moved))


def draw(mission: str, outcome: Outcome, path: str | Path, recorder: Any = None) -> Path:
    """Write ``outcome``'s run to ``path`` (``.png``, ``.gif`` or ``.mp4``) from the frames
    ``recorder`` (:func:`frame_recorder`'s callback, after the run) kept."""
    _check(mission)
    path = Path(path)
    suffix = check_suffix(path)
    if recorder is not None and hasattr(recorder, "finish"):
        recorder.finish(outcome.run)  # exploration's last frame, the run's final state
    frames = list(getattr(recorder, "frames", ()))
    if mission == "traversal":
        from swarmex.viz.traversal import render_traversal

        render_traversal(outcome.record.to_dict(), outcome.world, path, frames)
    elif mission == "foraging":
        from swarmex.viz.foraging import render_run

        render_run(outcome.record.to_dict(), path, frames)
    elif mission == "exploration":
        from swarmex.viz.exploration import exploration_animation, exploration_png

        if suffix in ANIMATION_SUFFIXES:
            exploration_animation(frames, outcome.run, path)
        else:
            exploration_png(outcome.run, path)
    else:
        from swarmex.viz.roadmap_plot import render, run_from_frames

        render(run_from_frames(outcome.run, frames), path)
    return path


def _check(mission: str) -> None:
    if mission not in DRAWN:
        raise InputError(f"no drawing for {mission!r} runs (swarmex draws {', '.join(DRAWN)})")
