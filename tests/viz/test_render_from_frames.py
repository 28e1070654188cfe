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


def _redrawn_frames(record: dict, frames, max_frames: int) -> list[np.ndarray]:
    """The foraging animation drawn the plain way: every artist made afresh for each frame
    (what animation_frames did until 27 Nov 2026), as the pixel reference."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from swarmex.viz.foraging import _axes, _colours, frames_state

    g, k = int(record["params"]["grid"]), int(record["params"]["food_units"])
    nest, food = record["params"]["nest"], record["params"]["food"]
    pos, carrying, delivered, left = frames_state(frames)
    T = pos.shape[1]
    cols = _colours(len(pos))
    fig = Figure(figsize=(5, 5), dpi=80)
    canvas = FigureCanvasAgg(fig)
    ax = _axes(fig, g)
    out = []
    for t in np.unique(np.linspace(0, T - 1, min(max_frames, T)).astype(int)):
        for line in list(ax.lines):
            line.remove()
        ax.plot(*nest, marker="*", ms=14, color="black", ls="", zorder=3)
        if left[t] > 0:
            ax.plot(*food, marker="s", ms=4 + 8 * np.sqrt(left[t] / k), color="red", ls="")
        else:
            ax.plot(*food, marker="s", ms=8, mfc="none", mec="red", ls="")
        for a in range(len(pos)):
            ax.plot(pos[a, : t + 1, 0], pos[a, : t + 1, 1], color=cols[a], lw=0.8, alpha=0.45)
            face = cols[a] if carrying[a, t] else "white"
            ax.plot(*pos[a, t], marker="o", ms=6, mec=cols[a], mfc=face, ls="", zorder=4)
        ax.set_title(
            f"t = {t} · food left {left[t]} · carried {k - int(left[t]) - int(delivered[t])}"
            f" · home {delivered[t]}/{k}",
            fontsize=9,
        )
        canvas.draw()
        out.append(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
    return out


def test_foraging_animation_makes_its_artists_once_for_the_same_pixels(monkeypatch):
    """The animation used to make 2n + 2 lines for every frame, most of the time of a
    ``--render run.gif`` (64 robots on 128×128: 5.0 s of CPU, now 1.9 s). It now makes them
    once and moves them; the frames are the same pixels as drawing each one afresh."""
    from matplotlib import lines

    from swarmex.viz.foraging import animation_frames

    mission = get("foraging")
    params = mission.params(grid=16, agents=8, algorithm="sectors", food="13,2", food_units=4,
                            transport="relay-food", seed=0)
    frames = FrameList()
    record = mission.run(params, frames).record.to_dict()
    reference = _redrawn_frames(record, frames, 12)
    made = []
    real_init = lines.Line2D.__init__

    def counting(self, *args, **kwargs):
        made.append(1)
        real_init(self, *args, **kwargs)

    monkeypatch.setattr(lines.Line2D, "__init__", counting)
    drawn = animation_frames(record, max_frames=12, frames=frames)
    # once: 2n + 2 lines plus the axes' own (their ticks, ~40); made per frame: > 12 (2n + 2)
    assert len(made) < 12 * (2 * 8 + 2) / 2
    assert len(drawn) == len(reference) == 12
    assert all(np.array_equal(a, b) for a, b in zip(drawn, reference, strict=True))
