"""MovingAI loader: every terrain letter, header validation, and the real maps."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.worlds import load_movingai, parse_movingai
from swarmex.worlds.movingai import to_movingai

ALL_LETTERS = "type octile\nheight 2\nwidth 4\nmap\n.GS@\nOTW.\n"


def test_every_terrain_letter():
    w = parse_movingai(ALL_LETTERS)
    # free: . G S ; blocked: @ O T W
    assert w.free.tolist() == [[True, True, True, False], [False, False, False, True]]
    assert chr(w.terrain[1, 2]) == "W"


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("type octile\nheight 2\nwidth 2\nmap\n..\n", "height 2 but the map has 1 rows"),
        ("type octile\nheight 1\nwidth 3\nmap\n..\n", "width 3 but row 0 has 2"),
        ("type octile\nheight x\nwidth 2\nmap\n..\n", "integers"),
        ("type octile\nwidth 2\nmap\n..\n", "'height'"),
        ("type octile\nheight 1\nwidth 2\n..\n", "malformed header line 4"),
        ("type octile\nheight 1\nwidth 2\n", "no 'map' line"),
        ("type octile\nheight 1\nwidth 2\nmap\n.Z\n", "unknown terrain letters 'Z'"),
        ("type octile\nheight 0\nwidth 2\nmap\n", "positive"),
    ],
)
def test_malformed_maps_name_the_problem(text, needle):
    with pytest.raises(InputError, match=None) as err:
        parse_movingai(text, source="bad.map")
    assert needle in str(err.value)
    assert str(err.value).startswith("bad.map")


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        load_movingai(tmp_path / "nope.map")


def test_round_trip(tmp_path):
    w = parse_movingai(ALL_LETTERS)
    path = tmp_path / "x.map"
    path.write_text(to_movingai(w))
    again = load_movingai(path)
    assert np.array_equal(again.free, w.free)


def test_real_map_header_and_free_cells(real_map):
    w = load_movingai(real_map("den520d.map"))
    assert (w.width, w.height) == (256, 257)
    assert w.free_cells == 28178  # the count the traversal issue quotes
    # independent count straight from the text
    rows = real_map("den520d.map").read_text().splitlines()[4:]
    assert sum(row.count(".") + row.count("G") + row.count("S") for row in rows) == 28178
