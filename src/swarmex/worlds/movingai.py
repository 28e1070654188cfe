"""Loader for MovingAI ``.map`` files (Sturtevant 2012), the format of ``../shared/maps``.

Header: ``type <name>``, ``height H``, ``width W``, ``map``, then exactly H rows of W
terrain letters. The letters, and how swarmex reads them for a ground agent:

=====  ===========================================  =========
char   MovingAI meaning                             swarmex
=====  ===========================================  =========
``.``  passable terrain                             free
``G``  passable terrain                             free
``S``  swamp, passable from regular terrain         free
``@``  out of bounds                                blocked
``O``  out of bounds                                blocked
``T``  trees, unpassable                            blocked
``W``  water, traversable only from water           blocked
=====  ===========================================  =========

Water is blocked because an agent on land can never enter it (the format says water is not
passable from terrain), and no mission here starts agents in water. The raw letters are kept
in ``GridWorld.terrain`` so a caller can choose otherwise.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from swarmex.errors import InputError
from swarmex.worlds.grid import GridWorld
from swarmex.worlds.mapfiles import is_ros_map, read_map_text

TERRAIN_FREE = frozenset(".GS")
TERRAIN_BLOCKED = frozenset("@OTW")
TERRAIN = TERRAIN_FREE | TERRAIN_BLOCKED


def parse_movingai(text: str, source: str = "<string>", connectivity: int = 4) -> GridWorld:
    lines = text.splitlines()
    header: dict[str, str] = {}
    i = 0
    while i < len(lines) and lines[i].strip().lower() != "map":
        parts = lines[i].split()
        if len(parts) == 2:
            header[parts[0].lower()] = parts[1]
        elif parts:
            raise InputError(f"{source}: malformed header line {i + 1}: {lines[i]!r}")
        i += 1
    if i == len(lines):
        raise InputError(f"{source}: not a MovingAI map (no 'map' line)")
    try:
        height, width = int(header["height"]), int(header["width"])
    except KeyError as missing:
        raise InputError(f"{source}: header lacks {missing.args[0]!r}") from None
    except ValueError:
        raise InputError(f"{source}: height/width must be integers") from None
    if height < 1 or width < 1:
        raise InputError(f"{source}: height and width must be positive, got {height}x{width}")
    rows = [line.rstrip("\r\n") for line in lines[i + 1 :]]
    while rows and not rows[-1].strip():
        rows.pop()
    if len(rows) != height:
        raise InputError(f"{source}: header says height {height} but the map has {len(rows)} rows")
    for r, row in enumerate(rows):
        if len(row) != width:
            raise InputError(
                f"{source}: header says width {width} but row {r} has {len(row)} characters"
            )
    terrain = np.frombuffer("".join(rows).encode("ascii", "replace"), dtype=np.uint8)
    terrain = terrain.reshape(height, width)
    known = np.zeros(256, dtype=bool)
    known[[ord(c) for c in TERRAIN]] = True
    if not known[terrain].all():
        bad = sorted({chr(c) for c in np.unique(terrain[~known[terrain]])})
        raise InputError(f"{source}: unknown terrain letters {''.join(bad)!r}")
    free_lut = np.zeros(256, dtype=bool)
    free_lut[[ord(c) for c in TERRAIN_FREE]] = True
    return GridWorld(free_lut[terrain], connectivity=connectivity, source=source, terrain=terrain)


def load_movingai(path: str | Path, connectivity: int = 4) -> GridWorld:
    path = Path(path)
    if is_ros_map(path):  # "malformed header line 3" misled
        raise InputError(f"{path}: a ROS map, not a MovingAI .map (swarmex explore reads ROS"
                         " maps; this option reads MovingAI files)")
    text = read_map_text(path, "ascii")
    return parse_movingai(text, source=str(path), connectivity=connectivity)


def to_movingai(world: GridWorld) -> str:
    """Serialise a grid back to the format ('.' free, '@' blocked)."""
    rows = ["".join("." if f else "@" for f in row) for row in world.free]
    return "type octile\nheight {}\nwidth {}\nmap\n{}\n".format(
        world.height, world.width, "\n".join(rows)
    )
