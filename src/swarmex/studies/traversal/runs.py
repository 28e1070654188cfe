"""One run of ``swarmex reproduce traversal``: the job function of the study runner.

Every run is one call of :func:`~swarmex.missions.traversal.run_traversal` with the thesis's
agent parameters (:mod:`.design`) on a world with its own random obstacle layout and uneven
starts, which the traversal mission's parameters cannot express (so it is not a plain
``swarmex.run``); its record keeps the totals and per-agent metrics the analysis needs. The
pipeline hands :func:`execute` and the plan's :class:`~.design.RunSpec` list to
:func:`swarmex.studies.runner.run_jobs`, which keeps the results in ``traversal.json``
(a :class:`~swarmex.experiments.runstore.RunStore`): a rerun skips every run already stored
(an interrupted sweep resumes, and a ``--quick`` sweep's runs are a subset of the full one's).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from scipy import ndimage

from swarmex.engine.record import plain
from swarmex.experiments.runstore import stable_seed
from swarmex.studies.traversal.design import (
    ALTITUDE,
    DOWN_SPEED,
    JOB_TIME,
    PER_AGENT_METRICS,
    START_INTERVAL,
    TRAVEL_SPEED,
    UP_SPEED,
    RunSpec,
    thesis_node,
)


def obstacle_layout(size: int, count: int, keep_free: int, seed: int) -> list[int]:
    """``count`` random obstacle nodes (thesis ids), never ``keep_free``, free cells connected.

    Fig. 5.10 plots obstacle *counts*, so we place exactly that many and redraw rather than
    fill disconnected pockets (which would change the count).
    """
    if count == 0:
        return []
    rng = np.random.default_rng(seed)
    candidates = np.array([k for k in range(1, size * size + 1) if k != keep_free])
    for _ in range(10_000):
        chosen = np.sort(rng.choice(candidates, size=count, replace=False))
        free = np.ones((size, size), dtype=bool)
        for k in chosen:
            v = thesis_node(int(k), size)
            free[v // size, v % size] = False
        if ndimage.label(free)[1] == 1:
            return [int(k) for k in chosen]
    raise RuntimeError(f"no connected layout with {count} obstacles on {size}x{size}")


def execute(spec: RunSpec) -> dict[str, Any]:
    """Run one configuration repetition and return its JSON-ready record (worker entry)."""
    from swarmex.missions.traversal import AgentSpec, run_metrics, run_traversal
    from swarmex.worlds import GridWorld

    cfg = spec.config
    n = cfg.size
    obstacles = obstacle_layout(
        n, cfg.obstacles, spec.nest, stable_seed("traversal-obstacles", cfg.key, spec.rep)
    )
    free = np.ones((n, n), dtype=bool)
    for k in obstacles:
        v = thesis_node(k, n)
        free[v // n, v % n] = False
    world = GridWorld(free, source=f"thesis {n}x{n}")
    nest = thesis_node(spec.nest, n)
    # Uneven starts (sensitivity series): the simulator starts client i at 0.5·i s plus its
    # takeoff time, so a slower climb is how a late start is expressed; it changes only
    # additionalTime_i (takeoff), which the sensitivity analysis does not use.
    offsets = [0.0] * cfg.agents
    if cfg.jitter:
        rng = np.random.default_rng(stable_seed("traversal-jitter", cfg.key, spec.rep))
        offsets = [float(x) for x in rng.uniform(0.0, cfg.jitter, cfg.agents)]
    ups = [UP_SPEED if off == 0 else ALTITUDE / (ALTITUDE / UP_SPEED + off) for off in offsets]
    agents = [AgentSpec(nest, TRAVEL_SPEED, JOB_TIME, ALTITUDE, up, DOWN_SPEED) for up in ups]
    t0 = time.perf_counter()
    run = run_traversal(
        world,
        agents,
        "madgta",
        seed=spec.seed,
        start_interval=START_INTERVAL,
        unit_length=cfg.unit_length,
    )
    totals, per_agent = run_metrics(run, cfg.unit_length)
    wall = time.perf_counter() - t0
    keep = (
        "total_time_all",
        "nodes_without_job_all",
        "max_total_time",
        "mission_end",
        "duplicate_jobs",
        "nodes_missed",
        "reachable_nodes",
    )
    return plain(
        {
            "id": spec.id,
            "config": cfg.key,
            "rep": spec.rep,
            "seed": spec.seed,
            "nest": spec.nest,
            "obstacles": obstacles,
            "start_offsets": offsets,
            "complete": run.complete,
            "totals": {k: totals[k] for k in keep},
            "agents": {m: [a[m] for a in per_agent] for m in (*PER_AGENT_METRICS, "finished_at")},
            "wall_seconds": wall,
        }
    )
