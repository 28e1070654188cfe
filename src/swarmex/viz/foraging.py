"""Pictures of a foraging run from its result record: a still (PNG) and an animation (GIF).

The still shows what the thesis's pattern figures show (Figs. 14–48): each robot's walk in its
own colour over the g×g grid, the nest as a star and the food as a square; the exploration part
(up to the discovery) is drawn solid, everything after it faint. The animation shows robots as
dots, filled when carrying food, with at most :data:`MAX_FRAMES` frames whatever the run length.
Only matplotlib's object API with the Agg canvas is used (headless, no global state).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

MAX_FRAMES = 120


def _colours(n: int) -> list[Any]:
    from matplotlib import colormaps

    cmap = colormaps["tab20" if n > 10 else "tab10"]
    return [cmap(i % cmap.N) for i in range(n)]


def _positions(record: dict[str, Any]) -> np.ndarray:
    return np.asarray([[r[1:] for r in a["trajectory"]] for a in record["agents"]], dtype=float)


def _axes(fig: Figure, g: int):
    ax = fig.add_subplot(111)
    ax.set_xlim(-0.5, g - 0.5)
    ax.set_ylim(g - 0.5, -0.5)  # row 0 at the top, as in the thesis
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    return ax


def render_png(record: dict[str, Any], path: Path) -> None:
    g = int(record["params"]["grid"])
    nest, food = record["params"]["nest"], record["params"]["food"]
    disc = int(record["metrics"]["exploration_time"])
    pos = _positions(record)
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
        f"{record['algorithm']} · n={len(pos)} · g={g} · found at {disc}, "
        f"done at {int(record['makespan'])}",
        fontsize=10,
    )
    fig.savefig(path)


def render_gif(record: dict[str, Any], path: Path) -> None:
    import imageio.v2 as imageio

    g = int(record["params"]["grid"])
    nest, food = record["params"]["nest"], record["params"]["food"]
    pos = _positions(record)
    T = pos.shape[1]
    carrying = np.zeros((len(pos), T), dtype=bool)
    for a, ag in enumerate(record["agents"]):
        for t, _x, _y, kind in ag["jobs"]:
            carrying[a, int(t) :] = kind == "pickup"
    frames_t = np.unique(np.linspace(0, T - 1, min(MAX_FRAMES, T)).astype(int))
    cols = _colours(len(pos))
    images = []
    for t in frames_t:
        fig = Figure(figsize=(5, 5), dpi=80)
        canvas = FigureCanvasAgg(fig)
        ax = _axes(fig, g)
        ax.plot(*nest, marker="*", ms=12, color="black", ls="")
        ax.plot(*food, marker="s", ms=7, color="red", ls="")
        for a in range(len(pos)):
            ax.plot(pos[a, : t + 1, 0], pos[a, : t + 1, 1], color=cols[a], lw=0.5, alpha=0.35)
            face = cols[a] if carrying[a, t] else "white"
            ax.plot(*pos[a, t], marker="o", ms=6, mec=cols[a], mfc=face, ls="")
        ax.set_title(f"t = {t}", fontsize=9)
        canvas.draw()
        images.append(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
    imageio.mimsave(path, images, duration=0.08)


def render_run(record: dict[str, Any], path: str | Path) -> Path:
    path = Path(path)
    if path.suffix.lower() == ".gif":
        render_gif(record, path)
    else:
        render_png(record, path)
    return path
