"""PolygonWorld: a continuous 2-D rectangle with polygon obstacles (seed 004's workspace).

Agents are points, so the free space is ``box(bounds) − ⋃ obstacles`` and a motion is valid
when its straight segment stays in the bounds and does not *touch* any obstacle (obstacles are
closed sets: grazing a corner counts as a collision, the conservative reading).

Why two collision routes: a single prepared union of all obstacles answers vectorised queries
(`points_free`, `segments_free`: one GEOS call for thousands of segments, which is what the
batched RRT growth, PRM merging and replay checks need), while an STRtree over the individual
polygons answers "which obstacles are near this geometry" (clearance, tests of the vectorised
route against per-obstacle checks). Scalar helpers exist for the few sequential calls of
RRT growth that cannot be batched.

Sources: a JSON file ``{"bounds": [xmin, ymin, xmax, ymax], "obstacles": [[[x, y], …], …]}``
(optional ``"starts": [[x, y], …]`` and ``"goal": [x, y]`` give scenario defaults), a MovingAI
``.map`` or a bitmap image (dark pixels < 128 are walls). Grid cells become unit squares
``[x, x+1] × [y, y+1]`` with ``x`` = column and ``y`` = row, as in the grid convention of the
result record, so such worlds have ``y_down`` set (rendering flips the axis; "lower-left" is the
visually lower-left corner).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from swarmex.errors import InputError
from swarmex.worlds.mapfiles import ROS_YAML_SUFFIXES

IMAGE_SUFFIXES = frozenset({".png", ".pgm", ".bmp", ".gif", ".jpg", ".jpeg", ".tif", ".tiff"})


#: the largest coordinate a world may have (a trillion units: far beyond any map, far enough
#: from float overflow for the geometry's products)
MAX_COORDINATE = 1e12


class PolygonWorld:
    """Bounds plus closed polygon obstacles; all queries take and return numpy arrays."""

    kind = "polygons"

    def __init__(
        self,
        bounds: Sequence[float],
        obstacles: Sequence[Polygon] = (),
        source: str = "generated",
        y_down: bool = False,
        starts: np.ndarray | None = None,
        goal: tuple[float, float] | None = None,
    ) -> None:
        if len(bounds) != 4:
            raise InputError(f"bounds must be [xmin, ymin, xmax, ymax], got {list(bounds)}")
        xmin, ymin, xmax, ymax = (float(b) for b in bounds)
        if not all(np.isfinite([xmin, ymin, xmax, ymax])) or xmax <= xmin or ymax <= ymin:
            raise InputError(f"bounds must satisfy xmin < xmax and ymin < ymax, got {list(bounds)}")
        if max(map(abs, (xmin, ymin, xmax, ymax))) > MAX_COORDINATE:
            # geometry over such an extent overflows inside GEOS (0 .. 1e308: a traceback)
            raise InputError(f"bounds must lie within ±{MAX_COORDINATE:g}, got {list(bounds)}")
        self.bounds = (xmin, ymin, xmax, ymax)
        frame = box(xmin, ymin, xmax, ymax)
        clipped = [shapely.intersection(p, frame) for p in obstacles]
        # keep only areal parts: an obstacle that merely touches the frame adds nothing
        self.obstacles: tuple[Polygon, ...] = tuple(
            q
            for g in clipped
            for q in shapely.get_parts(g)
            if isinstance(q, Polygon) and q.area > 0.0
        )
        self.source = source
        self.y_down = y_down
        self.starts = None if starts is None else np.asarray(starts, dtype=np.float64)
        self.goal = goal
        self.union = shapely.union_all(self.obstacles) if self.obstacles else shapely.Polygon()
        shapely.prepare(self.union)
        self.free_region = shapely.difference(frame, self.union)
        shapely.prepare(self.free_region)
        self.tree = shapely.STRtree(self.obstacles)

    # --- geometry facts -------------------------------------------------------------------
    @property
    def width(self) -> float:
        return self.bounds[2] - self.bounds[0]

    @property
    def height(self) -> float:
        return self.bounds[3] - self.bounds[1]

    @property
    def free_area(self) -> float:
        return float(self.free_region.area)

    @cached_property
    def edges(self) -> np.ndarray:
        """Every obstacle boundary segment as rows ``[x1, y1, x2, y2]`` (line-of-sight input)."""
        rows: list[np.ndarray] = []
        for poly in shapely.get_parts(self.union):
            if not isinstance(poly, Polygon):
                continue
            for ring in (poly.exterior, *poly.interiors):
                c = np.asarray(ring.coords, dtype=np.float64)
                rows.append(np.hstack([c[:-1], c[1:]]))
        return np.vstack(rows) if rows else np.zeros((0, 4), dtype=np.float64)

    def lower_left(self) -> tuple[float, float]:
        """The visually lower-left corner (y up for JSON worlds, y down for maps/images)."""
        xmin, ymin, _, ymax = self.bounds
        return (xmin, ymax) if self.y_down else (xmin, ymin)

    # --- collision checks (vectorised) ----------------------------------------------------
    def in_bounds(self, xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        xmin, ymin, xmax, ymax = self.bounds
        x, y = xy[:, 0], xy[:, 1]
        return (x >= xmin) & (x <= xmax) & (y >= ymin) & (y <= ymax)

    def points_free(self, xy: np.ndarray) -> np.ndarray:
        """For each point: inside the bounds and touching no obstacle."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        ok = self.in_bounds(xy)
        if self.obstacles and ok.any():
            ok[ok] = ~shapely.intersects_xy(self.union, xy[ok, 0], xy[ok, 1])
        return ok

    def segments_free(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """For each segment ``a[i]–b[i]``: both ends in bounds (a convex box, so the whole
        segment is) and no obstacle touched. One GEOS call on the prepared union."""
        a = np.asarray(a, dtype=np.float64).reshape(-1, 2)
        b = np.asarray(b, dtype=np.float64).reshape(-1, 2)
        ok = self.in_bounds(a) & self.in_bounds(b)
        if self.obstacles and ok.any():
            lines = shapely.linestrings(np.stack([a[ok], b[ok]], axis=1))
            ok[ok] = ~shapely.intersects(self.union, lines)
        return ok

    def segment_free(self, ax: float, ay: float, bx: float, by: float) -> bool:
        """Scalar form for the sequential parts of tree growth."""
        xmin, ymin, xmax, ymax = self.bounds
        if not (xmin <= ax <= xmax and xmin <= bx <= xmax and ymin <= ay <= ymax
                and ymin <= by <= ymax):
            return False
        if not self.obstacles:
            return True
        return not shapely.intersects(self.union, shapely.linestrings([[ax, ay], [bx, by]]))

    def segments_free_by_tree(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Same answer as :meth:`segments_free` through the STRtree of single polygons.

        Kept as an independent route (used by tests and replay checks): a bug in the union or
        its preparation would make the two disagree.
        """
        a = np.asarray(a, dtype=np.float64).reshape(-1, 2)
        b = np.asarray(b, dtype=np.float64).reshape(-1, 2)
        ok = self.in_bounds(a) & self.in_bounds(b)
        if self.obstacles and len(a):
            lines = shapely.linestrings(np.stack([a, b], axis=1))
            hit = self.tree.query(lines, predicate="intersects")[0]
            ok[np.unique(hit)] = False
        return ok

    def clearance(self, xy: np.ndarray) -> np.ndarray:
        """Distance from each point to the nearest obstacle or bound (0 when not free)."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        xmin, ymin, xmax, ymax = self.bounds
        d = np.minimum.reduce(
            [xy[:, 0] - xmin, xmax - xy[:, 0], xy[:, 1] - ymin, ymax - xy[:, 1]]
        )
        if self.obstacles:
            pts = shapely.points(xy)
            idx = self.tree.nearest(pts)
            d = np.minimum(d, shapely.distance(pts, np.asarray(self.obstacles, dtype=object)[idx]))
        return np.where(self.points_free(xy), np.maximum(d, 0.0), 0.0)

    # --- sampling ---------------------------------------------------------------------------
    def sample_free(self, rng: np.random.Generator, m: int) -> np.ndarray:
        """``m`` points uniform over the free space (rejection from the bounding box)."""
        xmin, ymin, xmax, ymax = self.bounds
        frac = max(self.free_area / (self.width * self.height), 1e-3)
        out: list[np.ndarray] = []
        have = 0
        while have < m:
            k = int((m - have) / frac * 1.2) + 8
            pts = np.column_stack([rng.uniform(xmin, xmax, k), rng.uniform(ymin, ymax, k)])
            pts = pts[self.points_free(pts)]
            out.append(pts)
            have += len(pts)
        return np.vstack(out)[:m]

    def describe(self) -> dict[str, Any]:
        return {
            "kind": "polygons",
            "source": self.source,
            "width": self.width,
            "height": self.height,
            "bounds": list(self.bounds),
            "obstacles": len(self.obstacles),
            "free_area": self.free_area,
        }

    def to_json(self) -> dict[str, Any]:
        """The JSON environment format (exteriors only; holes are not part of the format)."""
        d: dict[str, Any] = {
            "bounds": list(self.bounds),
            "obstacles": [np.asarray(p.exterior.coords)[:-1].tolist() for p in self.obstacles],
        }
        if self.starts is not None:
            d["starts"] = self.starts.tolist()
        if self.goal is not None:
            d["goal"] = list(self.goal)
        return d

    def __repr__(self) -> str:
        return (
            f"PolygonWorld({self.width:g}x{self.height:g}, {len(self.obstacles)} obstacles, "
            f"{self.source})"
        )


# --- loaders ------------------------------------------------------------------------------
def _point(value: Any, what: str, source: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"{source}: {what} must be a pair [x, y], got {value!r}") from None
    if not (np.isfinite(x) and np.isfinite(y)):
        raise InputError(f"{source}: {what} must be finite, got {value!r}")
    return x, y


def parse_polygon_json(text: str, source: str = "<string>") -> PolygonWorld:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{source}: malformed JSON: {exc.msg} at line {exc.lineno}") from None
    if not isinstance(data, dict) or "bounds" not in data:
        raise InputError(f"{source}: expected an object with 'bounds' and 'obstacles'")
    bounds = data["bounds"]
    if not isinstance(bounds, list) or len(bounds) != 4:
        raise InputError(f"{source}: 'bounds' must be [xmin, ymin, xmax, ymax]")
    try:
        bounds = [float(b) for b in bounds]
    except (TypeError, ValueError):
        raise InputError(f"{source}: 'bounds' must hold four numbers") from None
    raw = data.get("obstacles", [])
    if not isinstance(raw, list):
        raise InputError(f"{source}: 'obstacles' must be a list of polygons")
    polys: list[Polygon] = []
    for i, ring in enumerate(raw):
        if not isinstance(ring, list) or len(ring) < 3:
            raise InputError(f"{source}: obstacle {i} needs at least 3 [x, y] vertices")
        pts = [_point(p, f"vertex of obstacle {i}", source) for p in ring]
        poly = Polygon(pts)
        if not poly.is_valid:
            reason = shapely.is_valid_reason(poly)
            raise InputError(f"{source}: obstacle {i} is not a valid polygon ({reason})")
        if poly.area <= 0:
            raise InputError(f"{source}: obstacle {i} has zero area")
        polys.append(poly)
    starts = None
    if "starts" in data:
        if not isinstance(data["starts"], list) or not data["starts"]:
            raise InputError(f"{source}: 'starts' must be a non-empty list of [x, y]")
        starts = np.array([_point(p, "a start", source) for p in data["starts"]])
    goal = _point(data["goal"], "'goal'", source) if "goal" in data else None
    return PolygonWorld(bounds, polys, source=source, starts=starts, goal=goal)


def polygons_from_blocked(blocked: np.ndarray) -> list[Polygon]:
    """Blocked grid cells → merged unit-square polygons (row runs first, then one union)."""
    blocked = np.asarray(blocked, dtype=bool)
    boxes = []
    for y, row in enumerate(blocked):
        padded = np.concatenate([[False], row, [False]])
        change = np.flatnonzero(padded[1:] != padded[:-1])
        for x0, x1 in zip(change[::2], change[1::2], strict=True):
            boxes.append(box(float(x0), float(y), float(x1), float(y + 1)))
    if not boxes:
        return []
    merged = shapely.union_all(boxes)
    return [p for p in shapely.get_parts(merged) if isinstance(p, Polygon)]


def world_from_blocked(blocked: np.ndarray, source: str) -> PolygonWorld:
    h, w = blocked.shape
    return PolygonWorld((0.0, 0.0, float(w), float(h)), polygons_from_blocked(blocked),
                        source=source, y_down=True)


def load_polygon_world(path: str | Path) -> PolygonWorld:
    """JSON polygons, a MovingAI ``.map`` or an image, chosen by the file's suffix."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"environment file not found: {path}")
    suffix = path.suffix.lower()
    if suffix == ".map":
        from swarmex.worlds.movingai import load_movingai

        grid = load_movingai(path)
        return world_from_blocked(~grid.free, str(path))
    if suffix in IMAGE_SUFFIXES:
        import imageio.v3 as iio

        try:
            img = np.asarray(iio.imread(path), dtype=np.float64)
        except Exception as exc:  # imageio raises many types for unreadable files
            # first line only: imageio appends lines of plugins to pip install, and bad input
            # is one line
            reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            raise InputError(f"cannot read image {path}: {reason}") from None
        if img.ndim == 3:
            img = img[..., :3].mean(axis=2)
        if img.ndim != 2:
            raise InputError(f"{path}: expected a 2-D image")
        return world_from_blocked(img < 128, str(path))
    if suffix in ROS_YAML_SUFFIXES:  # JSON's "Expecting value" said nothing useful
        raise InputError(f"{path}: a ROS map YAML is not a roadmap environment (give a JSON"
                         " of polygons, a MovingAI .map or an image)")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read environment file {path}: {exc}") from None
    return parse_polygon_json(text, source=str(path))
