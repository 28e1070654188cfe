"""Shared fixtures: where the real benchmark maps live, and skipping when they are absent."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def maps_dir() -> Path:
    return Path(os.environ.get("SWARMEX_MAPS", REPO.parent / "shared" / "maps"))


@pytest.fixture
def real_map():
    """Path of a map in SWARMEX_MAPS, or a skip naming what is missing."""

    def get(name: str) -> Path:
        path = maps_dir() / name
        if not path.exists():
            pytest.skip(f"real map {name} not found in {maps_dir()} (set SWARMEX_MAPS)")
        return path

    return get
