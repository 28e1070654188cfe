"""Pictures of exploration runs: the team's map with the robots' paths (PNG) and its growth
over time (GIF or MP4).

Colours follow the thesis's Fig. 1.2 in spirit: unknown is grey, known free is white,
known obstacles are black, true walls nobody has seen are a darker grey; each robot's path
is drawn in its own colour with a dot where it ended. Animation frames also paint the
frontier (known free cells next to unknown ones, what the strategies choose goals from) in
gold and each robot's current goal as a hollow square in its colour, so one sees why robots
head where they do, under a line with the run, its step and the share explored. Frames are
composed directly as numpy RGB arrays (no matplotlib per frame), so a 400×400 animation of a
few hundred frames costs about a second.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from swarmex.missions.exploration.frames import Snapshot, snapshot  # re-exported for viz users
from swarmex.sensing.frontiers import frontier_mask
from swarmex.viz.animation import write_animation
from swarmex.viz.axes import coordinate_ticks, side_legend
from swarmex.viz.files import save_figure

UNKNOWN = np.array([170, 170, 170], dtype=np.uint8)
FREE = np.array([255, 255, 255], dtype=np.uint8)
OCCUPIED = np.array([0, 0, 0], dtype=np.uint8)
HIDDEN_WALL = np.array([120, 120, 120], dtype=np.uint8)
FRONTIER = np.array([255, 190, 0], dtype=np.uint8)


def robot_colours(n: int) -> np.ndarray:
    """RGB (0–255) per robot from matplotlib's tab10/tab20."""
    import matplotlib

    cmap = matplotlib.colormaps["tab10" if n <= 10 else "tab20"]
    return (np.array([cmap(i % cmap.N)[:3] for i in range(n)]) * 255).astype(np.uint8)


def base_rgb(known: np.ndarray, truth_free: np.ndarray) -> np.ndarray:
    img = np.empty(known.shape + (3,), dtype=np.uint8)
    img[:] = UNKNOWN
    img[~truth_free & (known == 0)] = HIDDEN_WALL
    img[known == 1] = FREE
    img[known == 2] = OCCUPIED
    return img


def paths_until(trajectories: list[list[tuple[int, int, int]]], t: int) -> list[np.ndarray]:
    out = []
    for tr in trajectories:
        a = np.asarray(tr, dtype=np.int64).reshape(-1, 3)
        out.append(a[a[:, 0] <= t][:, 1:])
    return out


def rgb_frame(snap: Snapshot, trajectories, truth_free: np.ndarray, scale: int = 1) -> np.ndarray:
    """One animation frame: map, frontier and paths in cells; goals and robots in pixels."""
    img = base_rgb(snap.known, truth_free)
    img[frontier_mask(snap.known == 1, snap.known == 0)] = FRONTIER  # free, unknown
    cols = robot_colours(len(trajectories))
    for i, p in enumerate(paths_until(trajectories, snap.t)):
        if p.size:
            img[p[:, 1], p[:, 0]] = cols[i]
    if scale > 1:
        img = img.repeat(scale, axis=0).repeat(scale, axis=1)
    r = max(3, scale)  # robots outsize a path cell, with a black rim, so they stand out

    def box(cx: int, cy: int, half: int) -> tuple[slice, slice]:
        return slice(max(0, cy - half), cy + half + 1), slice(max(0, cx - half), cx + half + 1)

    for i, goal in enumerate(snap.goals):
        if goal is None:
            continue
        gx, gy = goal[0] * scale + scale // 2, goal[1] * scale + scale // 2
        outer = img[box(gx, gy, r + 2)]
        saved = img[box(gx, gy, r)].copy()
        outer[:] = cols[i]  # a hollow square two pixels thick: fill, then restore the inside
        img[box(gx, gy, r)] = saved
    for i, (x, y) in enumerate(snap.positions):
        cx, cy = x * scale + scale // 2, y * scale + scale // 2
        img[box(cx, cy, r + 1)] = OCCUPIED
        img[box(cx, cy, r)] = cols[i]
    return img


def draw(
    ax,
    snap: Snapshot,
    trajectories,
    truth_free: np.ndarray,
    title: str = "",
    laser_cells: float | None = None,
) -> None:
    """A matplotlib panel: the team map, paths, robot positions (and goals' exclusion discs)."""
    ax.imshow(base_rgb(snap.known, truth_free), interpolation="nearest")
    cols = robot_colours(len(trajectories)) / 255.0
    for i, p in enumerate(paths_until(trajectories, snap.t)):
        if len(p):
            ax.plot(p[:, 0], p[:, 1], "-", color=cols[i], lw=0.8)
            ax.plot([p[0, 0]], [p[0, 1]], "s", mfc="none", mec=cols[i], ms=4.5, mew=0.9)
        x, y = snap.positions[i]
        ax.plot([x], [y], "o", color=cols[i], ms=3.5, mec="k", mew=0.4)
        g = snap.goals[i]
        if laser_cells and g is not None:
            from matplotlib.patches import Circle

            ax.add_patch(Circle(g, laser_cells, fill=False, color="gold", lw=0.7))
    h, w = snap.known.shape
    ax.set_xlim(-0.5, w - 0.5)
    ax.set_ylim(h - 0.5, -0.5)
    coordinate_ticks(ax, unit="cells")
    if title:
        ax.set_title(title, fontsize=8)


def exploration_png(run, path: str | Path, title: str | None = None) -> Path:
    """The final team map with every robot's path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = Path(path)
    snap = snapshot(run.makespan, run)
    h, w = run.grid.shape
    fig, ax = plt.subplots(figsize=(6, 6 * h / max(w, 1) + 0.4), dpi=120)
    p = run.params
    draw(
        ax,
        snap,
        run.trajectories,
        run.grid.free,
        title
        or (
            f"{p.strategy}: {p.robots} robot(s), laser {p.laser_range:g} m, comm "
            f"{p.comm_range:g} m — {run.makespan} steps, explored {run.explored_fraction():.1%}"
        ),
    )
    _legend(ax)
    try:
        save_figure(fig, path, bbox_inches="tight")
    finally:
        plt.close(fig)
    return path


def _legend(ax) -> None:
    """What the colours and marks mean (each robot's colour only tells it apart)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    side_legend(ax, [
        Patch(fc=FREE / 255, ec="0.5", label="known free"),
        Patch(fc=OCCUPIED / 255, label="known obstacle"),
        Patch(fc=UNKNOWN / 255, label="unknown"),
        Patch(fc=HIDDEN_WALL / 255, label="wall nobody saw"),
        Line2D([], [], marker="s", mfc="none", mec="0.2", ls="-", color="0.2", lw=0.8,
               label="a robot's path from its start"),
        Line2D([], [], marker="o", color="0.2", mec="k", ls="", label="where it ended"),
    ])


def exploration_animation(frames: list[Snapshot], run, path: str | Path, fps: int = 12) -> Path:
    """Write the recorded snapshots as a ``.gif`` or ``.mp4`` (by the suffix), each under a
    line saying which run it is, its step and how much is explored (the other missions'
    animations have a title and a clock; these frames had neither)."""
    h, w = run.grid.shape
    scale = max(1, 400 // max(h, w))
    free = run.grid.free
    total = max(int(free.sum()), 1)
    name = f"{run.params.strategy}, {len(run.trajectories)} robot(s)"
    images = [
        captioned(rgb_frame(s, run.trajectories, free, scale),
                  f"{name}, step {s.t}, explored {((s.known == 1) & free).sum() / total:.0%}")
        for s in frames
    ]
    return write_animation(path, images, fps)


CAPTION_PX = 16  # the band above a frame: Pillow's default font is 11 pixels tall


def captioned(img: np.ndarray, text: str) -> np.ndarray:
    """``img`` under a white band with ``text`` in black (Pillow's built-in font: no font
    file to find, and no matplotlib per frame)."""
    from PIL import Image, ImageDraw

    out = np.full((img.shape[0] + CAPTION_PX, img.shape[1], 3), 255, dtype=np.uint8)
    out[CAPTION_PX:] = img
    canvas = Image.fromarray(out)
    ImageDraw.Draw(canvas).text((3, 2), text, fill=(0, 0, 0))
    return np.asarray(canvas)
