"""Loader for ROS ``map_server`` maps: a ``.yaml`` description beside a ``.pgm`` image.

This is the format robotics users already have (``map_saver`` writes it). The YAML keys used
(the map_server documentation's names):

* ``image``: the image path, relative to the YAML file;
* ``resolution``: metres per pixel (one grid cell per pixel);
* ``negate``: 0 means white = free, black = occupied (the usual); 1 inverts;
* ``occupied_thresh`` / ``free_thresh``: a pixel's occupancy probability
  ``p = (255 - value) / 255`` (or ``value / 255`` when negated) above ``occupied_thresh`` is
  an obstacle, below ``free_thresh`` free, and in between *unknown*;
* ``origin``, ``mode``: read and ignored (swarmex grids start at cell (0, 0); only the
  default ``trinary`` interpretation is meaningful for a true world).

Unknown pixels of a *true* world are treated as blocked: they are the parts of a saved map
the mapper never saw, so a simulated robot may not enter them. Image row 0 (the top of the
picture) is grid row 0, as in MovingAI files. PyYAML is not a dependency: map_server files
are flat ``key: value`` lines, which a ten-line reader handles. A ``.pgm`` given directly
uses the map_server defaults (resolution 0.05 m, thresholds 0.65 / 0.196).
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.grid import GridWorld
from swarmex.worlds.mapfiles import ROS_YAML_SUFFIXES, read_map_text

DEFAULTS = {"resolution": 0.05, "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196}


def parse_yaml_flat(text: str, source: str) -> dict[str, object]:
    """``key: value`` lines (comments allowed) → dict; numbers and [lists] are parsed."""
    out: dict[str, object] = {}
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if ":" not in line:
            raise InputError(f"{source}: line {n} is not 'key: value': {raw.strip()!r}")
        key, value = (s.strip() for s in line.split(":", 1))
        value = value.strip("'\"") if value[:1] in "'\"" else value
        try:
            out[key] = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            out[key] = value
    return out


def _read_pgm(path: Path) -> np.ndarray:
    try:
        from PIL import Image, UnidentifiedImageError

        with Image.open(path) as im:
            return np.asarray(im.convert("L"), dtype=np.uint8)
    except FileNotFoundError:
        raise InputError(f"map image not found: {path}") from None
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise InputError(f"cannot read map image {path}: {exc}") from None


def rosmap_image(path: str | Path) -> Path | None:
    """The image file a ROS map YAML names (None for a ``.pgm`` itself, or a YAML that cannot
    be read or names none): the other file a run on ``path`` reads."""
    path = Path(path)
    if path.suffix.lower() not in ROS_YAML_SUFFIXES:
        return None
    try:
        image = _yaml_meta(path).get("image")
    except InputError:
        return None
    return None if image is None else path.parent / str(image)


def _yaml_meta(path: Path) -> dict[str, object]:
    """The keys of a ROS map YAML (:class:`InputError` if it cannot be read)."""
    return parse_yaml_flat(read_map_text(path, "utf-8"), str(path))


def load_rosmap(path: str | Path) -> tuple[GridWorld, float]:
    """Read a map_server map; returns the world and its resolution (metres per cell)."""
    path = Path(path)
    if path.suffix.lower() == ".pgm":
        meta: dict[str, object] = dict(DEFAULTS, image=path.name)
        yaml_dir = path.parent
    else:
        meta = dict(DEFAULTS)
        meta.update(_yaml_meta(path))
        yaml_dir = path.parent
        if "image" not in meta:
            raise InputError(f"{path}: ROS map YAML lacks 'image'")
    try:
        res = float(meta["resolution"])  # type: ignore[arg-type]
        negate = int(meta["negate"])  # type: ignore[call-overload]
        occ_t = float(meta["occupied_thresh"])  # type: ignore[arg-type]
        free_t = float(meta["free_thresh"])  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"{path}: resolution/negate/thresholds must be numbers") from None
    if not res > 0:
        raise InputError(f"{path}: resolution must be positive, got {res}")
    # map_server's own rules, so a typo is not read as something else ("negate: 5" was an
    # inverted map reported as having no free cell; a bad mode or origin passed unseen)
    if negate not in (0, 1):
        raise InputError(f"{path}: negate must be 0 or 1, got {meta['negate']}")
    mode = meta.get("mode", "trinary")
    if mode not in ("trinary", "scale", "raw"):
        raise InputError(f"{path}: mode must be trinary, scale or raw, got {mode!r}")
    origin = meta.get("origin")
    if origin is not None and not (
        isinstance(origin, list) and len(origin) in (2, 3)
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in origin)
    ):
        raise InputError(f"{path}: origin must be [x, y, yaw] numbers, got {origin!r}")
    if not 0 <= free_t <= occ_t <= 1:
        raise InputError(f"{path}: need 0 <= free_thresh <= occupied_thresh <= 1")
    img = _read_pgm(yaml_dir / str(meta["image"]))
    p = img / 255.0 if negate else (255 - img.astype(np.int32)) / 255.0
    free = p < free_t
    if not free.any():
        raise InputError(f"{path}: the map has no free cell")
    return GridWorld(free, source=str(path)), res
