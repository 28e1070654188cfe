"""``swarmex.run("traversal", map=GridWorld)``: a world built in Python runs as its file does.

Roadmap's ``env`` took a PolygonWorld, but traversal's ``map`` refused a GridWorld ("expected a
file path"), so a world generated or edited in Python had to be written to a .map first.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import swarmex
from swarmex.worlds import GridWorld, load_movingai

TINY = Path(__file__).resolve().parents[2] / "golden" / "tiny.map"


def _run_part(record: swarmex.ResultRecord) -> dict:
    data = record.to_dict()
    data.pop("wall_seconds")
    data["params"] = {k: v for k, v in data["params"].items() if k not in ("map", "generated")}
    return data


@pytest.mark.parametrize("connectivity", [4, 8])
def test_a_gridworld_runs_like_its_map_file(connectivity: int) -> None:
    by_file = swarmex.run("traversal", map=TINY, agents=2, connectivity=connectivity, seed=5)
    world = load_movingai(TINY)  # 4-connected: the option's connectivity applies
    by_object = swarmex.run("traversal", map=world, agents=2, connectivity=connectivity, seed=5)
    assert _run_part(by_object) == _run_part(by_file)
    assert by_file.params["map"] == str(TINY)
    assert by_object.params["map"] is None and by_object.params["generated"] == str(TINY)


def test_a_gridworld_takes_obstacles_and_nests_and_is_checked() -> None:
    free = np.ones((6, 6), dtype=bool)
    free[2, 1:5] = False
    record = swarmex.run("traversal", map=GridWorld(free), agents=2, obstacles="0,0",
                         nests="5,5")
    assert record.complete and record.world["free_cells"] == 31
    with pytest.raises(swarmex.InputError, match="only 0 free cells"):
        swarmex.run("traversal", map=GridWorld(np.zeros((3, 3), dtype=bool)), agents=1)
    with pytest.raises(swarmex.InputError, match="a .map file path or a GridWorld"):
        swarmex.run("traversal", map=42, agents=1)
