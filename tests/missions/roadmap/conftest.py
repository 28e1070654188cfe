"""Small generated environments for the roadmap tests (fast: 200 × 150 units)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from swarmex.worlds.polygon import PolygonWorld, parse_polygon_json

CLUTTER = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [
        [[40, 30], [70, 30], [70, 60], [40, 60]],
        [[100, 20], [130, 50], [100, 80]],
        [[150, 90], [190, 90], [190, 100], [150, 100]],
        [[30, 100], [90, 100], [90, 108], [38, 108], [38, 140], [30, 140]],
    ],
    "goal": [175, 130],
}

# the team's corner is walled in; the goal is outside (Figs. 14-16)
ENCLOSED = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [
        [[0, 60], [80, 60], [80, 66], [0, 66]],
        [[74, 0], [80, 0], [80, 66], [74, 66]],
        [[120, 90], [160, 90], [160, 100], [120, 100]],
    ],
    "goal": [170, 130],
}


def make(env: dict) -> PolygonWorld:
    return parse_polygon_json(json.dumps(env), "test")


@pytest.fixture(scope="session")
def clutter() -> PolygonWorld:
    return make(CLUTTER)


@pytest.fixture(scope="session")
def enclosed() -> PolygonWorld:
    return make(ENCLOSED)


def cluster(n: int, centre=(12.0, 12.0), rho: float = 4.0) -> np.ndarray:
    if n == 1:
        return np.array([centre], dtype=float)
    ang = 2 * np.pi * np.arange(n) / n
    return np.asarray(centre) + rho * np.column_stack([np.cos(ang), np.sin(ang)])
