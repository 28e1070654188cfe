"""Fingerprints of exploration runs at several team sizes (issue 14, item 2).

Recorded *before* the exploration scale work so that every speed change (spatial index for
the radio, shared scans, delta merges, incremental frontiers) is checked to give the same
records bit for bit: 5, 10 and 20 robots, with and without AODV, a short radio (the mesh
splits and re-joins, so flooding, ``NEED_MAP``/``MAP`` catch-up and AODV routes all run),
on an empty field and on a walled map with doors, plus the other strategies at 10 robots.

Regenerate only for a deliberate change of results, from the repository root:
``PYTHONPATH=src python -m tests.missions.exploration.fingerprints``.
"""

from __future__ import annotations

import hashlib
import json
import sys
import tempfile
from pathlib import Path
from typing import Any

import swarmex

RECORDS = Path(__file__).with_name("fingerprints.json")

# a 64 x 48 cell map at 0.125 m: four rooms, doors 3 cells wide, a stub wall in one room


def _rooms() -> list[str]:
    w, h = 64, 48
    grid = [["." for _ in range(w)] for _ in range(h)]
    for x in range(w):
        grid[0][x] = grid[h - 1][x] = grid[23][x] = "@"
    for y in range(h):
        grid[y][0] = grid[y][w - 1] = grid[y][31] = "@"
    for y in (10, 11, 12, 34, 35, 36):  # doors in the vertical wall
        grid[y][31] = "."
    for x in (11, 12, 13, 45, 46, 47):  # doors in the horizontal wall
        grid[23][x] = "."
    for x in range(40, 56):  # a stub wall
        grid[8][x] = "@"
    return ["".join(row) for row in grid]


ROOMS = _rooms()


def rooms_map(folder: Path) -> Path:
    path = folder / "rooms.map"
    body = "\n".join(ROOMS)
    path.write_text(f"type octile\nheight {len(ROOMS)}\nwidth {len(ROOMS[0])}\nmap\n{body}\n")
    return path


def scenarios(folder: Path) -> dict[str, dict[str, Any]]:
    """Name -> keyword arguments of ``swarmex.run("exploration", ...)``."""
    out: dict[str, dict[str, Any]] = {}
    for n in (5, 10, 20):
        for aodv in (True, False):
            tag = "aodv" if aodv else "noaodv"
            out[f"empty-{n}-{tag}"] = dict(
                empty=(8.0, 8.0), cell=0.1, robots=n, laser_range=1.0, comm_range=2.0,
                aodv=aodv, seed=1,
            )
            out[f"rooms-{n}-{tag}"] = dict(
                map=rooms_map(folder), cell=0.125, robots=n, laser_range=1.0, comm_range=1.5,
                robot_radius=0.1, aodv=aodv, seed=2,
            )
    out["fine-20-aodv"] = dict(
        empty=(5.0, 5.0), cell=0.05, robots=20, laser_range=0.6, comm_range=1.5, seed=3,
    )
    for st in ("greedy", "utility", "minpos", "hungarian"):
        out[f"empty-10-{st}"] = dict(
            empty=(8.0, 8.0), cell=0.1, robots=10, laser_range=1.0, comm_range=2.0,
            strategy=st, seed=4,
        )
    return out


def digest(record: dict[str, Any]) -> str:
    """SHA-256 of the record without ``wall_seconds``; a map file's folder (a temporary
    one) is cut from the world's source."""
    record = {k: v for k, v in record.items() if k != "wall_seconds"}
    world = dict(record["world"])
    world["source"] = Path(str(world["source"])).name
    record["world"] = world
    text = json.dumps(record, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def run_one(kwargs: dict[str, Any]) -> dict[str, Any]:
    return swarmex.run("exploration", **kwargs).to_dict()


if __name__ == "__main__":
    table = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, kw in scenarios(Path(tmp)).items():
            rec = run_one(kw)
            table[name] = {"sha256": digest(rec), "makespan": rec["makespan"],
                           "complete": rec["complete"],
                           "messages_sent": rec["metrics"].get("messages_sent")}
            print(name, table[name], file=sys.stderr)
    RECORDS.write_text(json.dumps(table, indent=1, sort_keys=True) + "\n")
