"""What the map readers share: which files are ROS maps, and reading a map file's text with
one line for a missing or unreadable file (the MovingAI and ROS readers had a copy each)."""

from __future__ import annotations

import os
from pathlib import Path

from swarmex.errors import InputError

#: a ROS map_server map: its YAML, or the image alone
ROS_YAML_SUFFIXES = (".yaml", ".yml")
ROS_SUFFIXES = (*ROS_YAML_SUFFIXES, ".pgm")


def maps_dir() -> Path:
    """The folder of the real benchmark maps (MovingAI): ``$SWARMEX_MAPS``, else
    ``../shared/maps`` from the working folder, else beside this checkout. One place, so the
    studies, the tests and the bench scripts look for the maps in the same folder."""
    env = os.environ.get("SWARMEX_MAPS")
    if env:
        return Path(env)
    for cand in (Path("../shared/maps"), Path(__file__).resolve().parents[4] / "shared" / "maps"):
        if cand.is_dir():
            return cand
    return Path("../shared/maps")


def source_name(source: str) -> str:
    """A world's source as a title shows it: a map file's name without its folders (a deep
    path overflowed titles and the monitor's header), anything else as it is."""
    return source.replace("\\", "/").rsplit("/", 1)[-1]


def is_ros_map(path: str | Path) -> bool:
    return str(path).lower().endswith(ROS_SUFFIXES)


def read_map_text(path: Path, encoding: str) -> str:
    """The file's text (undecodable bytes replaced), or an InputError naming the file."""
    try:
        return path.read_text(encoding=encoding, errors="replace")
    except FileNotFoundError:
        raise InputError(f"map file not found: {path}") from None
    except OSError as exc:
        raise InputError(f"cannot read map file {path}: {exc.strerror}") from None
