"""Agent parameters of seed 000 §4.3 and the derived times.

Each UAV has its own travel speed, job time, target altitude and climb/descent speeds.
Lengths are in the world's length unit times ``unit_length`` metres (a grid edge is one unit;
``unit_length`` is the node spacing). Speeds are metres per second.

``additional_time`` = takeoff (altitude / up speed) + return-to-launch along the shortest path
to the nest + landing (altitude / down speed), the thesis's ``additionalTime_i``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from swarmex.errors import InputError


@dataclass(frozen=True)
class AgentSpec:
    nest: int
    travel_speed: float = 1.0  # metres per second
    job_time: float = 0.0  # seconds per job
    altitude: float = 0.0  # metres above the nest
    up_speed: float = 1.0  # metres per second
    down_speed: float = 1.0  # metres per second

    def __post_init__(self) -> None:
        if not self.travel_speed > 0:
            raise InputError(f"travel speed must be > 0, got {self.travel_speed}")
        if self.job_time < 0:
            raise InputError(f"job time must be >= 0, got {self.job_time}")
        if self.altitude < 0:
            raise InputError(f"altitude must be >= 0, got {self.altitude}")
        if not (self.up_speed > 0 and self.down_speed > 0):
            raise InputError("climb and descent speeds must be > 0")

    @property
    def takeoff_time(self) -> float:
        return self.altitude / self.up_speed

    @property
    def landing_time(self) -> float:
        return self.altitude / self.down_speed

    def to_dict(self) -> dict:
        return asdict(self)


def uniform_agents(
    nests: list[int],
    travel_time: float,
    job_time: float,
    unit_length: float = 1.0,
    altitude: float = 0.0,
    up_speed: float = 1.0,
    down_speed: float = 1.0,
) -> list[AgentSpec]:
    """Identical agents; ``travel_time`` is seconds per unit edge (the CLI's --travel-time)."""
    if not travel_time > 0:
        raise InputError(f"travel time must be > 0, got {travel_time}")
    speed = unit_length / travel_time
    return [
        AgentSpec(n, speed, job_time, altitude, up_speed, down_speed) for n in nests
    ]
