"""What an exploration pattern hands to the engine: one route per robot and its schedule.

A :class:`Plan` is pure data computed from ``(g, n)`` alone, i.e. from what every robot can
compute for itself once it has met the boundary (Θ(log g) state: its id, ``g``, ``n`` and a
position counter along the pattern; the lists here are a simulation convenience, never a
map held by a robot). The engine executes it: robot ``a`` stays in the nest until round
``depart[a]``, walks ``route[a]``; with ``sync`` it waits at ``route[a][explore_from[a]]``
(its Start-Cell) until every robot has reached its own, and all begin exploring together
(Strips, ZigZag/Hilbert, as the thesis requires for the regular meetings).

``neighbours[a]`` are the robots ``a`` must tell the food location (ch. 4), and
``follow_path_comm`` says the pattern delivers it without detours (Strips, ZigZag n = 4).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from swarmex.missions.foraging.grid import Cell, is_walk, nest_of


@dataclass
class Plan:
    algorithm: str
    g: int
    n: int
    routes: list[list[Cell]]
    depart: list[int]
    explore_from: list[int]
    neighbours: list[list[int]]
    sync: bool = False
    follow_path_comm: bool = False
    notes: dict[str, object] = field(default_factory=dict)

    @property
    def nest(self) -> Cell:
        return nest_of(self.g)

    def validate(self) -> None:
        """Internal consistency: every route starts in the nest and is a walk."""
        for a, r in enumerate(self.routes):
            if r[0] != self.nest:
                raise AssertionError(f"{self.algorithm}: route {a} does not start in the nest")
            if not is_walk(r):
                raise AssertionError(f"{self.algorithm}: route {a} is not a walk")
            if any(not (0 <= x < self.g and 0 <= y < self.g) for x, y in r):
                raise AssertionError(f"{self.algorithm}: route {a} leaves the grid")
