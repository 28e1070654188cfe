"""``--render`` draws the run's frames: the objects ``on_frame`` hands a notebook (issue 12).

For each mission the state rebuilt from the frames is checked against the run's own record
(an independent route: the simulator's logs), and the pictures drawn from frames against the
pictures drawn from the record, pixel for pixel. A run without its trace (``trace=False``)
still renders from its frames alone.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from swarmex.missions.base import FrameList
from swarmex.missions.registry import get

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _pixels(path: Path) -> np.ndarray:
    return np.asarray(Image.open(path).convert("RGB"))


def test_traversal_frames_rebuild_the_record_and_its_picture(tmp_path):
    from swarmex.viz.traversal import record_from_frames, render_traversal

    mission = get("traversal")
    for kw in ({"grid": "8x8", "agents": 3, "seed": 1},
               {"grid": "8x8", "agents": 3, "seed": 3, "job_failure": 0.3}):
        frames = FrameList()
        out = mission.run(mission.params(**kw), frames)
        record = out.record.to_dict()
        rebuilt = record_from_frames(record, frames)
        assert rebuilt["agents"] == record["agents"]
        assert sum(f.job for f in frames) == sum(len(a["jobs"]) for a in record["agents"])
    a, b = tmp_path / "frames.png", tmp_path / "record.png"
    render_traversal(record, out.world, a, frames)
    render_traversal(record, out.world, b)
    assert np.array_equal(_pixels(a), _pixels(b))
    # without the trace, the frames alone carry the moves
    frames = FrameList()
    bare = mission.run(mission.params(grid="8x8", agents=3, seed=3, job_failure=0.3), frames,
                       trace=False)
    assert all(not ag["trajectory"] for ag in bare.record.to_dict()["agents"])
    assert record_from_frames(bare.record.to_dict(), frames)["agents"] == record["agents"]


def test_roadmap_frames_rebuild_the_paths_and_the_picture(tmp_path):
    from swarmex.viz.roadmap_plot import render, run_from_frames

    mission = get("roadmap")
    for planner in ("wma-rrt", "prm"):
        params = mission.params(env=EXAMPLES / "roadmap_fig8.json", agents=3, nodes=80,
                                step=25, sensor_range=25, planner=planner, seed=2)
        frames = FrameList()
        out = mission.run(params, frames)
        view = run_from_frames(out.run, frames)
        assert view.trajectories == out.run.trajectories and view.steps == out.run.steps
    a, b = tmp_path / "frames.png", tmp_path / "run.png"
    render(view, a)
    render(out.run, b)
    assert np.array_equal(_pixels(a), _pixels(b))
    # a run stopped half-way is drawn as far as its frames go
    half = run_from_frames(out.run, frames[: len(frames) // 2])
    assert half.steps == frames[len(frames) // 2 - 1].step < out.run.steps


def test_foraging_frames_carry_exactly_and_draw_the_same_walks(tmp_path):
    from swarmex.viz.foraging import animation_frames, carried_units, frames_state, render_png

    mission = get("foraging")
    params = mission.params(grid=8, agents=4, algorithm="spiral", food="1,1", food_units=6,
                            transport="relay-food", seed=0)
    frames = FrameList()
    out = mission.run(params, frames)
    record = out.record.to_dict()
    pos, carrying, delivered, left = frames_state(frames)
    traj = np.asarray([[r[1:] for r in a["trajectory"]] for a in record["agents"]], float)
    assert np.array_equal(pos, traj)
    k = record["params"]["food_units"]
    # in transit = picked up − delivered, whoever holds the unit after a relay hand-over
    assert np.array_equal(carrying.sum(axis=0), k - left - delivered)
    _, fifo_delivered, fifo_left = carried_units(record, pos.shape[1])
    assert np.array_equal(delivered, fifo_delivered) and np.array_equal(left, fifo_left)
    a, b = tmp_path / "frames.png", tmp_path / "record.png"
    render_png(record, a, frames)
    render_png(record, b)
    assert np.array_equal(_pixels(a), _pixels(b))
    assert len(animation_frames(record, max_frames=5, frames=frames)) == 5
