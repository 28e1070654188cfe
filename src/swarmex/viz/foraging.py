"""Pictures of a foraging run, from its frames or its record: a still (PNG), an animation.

The still shows what the thesis's pattern figures show (Figs. 14–48): each robot's walk in its
own colour over the g×g grid, the nest as a star and the food as a square; the exploration part
(up to the discovery) is drawn solid, everything after it faint. The animation shows robots as
dots, filled when carrying food, the food square shrinking as it is picked up, and counts of
units left / carried / home, with at most :data:`MAX_FRAMES` frames whatever the run length.
Only matplotlib's object API with the Agg canvas is used (headless, no global state).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from swarmex.viz.animation import check_suffix, write_animation
from swarmex.viz.axes import coordinate_ticks, side_legend
from swarmex.viz.files import save_figure

MAX_FRAMES = 120


def _colours(n: int) -> list[Any]:
    from matplotlib import colormaps

    cmap = colormaps["tab20" if n > 10 else "tab10"]
    return [cmap(i % cmap.N) for i in range(n)]


def _positions(record: dict[str, Any]) -> np.ndarray:
    return np.asarray([[r[1:] for r in a["trajectory"]] for a in record["agents"]], dtype=float)


def frames_state(frames: Sequence[Any]) -> tuple[np.ndarray, ...]:
    """The run as the drawings need it, from its :class:`~swarmex.missions.foraging.sim.Frame`
    list (what ``on_frame`` got, one per round): positions ``(n, T, 2)``, who carries
    ``(n, T)``, units delivered ``(T,)`` and left at the food ``(T,)`` — exact, relay
    hand-overs included, where the record alone only allows :func:`carried_units`."""
    pos = np.stack([f.positions for f in frames], axis=1).astype(float)
    carrying = np.stack([f.carrying for f in frames], axis=1).astype(bool)
    delivered = np.array([f.delivered for f in frames], dtype=np.int64)
    left = np.array([f.food_left for f in frames], dtype=np.int64)
    return pos, carrying, delivered, left


def _axes(fig: Figure, g: int):
    ax = fig.add_subplot(111)
    ax.set_xlim(-0.5, g - 0.5)
    ax.set_ylim(g - 0.5, -0.5)  # row 0 at the top, as in the thesis
    ax.set_aspect("equal")
    coordinate_ticks(ax, unit="cells")
    return ax


def render_png(record: dict[str, Any], path: Path, frames: Sequence[Any] = ()) -> None:
    g = int(record["params"]["grid"])
    nest, food = record["params"]["nest"], record["params"]["food"]
    disc = int(record["metrics"]["exploration_time"])
    pos = frames_state(frames)[0] if frames else _positions(record)
    fig = Figure(figsize=(7, 7), dpi=110)
    FigureCanvasAgg(fig)
    ax = _axes(fig, g)
    for a, col in enumerate(_colours(len(pos))):
        tr = pos[a]
        if len(tr) < 2:
            continue
        segs = np.stack([tr[:-1], tr[1:]], axis=1)
        moved = np.any(segs[:, 0] != segs[:, 1], axis=1)
        early = moved.copy()
        early[disc:] = False
        late = moved & ~early
        ax.add_collection(LineCollection(segs[early], colors=[col], linewidths=1.2))
        ax.add_collection(LineCollection(segs[late], colors=[col], linewidths=0.6, alpha=0.25))
    ax.plot(*nest, marker="*", ms=14, color="black", ls="")
    ax.plot(*food, marker="s", ms=9, color="red", ls="")
    ax.set_title(
        f"{record['algorithm']} · n={len(pos)} · g={g} · found at round {disc}, "
        f"done at round {int(record['makespan'])}",
        fontsize=10,
    )
    _legend(ax)
    save_figure(fig, path, bbox_inches="tight")  # the legend beside the grid


def _legend(ax) -> None:
    """What the marks mean; the robots' colours only tell them apart."""
    from matplotlib.lines import Line2D

    side_legend(ax, [
        Line2D([], [], marker="*", ms=11, color="black", ls="", label="nest"),
        Line2D([], [], marker="s", ms=7, color="red", ls="", label="food"),
        Line2D([], [], color="0.2", lw=1.2, label="a robot's path until the food is found"),
        Line2D([], [], color="0.2", lw=0.6, alpha=0.25, label="after (communication, transport)"),
    ])


def carried_units(record: dict[str, Any], T: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per round: which robots are shown carrying, units delivered, units still at the food.

    The record lists pick-ups (at the food) and drops (in the nest) but not relay hand-overs,
    so whose hands a unit is in between is not recorded. Drops are matched to outstanding
    pick-ups first-in first-out: a robot is shown carrying from its pick-up until the drop
    that delivers its unit, so the number of filled dots always equals the units in transit
    (pick-ups minus drops), which is exact.
    """
    n = len(record["agents"])
    events = sorted(
        (int(t), kind != "pickup", a)  # pick-ups before drops in the same round
        for a, ag in enumerate(record["agents"])
        for t, _x, _y, kind in ag["jobs"]
    )
    carrying = np.zeros((n, T), dtype=bool)
    delivered = np.zeros(T, dtype=np.int64)
    picked = np.zeros(T, dtype=np.int64)
    queue: list[tuple[int, int]] = []  # (robot, round of its pick-up) of units in transit
    for t, is_drop, a in events:
        if is_drop:
            delivered[min(t, T - 1) :] += 1
            if queue:
                robot, since = queue.pop(0)
                carrying[robot, since:t] = True
        else:
            picked[min(t, T - 1) :] += 1
            queue.append((a, t))
    for robot, since in queue:
        carrying[robot, since:] = True
    k = int(record["params"]["food_units"])
    return carrying, delivered, k - picked


def animation_frames(record: dict[str, Any], max_frames: int = MAX_FRAMES,
                     frames: Sequence[Any] = ()) -> list[np.ndarray]:
    """RGB frames of the run: paths so far, robots (filled while carrying), food and nest.

    The food square shrinks as units are picked up and the title counts units left at the
    food, in transit and delivered, so the transport phase reads at a glance. With the run's
    ``frames`` everything moving is drawn from them; without (a record read back from JSON)
    from the record.
    """
    g = int(record["params"]["grid"])
    nest, food = record["params"]["nest"], record["params"]["food"]
    k = int(record["params"]["food_units"])
    if frames:
        pos, carrying, delivered, left = frames_state(frames)
        T = pos.shape[1]
    else:
        pos = _positions(record)
        T = pos.shape[1]
        carrying, delivered, left = carried_units(record, T)
    frames_t = np.unique(np.linspace(0, T - 1, min(max_frames, T)).astype(int))
    cols = _colours(len(pos))
    fig = Figure(figsize=(5, 5), dpi=80)
    canvas = FigureCanvasAgg(fig)
    ax = _axes(fig, g)  # built once: re-creating axes (ticks, spines) costs more than a frame
    # the artists are made once, in drawing order, and only their data and faces change per
    # frame: making 2n + 2 lines per frame took most of the time (64 robots on 128×128, 120
    # frames: 5.0 s of CPU, now 1.9 s), for the same pixels
    ax.plot(*nest, marker="*", ms=14, color="black", ls="", zorder=3)
    (food_mark,) = ax.plot(*food, marker="s", ms=8, color="red", ls="")
    paths, robots = [], []
    for a in range(len(pos)):
        (path,) = ax.plot(pos[a, :1, 0], pos[a, :1, 1], color=cols[a], lw=0.8, alpha=0.45)
        (robot,) = ax.plot(*pos[a, 0], marker="o", ms=6, mec=cols[a], mfc="white", ls="",
                           zorder=4)
        paths.append(path)
        robots.append(robot)
    images = []
    for t in frames_t:
        if left[t] > 0:  # the square's area follows the units still at the food
            food_mark.set_markersize(4 + 8 * np.sqrt(left[t] / k))
            food_mark.set_markerfacecolor("red")
        else:
            food_mark.set_markersize(8)
            food_mark.set_markerfacecolor("none")
        for a in range(len(pos)):
            paths[a].set_data(pos[a, : t + 1, 0], pos[a, : t + 1, 1])
            robots[a].set_data(pos[a, t, :1], pos[a, t, 1:])
            robots[a].set_markerfacecolor(cols[a] if carrying[a, t] else "white")
        in_transit = k - int(left[t]) - int(delivered[t])
        ax.set_title(
            f"t = {t} · food left {left[t]} · carried {in_transit} · home {delivered[t]}/{k}",
            fontsize=9,
        )
        canvas.draw()
        images.append(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
    return images


def render_run(record: dict[str, Any], path: str | Path, frames: Sequence[Any] = ()) -> Path:
    """Draw (``.png``) or animate (``.gif``, ``.mp4``) a run, by the file's suffix, from its
    ``frames`` when given."""
    path = Path(path)
    if check_suffix(path) == ".png":
        render_png(record, path, frames)
        return path
    return write_animation(path, animation_frames(record, frames=frames), fps=12)
