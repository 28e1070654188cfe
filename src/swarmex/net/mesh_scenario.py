"""The mesh run's scenario: what every process of one run reads from the run directory.

The launcher writes the world, the mission's parameters and the network's options once
(``scenario.msgpack``, in the wire format of :mod:`swarmex.net.wire`); each robot and the
display read them back at start. It lives apart from the processes so that both sides of
the hand-over (the launcher in :mod:`swarmex.net.mesh`, the nodes in
:mod:`swarmex.net.mesh_node`) share one definition of the file and of :class:`MeshOptions`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swarmex.net import wire

if TYPE_CHECKING:  # imported where used: each process loads only what it needs
    from swarmex.missions.exploration.params import ExplorationParams
    from swarmex.worlds.metric import MetricGrid


@dataclass
class MeshOptions:
    """The network's own options (the mission's are :class:`ExplorationParams`)."""

    time_scale: float = 1.0  # wall seconds per mission second (a tick is 0.1 s)
    loss: float = 0.0  # share of radio frames dropped at the receiver (fault injection)
    send_timeout_ms: int = 20
    dead_after: float = 4.0  # wall seconds without STATUS before the display drops a robot
    settle_ticks: int = 20  # all live robots finished for this many ticks → stop
    start_timeout: float = 60.0  # wall seconds to wait for every robot's HELLO
    timeout: float = 600.0  # wall seconds for the whole run
    inject_kill: dict[int, int] = field(default_factory=dict)  # robot id -> tick to die at
    display_cell: tuple[int, int] | None = None  # default: the first robot's start

    def to_wire(self) -> dict[str, Any]:
        return {
            "time_scale": self.time_scale, "loss": self.loss,
            "send_timeout_ms": self.send_timeout_ms, "dead_after": self.dead_after,
            "settle_ticks": self.settle_ticks, "start_timeout": self.start_timeout,
            "timeout": self.timeout,
            "inject_kill": [[int(k), int(v)] for k, v in self.inject_kill.items()],
            "display_cell": None if self.display_cell is None else list(self.display_cell),
        }

    @classmethod
    def from_wire(cls, d: dict[str, Any]) -> MeshOptions:
        cell = d.get("display_cell")
        return cls(
            float(d["time_scale"]), float(d["loss"]), int(d["send_timeout_ms"]),
            float(d["dead_after"]), int(d["settle_ticks"]), float(d["start_timeout"]),
            float(d["timeout"]), {int(k): int(v) for k, v in d.get("inject_kill") or []},
            None if cell is None else (int(cell[0]), int(cell[1])),
        )


def write_scenario(run_dir: Path, grid: MetricGrid, params: ExplorationParams,
                   options: MeshOptions, json_path: Path | None) -> None:
    from swarmex.missions.exploration.params import default_starts

    starts = params.starts or default_starts(grid, params.robots, params.robot_radius)
    p = params.as_dict()
    p["starts"] = [list(s) for s in starts]
    data = {
        "grid": {
            "width": grid.world.width, "height": grid.world.height, "cell": grid.cell,
            "free": np.packbits(grid.free.ravel()).tobytes(), "source": grid.world.source,
        },
        "params": p,
        "options": options.to_wire(),
        "json": None if json_path is None else str(json_path),
    }
    tmp = run_dir / "scenario.tmp"
    tmp.write_bytes(wire.pack(data))
    tmp.rename(run_dir / "scenario.msgpack")


def read_scenario(
    run_dir: Path,
) -> tuple[MetricGrid, ExplorationParams, MeshOptions, str | None]:
    """(grid, params, options, json path) of a run directory."""
    from swarmex.missions.exploration.params import ExplorationParams
    from swarmex.worlds import GridWorld
    from swarmex.worlds.metric import MetricGrid

    d = wire.unpack((run_dir / "scenario.msgpack").read_bytes())
    g = d["grid"]
    w, h = int(g["width"]), int(g["height"])
    free = np.unpackbits(np.frombuffer(g["free"], np.uint8), count=w * h).astype(bool)
    grid = MetricGrid(GridWorld(free.reshape(h, w), source=str(g["source"])), float(g["cell"]))
    p = dict(d["params"])
    p["starts"] = tuple((int(x), int(y)) for x, y in p["starts"])
    p["comm_range"] = math.inf if p["comm_range"] is None else float(p["comm_range"])
    params = ExplorationParams(**p)
    return grid, params, MeshOptions.from_wire(d["options"]), d.get("json")
