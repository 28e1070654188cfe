"""Pictures of a traversal run: a still in the style of seed 000's Fig. 3.4, and an animation.

Both functions take the *result record* (the dict of DESIGN.md: per agent a trajectory of
``[t, x, y]`` and jobs ``[t, x, y]``) plus the world it ran on, so they draw any record,
including one read back from a JSON file or produced by another algorithm (the MILP optimum).
A :class:`~swarmex.missions.traversal.TraversalRun` or a ``ResultRecord`` is accepted too and
converted first.

Drawing conventions (thesis Fig. 3.4): free vertices as small grey dots on the grid graph,
obstacles as black squares, each agent's travelled edges in its colour, a circle in its colour
on every vertex where it did a job, nests as stars. Maps with more than
:data:`SMALL_CELLS` cells switch to an image rendering: the grid is one ``imshow`` and jobs are
a translucent colour wash over the cells, because tens of thousands of per-cell markers are
slow and unreadable (den520d has 65 792 cells).

Only matplotlib's object API with the Agg canvas is used (no pyplot): no global backend switch,
no figure registry to leak, and it works on a headless machine.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.artist import Artist
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PathCollection
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from swarmex.engine.atomic import atomic_path
from swarmex.errors import InputError
from swarmex.viz.animation import (
    ANIMATION_SUFFIXES,
    HOLD_SECONDS,
    RENDER_SUFFIXES,
    write_animation,
)
from swarmex.viz.axes import coordinate_ticks
from swarmex.viz.files import save_figure
from swarmex.worlds.mapfiles import source_name

SMALL_CELLS = 2500  # up to 50x50 the thesis style (dots, edges, circles) stays legible
MAX_FRAMES = 120  # an animation never has more frames than this, whatever the map size


def as_record(record_or_run: Any) -> dict:
    """The record dict of a run, a ResultRecord or an already-plain record."""
    if isinstance(record_or_run, dict):
        return record_or_run
    if hasattr(record_or_run, "to_dict"):
        return record_or_run.to_dict()
    if hasattr(record_or_run, "agents") and hasattr(record_or_run, "world"):
        from swarmex.missions.traversal import traversal_record

        return traversal_record(record_or_run, {}).to_dict()
    raise TypeError(f"cannot draw a {type(record_or_run).__name__}")


def agent_colors(m: int) -> list[tuple[float, float, float, float]]:
    """Distinct colours: tab10, tab20, then evenly spaced hues for bigger teams."""
    from matplotlib import colormaps

    if m <= 10:
        return [colormaps["tab10"](i) for i in range(m)]
    if m <= 20:
        return [colormaps["tab20"](i) for i in range(m)]
    return [colormaps["hsv"](i / m) for i in range(m)]


@dataclass
class _Agent:
    traj: np.ndarray  # (k, 3): t, x, y
    jobs: np.ndarray  # (j, 3)
    color: tuple


def _agents(record: dict) -> list[_Agent]:
    agents = record.get("agents", [])
    colors = agent_colors(len(agents))
    out = []
    for a, c in zip(agents, colors, strict=True):
        traj = np.asarray(a.get("trajectory") or np.zeros((0, 3)), dtype=float).reshape(-1, 3)
        jobs = np.asarray(a.get("jobs") or np.zeros((0, 3)), dtype=float).reshape(-1, 3)
        out.append(_Agent(traj, jobs, c))
    return out


class _Canvas:
    """One figure with the static world drawn once; artists are updated per frame."""

    def __init__(self, world, record: dict, dpi: int, title: str | None) -> None:
        self.world = world
        self.is_grid = getattr(world, "kind", "") == "grid"
        pos = world.graph.pos
        self.small = world.graph.n_nodes <= SMALL_CELLS
        self.spacing = spacing = self._spacing()
        if self.is_grid:
            w, h = world.width, world.height
            lo, hi = np.array([-0.5, -0.5]), np.array([w - 0.5, h - 0.5])
        else:
            lo, hi = pos.min(axis=0), pos.max(axis=0)
            pad = 0.6 * spacing  # room for the markers of border vertices
            lo, hi = lo - pad, hi + pad
        span = np.maximum(hi - lo, 1e-9)
        side = 6.5
        size = side * span / span.max()
        self.fig = Figure(figsize=(max(size[0], 3.5) + 2.2, max(size[1], 3.5) + 0.6), dpi=dpi)
        self.canvas = FigureCanvasAgg(self.fig)  # also becomes self.fig.canvas
        self.ax = self.fig.add_axes((0.06, 0.06, 0.65, 0.86))
        self.ax.set_xlim(lo[0], hi[0])
        self.ax.set_ylim(hi[1], lo[1]) if self.is_grid else self.ax.set_ylim(lo[1], hi[1])
        self.ax.set_aspect("equal")
        coordinate_ticks(self.ax, integer=self.is_grid, unit="cells" if self.is_grid else "")
        if title:
            self.ax.set_title(title, fontsize=10)
        # points per vertex spacing, to size markers and lines to the cells
        self.unit_pts = 72.0 * size.max() / span.max() * spacing
        self.agents = _agents(record)
        self._draw_world()

    def _spacing(self) -> float:
        """Typical gap between neighbours: 1 on grids, else the median shortest incident edge."""
        g = self.world.graph
        if self.is_grid or g.indices.size == 0:
            return 1.0
        src = np.repeat(np.arange(g.n_nodes), np.diff(g.indptr))
        length = np.linalg.norm(g.pos[src] - g.pos[g.indices], axis=1)
        starts = g.indptr[:-1][np.diff(g.indptr) > 0]
        return float(np.median(np.minimum.reduceat(length, starts))) or 1.0

    # ------------------------------------------------------------------ static world
    def _draw_world(self) -> None:
        world, ax = self.world, self.ax
        g = world.graph
        blocked = world.blocked
        if self.is_grid:
            shade = 0.97 if self.small else 1.0  # a faint tint lets the white dots' grid read
            img = np.where(world.free[..., None], shade, 0.0).repeat(3, axis=2)
            ax.imshow(
                img,
                origin="upper",
                interpolation="nearest",
                zorder=0,
                extent=(-0.5, world.width - 0.5, world.height - 0.5, -0.5),
            )
        elif blocked.any():
            bx, by = g.pos[blocked].T
            ax.scatter(bx, by, marker="s", s=(0.5 * self.unit_pts) ** 2, c="black", zorder=1)
        if self.small or not self.is_grid:
            src = np.repeat(np.arange(g.n_nodes), np.diff(g.indptr))
            keep = (src < g.indices) & ~blocked[src] & ~blocked[g.indices]
            segs = np.stack([g.pos[src[keep]], g.pos[g.indices[keep]]], axis=1)
            # an (N, 2, 2) array of segments works; the stub asks for a Sequence
            lines = LineCollection(
                segs,  # type: ignore[arg-type]
                colors="0.82",
                linewidths=0.6,
                zorder=1,
            )
            ax.add_collection(lines)
            fx, fy = g.pos[~blocked].T
            ax.scatter(
                fx,
                fy,
                s=float(np.clip((0.1 * self.unit_pts) ** 2, 1.0, 25.0)),
                c="0.55",
                linewidths=0,
                zorder=2,
            )

    # ------------------------------------------------------------------ dynamic parts
    def offsets(self) -> list[float]:
        """Side offsets so agents that travel the same edge show side by side, as in Fig. 3.4."""
        m = len(self.agents)
        if not self.small or m == 1:
            return [0.0] * m
        step = min(0.08, 0.5 / m) * self.spacing
        return [(i - (m - 1) / 2) * step for i in range(m)]

    def line_width(self) -> float:
        return float(np.clip(0.12 * self.unit_pts, 0.5, 3.0))

    def job_size(self) -> float:
        return float(max(4.0, (0.55 * self.unit_pts) ** 2))

    def legend(self) -> None:
        handles: list[Artist] = []
        for i, a in enumerate(self.agents):
            handles.append(
                Line2D([], [], color=a.color, lw=2, label=f"agent {i + 1} ({len(a.jobs)} jobs)")
            )
        if len(handles) > 12:  # a legend for a big team is noise; keep the first ones
            handles = [*handles[:11], Line2D([], [], color="none", label="…")]
        handles.append(
            Line2D(
                [],
                [],
                marker="*",
                color="black",
                lw=0,
                markersize=11,
                markerfacecolor="white",
                label="nest",
            )
        )
        if self.small:
            handles.append(
                Line2D(
                    [],
                    [],
                    marker="o",
                    color="0.3",
                    lw=0,
                    markersize=8,
                    markerfacecolor="none",
                    label="job done",
                )
            )
        if self.world.blocked.any():  # a key for what is not drawn reads as a missing mark
            handles.append(Patch(facecolor="black", label="obstacle"))
        self.fig.legend(
            handles=handles,
            loc="upper left",
            bbox_to_anchor=(0.72, 0.92),
            fontsize=max(8.0, 8 * 72 / self.fig.dpi),  # 8 px at least in a 64-dpi frame
            frameon=False,
        )

    def nests(self) -> None:
        """A star per nest: in its agent's colour, or white when agents share it."""
        owners: dict[tuple[float, float], list] = {}
        for a in self.agents:
            if len(a.traj):
                owners.setdefault((a.traj[0, 1], a.traj[0, 2]), []).append(a.color)
        if owners:
            colors = [c[0] if len(c) == 1 else "white" for c in owners.values()]
            nx, ny = np.array(list(owners)).T
            self.ax.scatter(
                nx,
                ny,
                marker="*",
                c=colors,
                s=float(np.clip(self.job_size(), 60.0, 500.0)),
                edgecolors="black",
                linewidths=0.8,
                zorder=6,
            )

    def job_wash(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per-cell first job time and doer, for the big-map colour wash (grid only)."""
        w, h = self.world.width, self.world.height
        when = np.full((h, w), np.inf)
        who = np.zeros((h, w), dtype=np.int64)
        for i, a in enumerate(self.agents):
            if not len(a.jobs):
                continue
            xs = a.jobs[:, 1].astype(np.int64)
            ys = a.jobs[:, 2].astype(np.int64)
            earlier = a.jobs[:, 0] < when[ys, xs]
            when[ys[earlier], xs[earlier]] = a.jobs[earlier, 0]
            who[ys[earlier], xs[earlier]] = i
        palette = np.array([to_rgba(a.color, 0.45) for a in self.agents] or [(0, 0, 0, 0)])
        return when, who, palette


def _check_suffix(path: Path, suffix: str) -> None:
    if path.suffix.lower() != suffix:
        raise InputError(f"render file {path} must end in {suffix}")


def _save(write, path: Path) -> Path:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write()
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror or exc}") from None
    return path


def traversal_png(
    record_or_run: Any, world, path: str | Path, title: str | None = None, dpi: int = 110
) -> Path:
    """Draw every agent's whole path and jobs on the world (thesis Fig. 3.4) as a PNG."""
    path = Path(path)
    _check_suffix(path, ".png")
    record = as_record(record_or_run)
    cv = _Canvas(world, record, dpi, title or _title(record))
    offs = cv.offsets()
    for a, off in zip(cv.agents, offs, strict=True):
        if len(a.traj) > 1:
            cv.ax.plot(
                a.traj[:, 1] + off,
                a.traj[:, 2] + off,
                color=a.color,
                lw=cv.line_width(),
                solid_capstyle="round",
                zorder=4,
            )
        if cv.small and len(a.jobs):
            cv.ax.scatter(
                a.jobs[:, 1],
                a.jobs[:, 2],
                s=cv.job_size(),
                facecolors="none",
                edgecolors=[a.color],
                linewidths=1.4,
                zorder=5,
            )
    if not cv.small and cv.is_grid:
        when, who, palette = cv.job_wash()
        wash = np.where(np.isfinite(when)[..., None], palette[who], 0.0)
        cv.ax.imshow(
            wash,
            origin="upper",
            interpolation="nearest",
            zorder=3,
            extent=(-0.5, world.width - 0.5, world.height - 0.5, -0.5),
        )
    cv.nests()
    cv.legend()
    return save_figure(cv.fig, path, bbox_inches="tight")


def frame_times(record: dict, max_frames: int = MAX_FRAMES) -> np.ndarray:
    """Evenly spaced instants from the first to the last event, at most ``max_frames``.

    Fewer frames than events when the mission is long: the count is bounded so a 65 000-cell
    map animates as fast as a 6x6 one.
    """
    times = [
        t
        for a in record.get("agents", [])
        for t, *_ in (*a.get("trajectory", []), *a.get("jobs", []))
    ]
    if not times:
        return np.zeros(1)
    end = max(max(times), float(record.get("makespan") or 0.0))
    n = int(min(max(2, max_frames), len(set(times)) + 1))
    return np.linspace(0.0, end, n)


def traversal_gif(
    record_or_run: Any,
    world,
    path: str | Path,
    max_frames: int = MAX_FRAMES,
    seconds: float = 8.0,
    dpi: int = 64,
) -> Path:
    """Animate the mission (``.gif``, or ``.mp4`` by the suffix): agents hop along their paths
    and jobs appear as they start.

    The clock is sampled at :func:`frame_times` (≤ ``max_frames`` frames); the GIF plays in
    about ``seconds`` and holds the last frame. Positions are the last vertex each agent reached
    by the frame's time (the record stores arrivals, not departures).

    Speed: the world, nests and legend are rendered once and restored for every frame (only
    the clock text is redrawn by matplotlib); on small maps the paths, job circles and agents
    are matplotlib artists redrawn by blitting; on big grids they are composited straight into
    the pixels with numpy (a colour wash of done cells and a square per agent; whole paths
    would be a tangle there anyway). Frames share one palette, applied with a lookup table
    instead of Pillow's adaptive quantisation per frame.
    """
    path = Path(path)
    if path.suffix.lower() not in ANIMATION_SUFFIXES:
        raise InputError(f"render file {path} must end in .gif or .mp4")
    record = as_record(record_or_run)
    times = frame_times(record, max_frames)
    # the outcome is said by the last frame's clock, not from the first frame on
    cv = _Canvas(world, record, dpi, _title(record, outcome=False))
    cv.nests()
    cv.legend()
    unit = record.get("time_unit", "s")
    outcome = _outcome(record)
    # only the clock changes between frames: few glyphs to rasterise per frame
    clock = cv.fig.text(0.73, 0.05, "", fontsize=10, family="monospace", animated=True)
    layer = _VectorLayer(cv) if cv.small or not cv.is_grid else _RasterLayer(cv)
    canvas = cv.canvas
    canvas.draw()
    background = canvas.copy_from_bbox(cv.fig.bbox)

    def draw_at(t: float, last: bool = False) -> np.ndarray:
        canvas.restore_region(background)
        clock.set_text(f"t = {t:8,.1f} {unit}" + (f"\n{outcome}" if last else ""))
        cv.fig.draw_artist(clock)
        return layer.draw(t)

    if path.suffix.lower() == ".mp4":
        frames = [draw_at(float(t), i == len(times) - 1).copy()  # the buffer is reused
                  for i, t in enumerate(times)]
        fps = max(1.0, len(frames) / seconds)
        return write_animation(path, frames, fps)
    # the last frame shows every path and job, so its colours make the shared palette
    palette, lut = _palette(draw_at(float(times[-1]), last=True))
    frames = [_indexed(draw_at(float(t), i == len(times) - 1), lut) for i, t in enumerate(times)]
    step = max(20, int(1000 * seconds / len(frames)))
    durations = [step] * (len(frames) - 1) + [int(1000 * HOLD_SECONDS)]
    return _save(lambda: _write_gif(path, frames, palette, durations), path)


class _VectorLayer:
    """Small maps: paths, job circles and agents as animated matplotlib artists."""

    def __init__(self, cv: _Canvas) -> None:
        self.cv = cv
        self.lines: list[tuple[Line2D, float]] = []
        self.heads: list[PathCollection] = []
        self.rings: list[PathCollection] = []
        for a, off in zip(cv.agents, cv.offsets(), strict=True):
            (line,) = cv.ax.plot([], [], color=a.color, lw=cv.line_width(), zorder=4)
            self.lines.append((line, off))
            self.rings.append(
                cv.ax.scatter(
                    [],
                    [],
                    s=cv.job_size(),
                    facecolors="none",
                    edgecolors=[a.color],
                    linewidths=1.4,
                    zorder=5,
                )
            )
            self.heads.append(
                cv.ax.scatter(
                    [],
                    [],
                    s=max(20.0, cv.job_size()),
                    c=[a.color],
                    edgecolors="black",
                    linewidths=0.8,
                    zorder=7,
                )
            )
        self.artists: list[Artist] = [*(ln for ln, _ in self.lines), *self.rings, *self.heads]
        for artist in self.artists:
            artist.set_animated(True)

    def draw(self, t: float) -> np.ndarray:
        for i, a in enumerate(self.cv.agents):
            k = int(np.searchsorted(a.traj[:, 0], t, side="right"))
            line, off = self.lines[i]
            line.set_data(a.traj[:k, 1] + off, a.traj[:k, 2] + off)
            self.heads[i].set_offsets(a.traj[k - 1 : k, 1:] if k else np.zeros((0, 2)))
            self.rings[i].set_offsets(a.jobs[a.jobs[:, 0] <= t, 1:])
        for artist in self.artists:
            self.cv.ax.draw_artist(artist)
        return np.asarray(self.cv.canvas.buffer_rgba())[..., :3]


class _RasterLayer:
    """Big grids: done cells and agents painted into the frame's pixels with numpy."""

    ALPHA = 0.45

    def __init__(self, cv: _Canvas) -> None:
        self.cv = cv
        self.when, self.who, self.palette = cv.job_wash()
        self.geometry: tuple | None = None  # known only once the axes box is laid out

    def _layout(self) -> tuple:
        """Pixel box of the axes and, per pixel row/column, the grid cell under it."""
        fig, ax, world = self.cv.fig, self.cv.ax, self.cv.world
        height = int(fig.canvas.get_width_height()[1])
        box = ax.get_window_extent()
        c0, c1 = int(np.ceil(box.x0)), int(np.floor(box.x1))
        r0, r1 = height - int(np.floor(box.y1)), height - int(np.ceil(box.y0))
        inv = ax.transData.inverted()
        xs = inv.transform(np.stack([np.arange(c0, c1) + 0.5, np.full(c1 - c0, box.y0)], 1))
        ys = inv.transform(
            np.stack([np.full(r1 - r0, box.x0), height - np.arange(r0, r1) - 0.5], 1)
        )
        cols = np.clip(np.rint(xs[:, 0]).astype(int), 0, world.width - 1)
        rows = np.clip(np.rint(ys[:, 1]).astype(int), 0, world.height - 1)
        when = self.when[np.ix_(rows, cols)]
        color = self.palette[self.who[np.ix_(rows, cols)], :3] * 255.0
        to_px = ax.transData.transform  # cell (x, y) -> display pixels
        cell_px = abs(to_px((1.0, 0.0))[0] - to_px((0.0, 0.0))[0])
        return (r0, r1, c0, c1), when, color, to_px, height, max(2, int(0.9 * cell_px))

    def draw(self, t: float) -> np.ndarray:
        if self.geometry is None:
            self.geometry = self._layout()
        (r0, r1, c0, c1), when, color, to_px, height, half = self.geometry
        frame = np.asarray(self.cv.canvas.buffer_rgba())[..., :3].copy()
        region = frame[r0:r1, c0:c1]
        done = when <= t
        blend = region[done] * (1 - self.ALPHA) + color[done] * self.ALPHA
        region[done] = blend.astype(np.uint8)
        for a in self.cv.agents:
            k = int(np.searchsorted(a.traj[:, 0], t, side="right"))
            if not k:
                continue
            px, py = to_px(a.traj[k - 1, 1:])
            r, c = int(height - py), int(px)
            frame[max(r - half - 1, 0) : r + half + 2, max(c - half - 1, 0) : c + half + 2] = 0
            rgb = (np.array(a.color[:3]) * 255).astype(np.uint8)
            frame[max(r - half, 0) : r + half + 1, max(c - half, 0) : c + half + 1] = rgb
        return frame


def _palette(rgb: np.ndarray) -> tuple[bytes, np.ndarray]:
    """A 256-colour palette (Pillow's median cut of ``rgb``) and a 32x32x32 lookup table.

    The table maps 5-bit-per-channel RGB to the nearest palette entry, so indexing a frame is
    one numpy gather instead of a per-frame adaptive quantisation.
    """
    from PIL import Image

    pal_img = Image.fromarray(np.ascontiguousarray(rgb)).quantize(
        colors=256, dither=Image.Dither.NONE
    )
    palette = pal_img.getpalette()
    assert palette is not None  # quantize() returns a "P" image, which has a palette
    pal = np.array(palette[: 3 * 256], dtype=np.int32).reshape(-1, 3)
    cube = (np.indices((32, 32, 32)).reshape(3, -1).T * 8 + 4).astype(np.int32)
    lut = np.empty(cube.shape[0], dtype=np.uint8)
    for lo in range(0, cube.shape[0], 2048):  # chunks keep the distance matrix small
        d = ((cube[lo : lo + 2048, None, :] - pal[None]) ** 2).sum(axis=2)
        lut[lo : lo + 2048] = d.argmin(axis=1)
    return bytes(pal.astype(np.uint8).ravel()), lut


def _indexed(rgb: np.ndarray, lut: np.ndarray) -> np.ndarray:
    q = (rgb >> 3).astype(np.uint16)
    return lut[(q[..., 0] << 10) | (q[..., 1] << 5) | q[..., 2]]


def _write_gif(path: Path, frames: list[np.ndarray], palette: bytes, durations: list[int]):
    """Palette frames → GIF with Pillow, the plugin imageio itself uses for GIF.

    Pillow is called directly because imageio only hands it RGB (re-quantised per frame) or
    palette indices with a ``palette=`` option that Pillow remaps in Python per frame; both
    cost more than drawing the frames.
    """
    from PIL import Image

    images = []
    for f in frames:
        im = Image.frombytes("P", (f.shape[1], f.shape[0]), np.ascontiguousarray(f).tobytes())
        im.putpalette(palette)
        images.append(im)
    with atomic_path(path) as tmp:  # whole or not at all: Pillow writes straight to its path
        images[0].save(
            tmp,
            format="GIF",
            save_all=True,
            append_images=images[1:],
            duration=durations,
            loop=0,
            optimize=False,
            disposal=1,
        )


def traversal_frame(record: dict[str, Any], world: Any, t: float, title: str,
                    dpi: int = 64) -> np.ndarray:
    """One RGB frame of the traversal animation: ``record``'s paths and jobs up to time ``t``
    (the frame its GIF shows at ``t``), for a live view such as ``traversal_v0.render()``."""
    cv = _Canvas(world, record, dpi, title)
    cv.nests()
    cv.legend()
    layer = _VectorLayer(cv) if cv.small or not cv.is_grid else _RasterLayer(cv)
    cv.fig.canvas.draw()
    return np.ascontiguousarray(layer.draw(t), dtype=np.uint8).copy()


def record_from_frames(record: dict, frames: Sequence[Any]) -> dict:
    """``record`` with each agent's trajectory and jobs rebuilt from the run's
    :class:`~swarmex.missions.traversal.sim.TraversalFrame` list (what ``on_frame`` got).

    Every start and arrival is a frame whose ``positions`` hold the agent's new vertex, and
    every job begins right after a frame of its agent (``job``), so the rebuilt lists are
    the record's own for a run with the full trace, and the only source for a run without it
    (``trace=False``) or one still going (a live view)."""
    ids = [int(a.get("id", i + 1)) for i, a in enumerate(record.get("agents", []))]
    traj: dict[int, list[list[float]]] = {i: [] for i in ids}
    jobs: dict[int, list[list[float]]] = {i: [] for i in ids}
    for f in frames:
        xy = next(([x, y] for a, x, y in f.positions if a == f.agent), None)
        if xy is None or f.agent not in traj:
            continue
        if f.event in ("start", "arrive"):
            traj[f.agent].append([f.t, *xy])
        if f.job:
            jobs[f.agent].append([f.t, *xy])
    agents = [dict(a, trajectory=traj[i], jobs=jobs[i])
              for a, i in zip(record.get("agents", []), ids, strict=True)]
    return dict(record, agents=agents)


def render_traversal(record_or_run: Any, world, path: str | Path,
                     frames: Sequence[Any] | None = None) -> Path:
    """Draw (``.png``) or animate (``.gif``, ``.mp4``) a run, by the file's suffix; with the
    run's ``frames`` the agents' moves and jobs are drawn from them."""
    path = Path(path)
    if frames:
        record_or_run = record_from_frames(as_record(record_or_run), frames)
    suffix = path.suffix.lower()
    if suffix not in RENDER_SUFFIXES:
        raise InputError(f"render file {path} must end in {', '.join(RENDER_SUFFIXES)}")
    if suffix == ".png":
        return traversal_png(record_or_run, world, path)
    return traversal_gif(record_or_run, world, path)


def _outcome(record: dict) -> str:
    return "complete" if record.get("complete") else "incomplete"


def _title(record: dict, outcome: bool = True) -> str:
    """The run in one line; a still picture ends with its outcome (an animation's last frame
    says it instead: a title saying "complete" over the first frame reads as a wrong one)."""
    world = record.get("world") or {}
    where = source_name(str(world.get("source") or world.get("kind") or ""))
    m = len(record.get("agents", []))
    tail = f" · {_outcome(record)}" if outcome else ""
    return f"{record.get('algorithm', '?')} · {m} agent{'' if m == 1 else 's'} · {where}{tail}"
