"""Start positions and goal: validation and the default start cluster.

Seed 004 assumes the agents "are situated close to each other" (§2) but never says where. The
default here is deterministic — the same team layout in every run, so that runs differ only
by their roadmaps: n agents on a circle of radius ρ = 1 % of the larger side × max(1, n/3)
(6.4 units for up to 3 agents on a 640 × 480 map), the first at angle 0, centred on the point
of the free space nearest the visually lower-left corner that keeps ρ + 2 % of the larger side
of clearance (so the whole cluster, and its convex hull, are free).
"""

from __future__ import annotations

import numpy as np
import shapely

from swarmex.errors import InputError
from swarmex.worlds.polygon import PolygonWorld


def default_starts(world: PolygonWorld, n: int) -> np.ndarray:
    scale = max(world.width, world.height)
    rho = 0.01 * scale * max(1.0, n / 3.0)
    margin = rho + 0.02 * scale
    room = shapely.buffer(world.free_region, -margin)
    if room.is_empty:
        raise InputError(  # the user did not choose this cluster: say how to avoid it
            f"no free spot with {margin:g} units of clearance for the default cluster of {n}"
            " agents: give their positions with --starts"
        )
    corner = shapely.Point(world.lower_left())
    centre = np.asarray(shapely.shortest_line(room, corner).coords[0])
    if n == 1:
        return centre[None].copy()
    ang = 2.0 * np.pi * np.arange(n) / n
    return centre + rho * np.column_stack([np.cos(ang), np.sin(ang)])


def check_starts(world: PolygonWorld, starts: np.ndarray, n: int) -> np.ndarray:
    starts = np.asarray(starts, dtype=np.float64).reshape(-1, 2)
    if len(starts) != n:
        raise InputError(f"--starts gives {len(starts)} positions for --agents {n}")
    inside = world.in_bounds(starts)
    free = world.points_free(starts)
    for i, p in enumerate(starts):
        if not inside[i]:
            raise InputError(f"start {i} ({p[0]:g},{p[1]:g}) is outside the bounds")
        if not free[i]:
            raise InputError(f"start {i} ({p[0]:g},{p[1]:g}) is inside an obstacle")
    return starts


def check_goal(world: PolygonWorld, goal: np.ndarray) -> np.ndarray:
    goal = np.asarray(goal, dtype=np.float64).reshape(2)
    if not world.in_bounds(goal)[0]:
        xmin, ymin, xmax, ymax = world.bounds
        raise InputError(
            f"goal ({goal[0]:g},{goal[1]:g}) is outside the bounds "
            f"[{xmin:g},{xmax:g}]x[{ymin:g},{ymax:g}]"
        )
    if not world.points_free(goal)[0]:
        raise InputError(f"goal ({goal[0]:g},{goal[1]:g}) is inside an obstacle")
    return goal
