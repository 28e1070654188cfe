"""Transportation phase (thesis ch. 5): End-to-End (Alg. 14) and Relay (Alg. 15).

Both are rules a robot applies each round to what it sees; :class:`~.sim.Mission` calls them.

* **End-to-End**: walk to the food, pick one unit, walk to the nest, drop, repeat. Moves are
  Alg. 1's distance-reducing steps with the x step first, so robots going out follow the
  x-then-y L from the nest and robots coming back the x-then-y L from the food — two disjoint
  monotone paths whenever nest and food are not collinear (the premise of Theorem 5.3.1).
* **Relay**: one common shortest nest–food path, the same for every robot (from the nest
  along its row, then along the food's column — the released code's L). Robots on it carry
  toward the nest or walk empty toward the food; when an empty robot is on the path cell next
  to a carrier, on the carrier's nest side, the unit is handed over and both turn round (the
  table of §5.2; zero cost, as the theorems assume). Hand-overs never happen *into* the nest
  cell: the carrier walks in and drops, as Agent_1 does in Lemma 5.3.6.
  Joining: **Relay-Food** walks to the food and enters there after picking a unit;
  **Relay-Path** walks to the nearest path cell (ties toward the food) and enters empty.

Pick-up, drop and hand-over happen in the Look of the round after the robot arrives or becomes
adjacent and cost no extra round. The mission ends the moment the k-th unit is in the nest; a
robot that finds the source empty stays idle (it would learn ``foodUnits = 0`` there).
"""

from __future__ import annotations

from swarmex.missions.foraging.grid import Cell, lpath, manhattan

END_TO_END, RELAY_FOOD, RELAY_PATH = "end-to-end", "relay-food", "relay-path"
TRANSPORTS = (RELAY_FOOD, RELAY_PATH, END_TO_END)


def relay_path(nest: Cell, food: Cell) -> list[Cell]:
    """The common nest→food path every robot computes the same way."""
    return [nest, *lpath(nest, food, x_first=True)]


def entry_cell(path: list[Cell], p: Cell) -> int:
    """Relay-Path: index of the path cell nearest ``p`` (ties toward the food)."""
    best = min(range(len(path)), key=lambda i: (manhattan(path[i], p), -i))
    return best
