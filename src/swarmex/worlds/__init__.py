"""The static environment: the only truth. Beliefs live with the agents."""

from swarmex.worlds.generators import empty_grid, maze, random_obstacles, rooms
from swarmex.worlds.graph import GraphWorld
from swarmex.worlds.grid import GridWorld
from swarmex.worlds.movingai import load_movingai, parse_movingai
from swarmex.worlds.nodegraph import NodeGraph

__all__ = [
    "GraphWorld",
    "GridWorld",
    "NodeGraph",
    "empty_grid",
    "load_movingai",
    "maze",
    "parse_movingai",
    "random_obstacles",
    "rooms",
]

from swarmex.worlds.polygon import (  # noqa: E402
    PolygonWorld,
    load_polygon_world,
    parse_polygon_json,
)

__all__ += ["PolygonWorld", "load_polygon_world", "parse_polygon_json"]
