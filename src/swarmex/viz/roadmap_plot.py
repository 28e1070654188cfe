"""Figures of roadmap runs: a PNG of the final state, a GIF/MP4 of the run step by step.

Drawn: obstacles (grey), the seen part of the free space (pale green raster), roadmap edges
coloured by branch (WMA-RRT) or by connected component (PRM), the Main Root (black square),
the starts (circles), the agents (triangles), the goal (star). Worlds read from maps/images
have ``y_down`` and are drawn with y pointing down, as the map looks.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, cast

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Polygon as MplPolygon  # noqa: E402

from swarmex.missions.roadmap.sim import RoadmapRun  # noqa: E402
from swarmex.viz.animation import check_suffix, write_animation  # noqa: E402
from swarmex.viz.axes import coordinate_ticks, side_legend  # noqa: E402
from swarmex.viz.files import save_figure  # noqa: E402

# tab10 is a ListedColormap whose colors are a tuple of ten RGB tuples
PALETTE = cast(
    "tuple[tuple[float, float, float], ...]",
    cast(ListedColormap, plt.get_cmap("tab10")).colors,
)


def _edge_colors(run: RoadmapRun) -> list:
    rm = run.roadmap
    if rm.branch is not None:
        lab = rm.branch[rm.edges[:, 1]]
    else:
        lab = rm.component_labels[rm.edges[:, 0]]
    return [PALETTE[int(k) % len(PALETTE)] for k in lab]


def _positions_at(run: RoadmapRun, t: int) -> np.ndarray:
    out = []
    for tr in run.trajectories:
        arr = np.asarray(tr)
        k = int(np.searchsorted(arr[:, 0], t, side="right")) - 1
        out.append(arr[max(k, 0), 1:])
    return np.asarray(out)


def run_from_frames(run: RoadmapRun, frames: Sequence[Any]) -> RoadmapRun:
    """``run`` with the agents' paths and its length rebuilt from the run's
    :class:`~swarmex.missions.roadmap.sim.RoadmapFrame` list (what ``on_frame`` got).

    Frame 0 holds the starts and every later frame the positions after its step, ``moved``
    naming who moved: exactly the run's trajectories when every frame is there, and what a
    live view or a stopped run has drawn so far otherwise. The world, roadmap and raster
    (whose cells remember the step they were first seen) are the run's static part.
    """
    if not frames:
        return run
    traj = [[[0.0, float(p[0]), float(p[1])]] for p in frames[0].positions]
    for f in frames[1:]:
        for i in f.moved:
            traj[i].append([float(f.step), float(f.positions[i][0]), float(f.positions[i][1])])
    return replace(run, trajectories=traj, steps=int(frames[-1].step))


def _first_use(run: RoadmapRun) -> np.ndarray:
    """Step at which each edge was first traversed (a large number if never)."""
    rm = run.roadmap
    key = {}
    for e, (u, v) in enumerate(rm.edges.tolist()):
        key[(u, v)] = key[(v, u)] = e
    pos_key = {tuple(np.round(p, 6)): i for i, p in enumerate(rm.pos)}
    first = np.full(rm.n_edges, np.iinfo(np.int64).max)
    for tr in run.trajectories:
        nodes = [pos_key.get(tuple(np.round(p[1:], 6)), -1) for p in tr]
        for j in range(1, len(tr)):
            edge = key.get((nodes[j - 1], nodes[j]))
            if edge is not None:
                first[edge] = min(first[edge], int(tr[j][0]))
    return first


def draw(
    ax,
    run: RoadmapRun,
    t: int | None = None,
    first_use: np.ndarray | None = None,
    title: str | None = None,
    built: int | None = None,
) -> None:
    """One panel: the world, seen space, roadmap, starts, agents and goal at step ``t``.

    With ``t`` (an animation frame) the edges not yet travelled are grey and each agent's
    path so far is drawn in its colour. With ``built`` the mission has not started: only the
    roadmap's first ``built`` nodes and the edges between them are drawn (construction
    phase), agents stand at their starts.
    """
    w, rm, r = run.world, run.roadmap, run.raster
    if built is not None:
        t, first_use = 0, None
    xmin, ymin, xmax, ymax = w.bounds
    seen = r.seen_mask(t)
    img = np.where(r.free, np.where(seen, 1, 0), 2)
    cmap = ListedColormap(["#ffffff", "#cdeccd", "#ffffff"])
    ax.imshow(
        img,
        origin="lower",
        extent=(r.x0, r.x0 + r.nx * r.h, r.y0, r.y0 + r.ny * r.h),
        cmap=cmap,
        vmin=0,
        vmax=2,
        interpolation="nearest",
        zorder=0,
    )
    for poly in w.obstacles:
        ax.add_patch(
            MplPolygon(
                np.asarray(poly.exterior.coords),
                closed=True,
                fc="#777777",
                ec="#444444",
                lw=0.5,
                zorder=1,
            )
        )
    segs = rm.pos[rm.edges]
    colors = _edge_colors(run)
    if built is not None:
        exists = rm.edges.max(axis=1) < built if rm.n_edges else np.zeros(0, dtype=bool)
        segs, colors = segs[exists], [c for c, e in zip(colors, exists, strict=True) if e]
        ax.plot(*rm.pos[:built].T, ".", color="#555555", ms=2.5, zorder=4)
    elif t is not None and first_use is not None:
        used = first_use <= t
        ax.add_collection(LineCollection(segs[~used], colors="#bbbbbb", lw=0.4, zorder=2))
        segs, colors = segs[used], [c for c, u in zip(colors, used, strict=True) if u]
    ax.add_collection(LineCollection(segs, colors=colors, lw=0.7, zorder=3))
    if rm.branch is not None:
        ax.plot(*rm.pos[0], "ks", ms=5, zorder=5)
    ax.plot(rm.starts[:, 0], rm.starts[:, 1], "o", mfc="none", mec="k", ms=4, zorder=5)
    if t is not None and built is None:
        for i, tr in enumerate(run.trajectories):
            arr = np.asarray(tr).reshape(-1, 3)
            done = arr[arr[:, 0] <= t]
            ax.plot(
                *done[:, 1:].T,
                "-",
                color=PALETTE[i % len(PALETTE)],
                lw=2.2,
                alpha=0.45,
                zorder=4,
                solid_capstyle="round",
            )
    pos = _positions_at(run, t if t is not None else run.steps)
    for i, p in enumerate(pos):
        ax.plot(*p, "^", color=PALETTE[i % len(PALETTE)], mec="k", ms=7, zorder=6)
    if run.goal is not None:
        # under the agents: an agent that ends on the goal stays visible above it
        ax.plot(*run.goal, "*", color="gold", mec="k", ms=14, zorder=5.5)
    ax.set_xlim(xmin, xmax)
    ax.set_ylim((ymax, ymin) if w.y_down else (ymin, ymax))
    ax.set_aspect("equal")
    coordinate_ticks(ax, integer=False)
    if title:
        ax.set_title(title, fontsize=9)


def summary_title(run: RoadmapRun, t: int | None = None) -> str:
    rng = "∞" if np.isinf(run.sensor_range) else f"{run.sensor_range:g}"
    cov = (
        run.raster.coverage()
        if t is None
        else float(run.raster.seen_mask(t).sum() / max(run.raster.free_cells, 1))
    )
    s = (
        f"{run.planner} {run.task}: {run.roadmap.n_nodes} nodes, R={rng}, "
        f"step {run.steps if t is None else t}, coverage {100 * cov:.1f}%"
    )
    if run.task == "search":
        # a frame says what was known at its step: the goal is found from its sighting on
        # (every frame of an animation used to say "goal found", from the first step)
        found = int(getattr(run.board, "found_step", -1))
        ended = t is None or t >= run.steps
        if run.goal_found and (t is None or 0 <= found <= t):
            s += ", goal found"
        elif not ended:
            s += ", searching"
        else:
            s += ", goal unreachable" if run.goal_unreachable else ", goal not found"
    if t is None and not run.complete:
        s += " · incomplete"
    return s


def _legend(ax, run: RoadmapRun) -> None:
    """What the marks mean: a roadmap's colours are its branches (or PRM's components), which
    an agent's colour does not match, so the agents are named by their triangles."""
    from matplotlib.artist import Artist
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    shown = min(len(run.trajectories), 8)  # a legend for a big team is noise
    handles: list[Artist] = [
        Line2D([], [], marker="^", color=PALETTE[i % len(PALETTE)], mec="k", ls="-", lw=2.2,
               alpha=0.8, label=f"agent {i + 1}")
        for i in range(shown)
    ]
    handles += [
        Line2D([], [], marker="o", mfc="none", mec="k", ls="", label="start"),
        Line2D([], [], color="#bbbbbb", lw=1, label="edge never travelled"),
        Patch(fc="#cdeccd", ec="none", label="seen"),
    ]
    if run.roadmap.branch is not None:
        handles.insert(shown + 1, Line2D([], [], marker="s", color="k", ls="", label="root"))
    if run.goal is not None:
        handles.append(Line2D([], [], marker="*", color="gold", mec="k", ms=12, ls="",
                              label="goal"))
    side_legend(ax, handles)


def render_png(run: RoadmapRun, path: str | Path, title: str | None = None) -> Path:
    """The run's end, as the animation's last frame shows it (edges never travelled grey,
    every agent's path in its colour), with a legend. Without the paths, the roadmap's
    branch colours read as the agents' own."""
    path = Path(path)
    fig, ax = plt.subplots(figsize=(8.4, 7 * run.world.height / run.world.width + 0.4),
                           dpi=110)
    draw(ax, run, t=run.steps, first_use=_first_use(run), title=title or summary_title(run))
    _legend(ax, run)
    fig.tight_layout()
    try:
        return save_figure(fig, path, bbox_inches="tight")  # the legend beside the axes
    finally:
        plt.close(fig)


BUILD_FRAMES = 20  # frames spent on the roadmap's construction before the mission starts


def _clear(ax) -> None:
    """Remove the drawn artists but keep the axes: ``ax.clear()`` rebuilds ticks and spines,
    which cost more than drawing a frame."""
    for artist in [*ax.images, *ax.lines, *ax.collections, *ax.patches]:
        artist.remove()


def animation_frames(run: RoadmapRun, frames: int = 60) -> list[np.ndarray]:
    """RGB frames: the roadmap growing node by node, then the mission step by step.

    The construction is replayed in node order — the order the builder added the nodes (for
    WMA-RRT every node's parent is older; PRM's merge edges appear once both their nodes
    exist). The mission part shows agents moving, their paths, edges lighting up in their
    branch's colour when first travelled, and the seen area spreading.
    """
    first = _first_use(run)
    n = run.roadmap.n_nodes
    sizes = np.unique(np.linspace(1, n, min(BUILD_FRAMES, n)).round().astype(int))
    times = np.unique(np.linspace(0, run.steps, min(frames, run.steps + 1)).round().astype(int))
    panels: list[dict[str, Any]] = [
        {"built": int(k), "title": f"{run.planner}: building the roadmap, {k}/{n} nodes"}
        for k in sizes
    ]
    panels += [
        {"t": int(t), "first_use": first, "title": summary_title(run, int(t))} for t in times
    ]
    images = []
    fig, ax = plt.subplots(figsize=(6, 6 * run.world.height / run.world.width + 0.4), dpi=80)
    try:
        for panel in panels:
            _clear(ax)
            draw(ax, run, **panel)
            canvas = cast(FigureCanvasAgg, fig.canvas)  # the Agg backend, chosen above
            canvas.draw()
            images.append(np.asarray(canvas.buffer_rgba())[..., :3].copy())
    finally:
        plt.close(fig)
    return images


def render(run: RoadmapRun, path: str | Path) -> Path:
    """Draw (``.png``) or animate (``.gif``, ``.mp4``) a run, by the file's suffix."""
    path = Path(path)
    if check_suffix(path) == ".png":
        return render_png(run, path)
    return write_animation(path, animation_frames(run), fps=8)
