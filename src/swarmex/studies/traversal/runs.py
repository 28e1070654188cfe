"""One run of ``swarmex reproduce traversal``: the job function of the study runner.

Every run goes through the traversal mission's contract (``registry.get("traversal")``:
``params``, ``run``) with the thesis's agent parameters (:mod:`.design`) as a fleet, one row
per agent with the thesis's speeds in m/s on grid edges of ``unit_length`` metres
(``edge_length``), its own random obstacle layout as ``obstacles`` cells, and uneven starts as
slower climbs (``up_speed`` per row); the record keeps the totals and per-agent metrics the
analysis needs, so the run is asked for without its trace. The pipeline hands
:func:`execute` and the plan's :class:`~.design.RunSpec` list to
:func:`swarmex.studies.runner.run_jobs`, which keeps the results in ``traversal.json``
(a :class:`~swarmex.experiments.runstore.RunStore`): a rerun skips every run already stored
(an interrupted sweep resumes, and a ``--quick`` sweep's runs are a subset of the full one's).
"""

from __future__ import annotations

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


def _cell(node: int, size: int) -> tuple[int, int]:
    """The ``(x, y)`` cell of thesis node id ``node`` on the ``size`` x ``size`` grid."""
    v = thesis_node(node, size)
    return v % size, v // size


def execute(spec: RunSpec) -> dict[str, Any]:
    """Run one configuration repetition and return its JSON-ready record (worker entry)."""
    from swarmex.missions.registry import get

    cfg = spec.config
    n = cfg.size
    obstacles = obstacle_layout(
        n, cfg.obstacles, spec.nest, stable_seed("traversal-obstacles", cfg.key, spec.rep)
    )
    # Uneven starts (sensitivity series): the simulator starts client i at 0.5·i s plus its
    # takeoff time, so a slower climb is how a late start is expressed; it changes only
    # additionalTime_i (takeoff), which the sensitivity analysis does not use.
    offsets = [0.0] * cfg.agents
    if cfg.jitter:
        rng = np.random.default_rng(stable_seed("traversal-jitter", cfg.key, spec.rep))
        offsets = [float(x) for x in rng.uniform(0.0, cfg.jitter, cfg.agents)]
    ups = [UP_SPEED if off == 0 else ALTITUDE / (ALTITUDE / UP_SPEED + off) for off in offsets]
    fleet = [
        {"id": i + 1, "travel_speed": TRAVEL_SPEED, "job_time": JOB_TIME,
         "altitude": ALTITUDE, "up_speed": up, "down_speed": DOWN_SPEED}
        for i, up in enumerate(ups)
    ]  # fmt: skip
    mission = get("traversal")
    params = mission.params(
        grid=(n, n),
        obstacles=[_cell(k, n) for k in obstacles],
        nests=[_cell(spec.nest, n)],
        fleet=fleet,
        edge_length=cfg.unit_length,
        algorithm="madgta",
        start_interval=START_INTERVAL,
        seed=spec.seed,
    )
    record = mission.run(params, trace=False).record
    totals = record.metrics
    per_agent = [a.metrics for a in record.agents]
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
            "complete": record.complete,
            "totals": {k: totals[k] for k in keep},
            "agents": {m: [a[m] for a in per_agent] for m in (*PER_AGENT_METRICS, "finished_at")},
            "wall_seconds": record.wall_seconds,
        }
    )
