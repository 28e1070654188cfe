"""GPS grids: seed 000's square grid of K x K nodes around a latitude and longitude.

Seed 000 built its field graphs with ``writegraphToArray(radius, pointsOnEdge, centerLat,
centerLon, *obstacles)`` (§4.3): K nodes on an edge, a square "radius of work" R around the
centre, every node with its own latitude and longitude, so that real UAVs fly to real
positions. :func:`gps_grid` builds that grid as a :class:`GeoGrid`:

* node ``(x, y)`` (x the column, y the row, row 0 the **north** edge, as a map is drawn) sits
  ``e = -R + x * s`` metres east and ``n = R - y * s`` metres north of the centre, with
  ``s = 2R / (K - 1)``: the K x K nodes span 2R metres each way, centred on the point (the
  centre is a node when K is odd);
* its position is the end of the geodesic from the centre with azimuth ``atan2(e, n)`` and
  length ``hypot(e, n)`` on the WGS84 ellipsoid (``pyproj.Geod.fwd``): an azimuthal
  equidistant layout, exact in distance and direction from the centre;
* every edge is as long as the geodesic between its two nodes (``pyproj.Geod.inv``), so
  travel times follow real distances. On a 100 m field the edges differ from ``s`` by well
  under a millimetre; the layout is what a user's GPS points are, not a flat-earth grid.

pyproj is the optional extra ``swarmex[geo]``. A GeoGrid made from known positions and edge
lengths (what a networked agent receives with the mission data) needs no pyproj.
docs/uav.md compares a grid built here with the seed's printed example.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from swarmex.errors import InputError, require
from swarmex.worlds.grid import GridWorld

ELLIPSOID = "WGS84"
MAX_NODES_ON_EDGE = 1000  # the record lists every node's latitude and longitude
MAX_RADIUS = 100_000.0  # metres: a field, not a map projection


def _geod() -> Any:
    require("pyproj", "geo", "a GPS grid (--center)")
    from pyproj import Geod

    return Geod(ellps=ELLIPSOID)


def north_east(origin: tuple[float, float], there: tuple[float, float]) -> tuple[float, float]:
    """Metres north and east of ``origin`` to ``there`` (both ``(lat, lon)``) along the
    WGS84 geodesic: what a vehicle flies from its nest, and how far it stands from it."""
    azimuth, _, dist = _geod().inv(origin[1], origin[0], there[1], there[0])
    a = math.radians(azimuth)
    return float(dist * math.cos(a)), float(dist * math.sin(a))


def check_center(lat: float, lon: float, flag: str = "--center") -> None:
    if not -90.0 < lat < 90.0:
        raise InputError(f"{flag}: latitude must be between -90 and 90 (poles excluded), "
                         f"got {lat:g}")
    if not -180.0 <= lon <= 180.0:
        raise InputError(f"{flag}: longitude must be between -180 and 180, got {lon:g}")


def grid_offsets(radius: float, nodes_on_edge: int) -> tuple[np.ndarray, np.ndarray]:
    """Each node's (east, north) offset from the centre in metres, row-major, row 0 north."""
    k = nodes_on_edge
    s = 2.0 * radius / (k - 1)
    ys, xs = np.divmod(np.arange(k * k), k)
    return -radius + xs * s, radius - ys * s


def grid_latlon(center: tuple[float, float], radius: float, nodes_on_edge: int) -> np.ndarray:
    """[lat, lon] of every node (row-major), geodesic from the centre (see the module)."""
    lat0, lon0 = center
    check_center(lat0, lon0)
    east, north = grid_offsets(radius, nodes_on_edge)
    az = np.degrees(np.arctan2(east, north))
    dist = np.hypot(east, north)
    n = east.size
    lon, lat, _ = _geod().fwd(np.full(n, lon0), np.full(n, lat0), az, dist)
    return np.stack([np.asarray(lat, dtype=float), np.asarray(lon, dtype=float)], axis=1)


class GeoGrid(GridWorld):
    """A :class:`GridWorld` whose nodes have latitudes and longitudes and whose edges are
    as long as the geodesics between them, in metres.

    Trajectories and drawings stay in cells (x, y), as for every grid; ``latlon(node)`` is
    where a vehicle flies, and ``describe()`` adds ``nodes_latlon`` (row-major [lat, lon]) and
    the grid's centre, radius and nominal edge.
    """

    def __init__(
        self,
        free: np.ndarray,
        connectivity: int,
        latlon: np.ndarray,
        center: tuple[float, float],
        radius: float,
        source: str | None = None,
        lengths: np.ndarray | None = None,
    ) -> None:
        free = np.asarray(free, dtype=bool)
        h, w = free.shape if free.ndim == 2 else (0, 0)
        if h != w or h < 2:
            raise InputError(f"a GPS grid is square with at least 2x2 nodes, got {free.shape}")
        latlon = np.asarray(latlon, dtype=float)
        if latlon.shape != (h * w, 2) or not np.all(np.isfinite(latlon)):
            raise InputError("a GPS grid needs one finite [lat, lon] per node")
        lat, lon = center
        src = source or f"gps {lat:.6f},{lon:.6f} r{radius:g} m {w}x{h}"
        super().__init__(free, connectivity, src)
        self.latlon_array = latlon
        self.center = (float(lat), float(lon))
        self.radius = float(radius)
        self._lengths = None if lengths is None else np.asarray(lengths, dtype=float)

    @property
    def nodes_on_edge(self) -> int:
        return self.width

    @property
    def edge_m(self) -> float:
        """The nominal edge: 2R / (K - 1) metres."""
        return 2.0 * self.radius / (self.nodes_on_edge - 1)

    def latlon(self, node: int) -> tuple[float, float]:
        lat, lon = self.latlon_array[int(node)]
        return float(lat), float(lon)

    def edge_lengths(self, u: np.ndarray, v: np.ndarray, unit: np.ndarray) -> np.ndarray:
        if self._lengths is not None:
            if self._lengths.shape != u.shape or not np.all(self._lengths > 0):
                raise InputError("GPS grid: the edge lengths do not fit the grid")
            return self._lengths
        a, b = self.latlon_array[u], self.latlon_array[v]
        _, _, dist = _geod().inv(a[:, 1], a[:, 0], b[:, 1], b[:, 0])
        self._lengths = np.asarray(dist, dtype=float)
        return self._lengths

    def lengths(self) -> np.ndarray:
        """Every edge's length in metres, in :meth:`edge_arrays` order."""
        if self._lengths is None:
            u, v, unit = self.edge_arrays()
            self.edge_lengths(u, v, unit)
        assert self._lengths is not None
        return self._lengths

    def with_free(self, free: np.ndarray) -> GeoGrid:
        """The same grid with other cells blocked (lengths recomputed for the new edges)."""
        return GeoGrid(free, self.connectivity, self.latlon_array, self.center, self.radius,
                       self.source)

    def describe(self) -> dict[str, Any]:
        d = super().describe()
        d["center"] = list(self.center)
        d["radius_m"] = self.radius
        d["nodes_on_edge"] = self.nodes_on_edge
        d["edge_m"] = self.edge_m
        d["ellipsoid"] = ELLIPSOID
        d["nodes_latlon"] = self.latlon_array.tolist()
        return d

    def __repr__(self) -> str:
        lat, lon = self.center
        return (f"GeoGrid({self.width}x{self.height} around {lat:.6f},{lon:.6f}, "
                f"r {self.radius:g} m, {self.free_cells} free)")


def gps_grid(
    center: tuple[float, float],
    radius: float,
    nodes_on_edge: int,
    connectivity: int = 4,
) -> GeoGrid:
    """Seed 000's grid: ``nodes_on_edge`` x ``nodes_on_edge`` nodes spanning 2 x ``radius``
    metres, centred on ``center`` = (lat, lon), every node free."""
    if not (math.isfinite(radius) and 0 < radius <= MAX_RADIUS):
        raise InputError(f"--radius must be in (0, {MAX_RADIUS:g}] metres, got {radius:g}")
    if not 2 <= nodes_on_edge <= MAX_NODES_ON_EDGE:
        raise InputError(
            f"--nodes-on-edge must be in 2..{MAX_NODES_ON_EDGE}, got {nodes_on_edge}"
        )
    lat0, lon0 = center
    check_center(lat0, lon0)
    pole = 90.0 if lat0 >= 0 else -90.0
    _, _, to_pole = _geod().inv(lon0, lat0, lon0, pole)
    if radius >= to_pole:  # the pole lies due north (south) of the centre: in the square
        raise InputError(
            f"--center {lat0},{lon0} with --radius {radius:g}: the grid reaches the"
            f" {'north' if pole > 0 else 'south'} pole ({to_pole:,.0f} m away); a GPS grid"
            " must not contain a pole"
        )
    latlon = grid_latlon(center, radius, nodes_on_edge)
    free = np.ones((nodes_on_edge, nodes_on_edge), dtype=bool)
    return GeoGrid(free, connectivity, latlon, center, radius)


__all__ = ["ELLIPSOID", "GeoGrid", "grid_latlon", "grid_offsets", "gps_grid"]
