"""Independent replay of a foraging result record (the JSON of DESIGN.md).

It uses nothing from the simulator: only the record's ``params``, ``world`` and trajectories.
It checks that every robot starts in the nest, is listed at every round ``0 … makespan``, moves
at most one cell (4-neighbour) per round and stays in the grid; that no two robots share a
non-nest cell in any round; that two robots exchange cells only if they were adjacent (a swap,
Fig. 3); that pick-ups happen on the food cell and drops in the nest, no more than ``k`` of
each; and that ``complete`` is true exactly when ``k`` drops were made.
"""

from __future__ import annotations

from typing import Any


def replay(record: dict[str, Any]) -> list[str]:
    """Every violation found, as readable lines (empty when the record is legal)."""
    errors: list[str] = []
    p = record["params"]
    g = int(p["grid"])
    nest = (g // 2, g // 2)
    food = tuple(p["food"])
    k = int(p["food_units"])
    T = int(record["makespan"])
    agents = record["agents"]
    traj = []
    for ag in agents:
        tr = ag["trajectory"]
        if [int(r[0]) for r in tr] != list(range(T + 1)):
            errors.append(f"robot {ag['id']}: trajectory does not list every round 0…{T}")
            return errors
        traj.append([(int(r[1]), int(r[2])) for r in tr])
    for a, tr in enumerate(traj):
        if tr[0] != nest:
            errors.append(f"robot {a} does not start in the nest")
        for t in range(1, T + 1):
            (x0, y0), (x1, y1) = tr[t - 1], tr[t]
            if abs(x1 - x0) + abs(y1 - y0) > 1:
                errors.append(f"robot {a}: illegal move at round {t}")
            if not (0 <= x1 < g and 0 <= y1 < g):
                errors.append(f"robot {a}: leaves the grid at round {t}")
    n = len(traj)
    for t in range(T + 1):
        seen: dict[tuple[int, int], int] = {}
        for a in range(n):
            c = traj[a][t]
            if c == nest:
                continue
            if c in seen:
                errors.append(f"round {t}: robots {seen[c]} and {a} share cell {c}")
            seen[c] = a
        if t:
            before = {traj[a][t - 1]: a for a in range(n) if traj[a][t - 1] != nest}
            for a in range(n):
                b = before.get(traj[a][t])
                if b is not None and b != a and traj[b][t] == traj[a][t - 1]:
                    (xa, ya), (xb, yb) = traj[a][t - 1], traj[b][t - 1]
                    if abs(xa - xb) + abs(ya - yb) != 1:
                        errors.append(f"round {t}: robots {a} and {b} swap from afar")
    picks = drops = 0
    for a, ag in enumerate(agents):
        for t, x, y, *kind in ag["jobs"]:
            what = kind[0] if kind else "?"
            if not 0 <= int(t) <= T or traj[a][int(t)] != (int(x), int(y)):
                errors.append(f"robot {a}: job at ({x},{y}) round {t} where it is not")
            if what == "pickup":
                picks += 1
                if (int(x), int(y)) != food:
                    errors.append(f"robot {a}: pick-up away from the food at round {t}")
            elif what == "drop":
                drops += 1
                if (int(x), int(y)) != nest:
                    errors.append(f"robot {a}: drop outside the nest at round {t}")
    if picks > k or drops > k:
        errors.append(f"{picks} pick-ups / {drops} drops for only {k} units")
    if drops != int(record["metrics"]["food_delivered"]):
        errors.append("food_delivered does not match the drops")
    if bool(record["complete"]) != (drops == k):
        errors.append("complete does not match the number of drops")
    return errors
