"""Which runs ``swarmex reproduce exploration`` makes: seed 003's chapter 4, and beyond.

The thesis's design (§4.1): one empty 20 × 20 m terrain at 5 cm (400 × 400 cells), teams of
1–10 robots, communication ranges 5, 10, 15 and 20 m, laser ranges 1.5 and 2 m, three runs
per configuration, time in steps of 100 ms. It prints no numbers — only Figs. 4.1–4.4 and
their trends — so the report redraws the figures from swarmex runs and checks each stated
trend:

1. any teamwork cuts the exploration time (every team beats one robot);
2. a shorter communication range costs steps (missed scans are explored again);
3. a shorter laser costs steps, and steps / team size keep their shape across lasers;
4. the plan-generation intervals of a 10-robot team with a 20 m radio have a flat part at
   20 steps (the 2 s timer) between a low start and a rising frequency at the end, when the
   robots crowd into the last unexplored part (Figs. 4.3–4.4);
5. the thesis also reports that steps rise again for big teams (an optimal team size); that
   is checked and reported either way, and a *team-size study* tests the cause the thesis
   gives for it — goal negotiation and the re-planning it triggers (§4.2–4.3) — under
   readings that make a re-plan cost more than ours does (:data:`TEAM_VARIANTS`), on teams
   up to twice the thesis's largest, at laser 2 m and radio 20 m (the setting of Fig. 4.4(d)).

Beyond the seed, the same machinery compares the coordination strategies (greedy,
greedy-exclusion, Burgard et al.'s utility, MinPos, Hungarian assignment) on the same maps
and seeds. ``--quick`` shrinks everything (a 10 × 10 m world, teams 1/2/5/10, radios 5 and
20 m, one run) to check the pipeline in a few minutes.

A job is a plain dict (:func:`job_key` is its identity); :mod:`.runs` runs one, and the study
runner (:mod:`swarmex.studies.runner`) executes them and keeps them one JSON line each in
``OUT/runs.jsonl``, so an interrupted reproduction resumes where it stopped; :mod:`.analysis`
checks the trends, :mod:`.figures` redraws Figs. 4.1–4.4 and :mod:`.report` writes
``exploration.md``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

from swarmex.worlds.mapfiles import maps_dir

THESIS_SNAPSHOT_STEPS = (80, 580, 800)
STRATEGY_ORDER = (
    "greedy", "greedy-exclusion", "utility", "minpos", "hungarian", "hungarian-exclusion",
    "adaptive-exclusion",
)


@dataclass(frozen=True)
class Design:
    world_m: float = 20.0
    cell: float = 0.05
    sizes: tuple[int, ...] = tuple(range(1, 11))
    comms: tuple[float, ...] = (5.0, 10.0, 15.0, 20.0)
    lasers: tuple[float, ...] = (2.0, 1.5)
    runs: int = 3


FULL = Design()
QUICK = Design(world_m=10.0, sizes=(1, 2, 5, 10), comms=(5.0, 20.0), runs=1)

# team-size study: larger teams than the thesis ran, and the model options that make the
# thesis's stated cause (goal negotiation → re-plans) costlier; name → ExplorationParams fields
BIG_TEAMS = {False: (12, 15, 20), True: (15,)}  # by quick
TEAM_VARIANTS: dict[str, dict[str, Any]] = {
    "as modelled": {},
    "loser yields its zone": {"conflict_yield": True},
    "plan stops robot 0.6 s": {"plan_pause": 6},
    "both": {"conflict_yield": True, "plan_pause": 6},
}

# name, world, robots, laser (m), comm (m)
SCENARIOS = [
    ("open 20x20 m, 10 robots, comm 10 m", {"empty": 20.0}, 10, 2.0, 10.0),
    ("open 20x20 m, 5 robots, laser 1.5 m, comm 5 m", {"empty": 20.0}, 5, 1.5, 5.0),
    (
        "room-32-32-4 (8x8 m), 6 robots, comm 5 m",
        {"map": "room-32-32-4.map", "cell": 0.25},
        6,
        2.0,
        5.0,
    ),
    (
        "warehouse-10-20-10-2-1 (40x16 m), 8 robots, comm 10 m",
        {"map": "warehouse-10-20-10-2-1.map", "cell": 0.25},
        8,
        2.0,
        10.0,
    ),
    (
        "ost003d (48x48 m), 8 robots, comm 10 m",
        {"map": "ost003d.map", "cell": 0.25},
        8,
        2.0,
        10.0,
    ),
]
QUICK_SCENARIOS = [
    ("open 10x10 m, 5 robots, comm 5 m", {"empty": 10.0}, 5, 2.0, 5.0),
    (
        "room-32-32-4 (8x8 m), 4 robots, comm 5 m",
        {"map": "room-32-32-4.map", "cell": 0.25},
        4,
        2.0,
        5.0,
    ),
]


def missing_maps(scenarios) -> list[str]:
    """The map files of ``scenarios`` not found in :func:`maps_dir`: their strategy rows are
    skipped (the maps are the MovingAI benchmark's, not part of the package)."""
    return [w["map"] for _, w, *_ in scenarios
            if "map" in w and not (maps_dir() / w["map"]).exists()]


def skipped_note(maps: list[str]) -> str:
    """The line saying which strategy scenarios were left out, and how to bring them back.

    Why: installed from a wheel, away from the repository's ``../shared/maps``, the room and
    warehouse rows used to vanish from the report without a word."""
    return (f"skipped the strategy scenario(s) on {', '.join(maps)}: not found in "
            f"{maps_dir()} (set SWARMEX_MAPS to a folder of the MovingAI maps)")


def world_options(spec: dict[str, Any]) -> dict[str, Any]:
    """A job's world as the exploration mission's options (``empty`` or ``map``, ``cell``)."""
    if "empty" in spec:
        side = float(spec["empty"])
        return {"empty": (side, side), "cell": float(spec.get("cell", 0.05))}
    return {"map": maps_dir() / spec["map"], "cell": float(spec["cell"])}


def job_key(job: dict[str, Any]) -> str:
    return json.dumps({k: job[k] for k in sorted(job) if k != "extra"}, sort_keys=True)


def sweep_jobs(d: Design) -> list[dict[str, Any]]:
    return [
        {
            "kind": "sweep",
            "world": {"empty": d.world_m, "cell": d.cell},
            "robots": n,
            "laser": laser,
            "comm": comm,
            "strategy": "greedy-exclusion",
            "seed": s,
        }
        for laser in d.lasers
        for comm in d.comms
        for n in d.sizes
        for s in range(d.runs)
    ]


def team_jobs(d: Design, quick: bool) -> list[dict[str, Any]]:
    """The team-size study at the largest laser and radio: every variant on the thesis's
    sizes and beyond. The plain variant's thesis-size runs are the sweep's own (same keys)."""
    sizes = tuple(d.sizes) + BIG_TEAMS[quick]
    jobs = []
    for opts in TEAM_VARIANTS.values():
        for n in sizes:
            for s in range(d.runs):
                kind = "sweep" if not opts and n in d.sizes else "teamsize"
                jobs.append(
                    {
                        "kind": kind,
                        "world": {"empty": d.world_m, "cell": d.cell},
                        "robots": n,
                        "laser": max(d.lasers),
                        "comm": max(d.comms),
                        "strategy": "greedy-exclusion",
                        "seed": s,
                        **opts,
                    }
                )
    return jobs


def strategy_jobs(scenarios, runs: int) -> list[dict[str, Any]]:
    jobs = []
    missing = missing_maps(scenarios)
    for name, world, n, laser, comm in scenarios:
        if world.get("map") in missing:
            continue
        for st in STRATEGY_ORDER:
            for s in range(runs):
                jobs.append(
                    {
                        "kind": "strategy",
                        "scenario": name,
                        "world": world,
                        "robots": n,
                        "laser": laser,
                        "comm": comm,
                        "strategy": st,
                        "seed": s,
                    }
                )
    return jobs


def picture_jobs(d: Design) -> list[dict[str, Any]]:
    world = {"empty": d.world_m, "cell": d.cell}
    jobs: list[dict[str, Any]] = [
        {
            "kind": "fig4_2",
            "world": world,
            "robots": n,
            "laser": laser,
            "comm": max(d.comms),
            "strategy": "greedy-exclusion",
            "seed": 0,
            "extra": {"pictures": True},
        }
        for laser in (2.0, 1.5)
        for n in (1, 2, 5)
    ]
    jobs.append(
        {
            "kind": "fig4_3",
            "world": world,
            "robots": 10,
            "laser": 2.0,
            "comm": max(d.comms),
            "strategy": "greedy-exclusion",
            "seed": 0,
            "extra": {"pictures": True, "snap_every": 10},
        }
    )
    return jobs
