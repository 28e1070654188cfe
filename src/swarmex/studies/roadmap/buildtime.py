"""Build (pre-processing) time of the roadmaps: WMA-RRT, the project's PRM, OMPL's PRM and RRT.

The paper says a PRM's pre-processing costs extra time but measures none. Here every
(nodes, step) of Table 1 is built on the Fig. 8 environment with the reproduction's team by
each builder, over seeds (seed i builds roadmap i, as in the tables), and timed in **CPU
seconds** (:func:`time.process_time`): the machine is shared, so wall time measures the
others' load as much as ours. All builders run in this one process, after one warm-up build
each (imports, compiled kernels), and the report gives each one's ratio to WMA-RRT measured
here — ratios, not absolute times, are what carries to another machine.

* **WMA-RRT** and **PRM (ours)**: :func:`~swarmex.planning.rrt_wma.build_wma_rrt`,
  :func:`~swarmex.planning.prm.build_prm` (numpy/scipy batches, GEOS segment tests);
* **OMPL PRM** and **OMPL RRT** (extra ``ompl``; skipped without it): the C++ planners with
  our sampler and our exact segment test as Python callbacks (:mod:`swarmex.planning.ompl`),
  so their times include one Python call per sample and per motion check; OMPL's RRT grows
  one tree from the team's centre with range ε to the same node budget.

Results go to ``DIR/roadmap_buildtimes.json`` (read back when the plan is the same).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.missions.roadmap.scenario import make_scenario
from swarmex.planning.prm import build_prm
from swarmex.planning.roadmap import Roadmap
from swarmex.planning.rrt_wma import build_wma_rrt
from swarmex.studies.roadmap.design import AGENTS, ompl_available, reference, world

BUILDERS = ("wma-rrt", "prm", "ompl-prm", "ompl-rrt")


def _builders(starts: np.ndarray) -> dict[str, Callable[..., Roadmap]]:
    w = world("fig8")
    out: dict[str, Callable[..., Roadmap]] = {
        "wma-rrt": lambda n, e, rng: build_wma_rrt(w, starts, n, e, rng),
        "prm": lambda n, e, rng: build_prm(w, starts, n, e, rng),
    }
    if ompl_available():
        from swarmex.planning.ompl import build_ompl_prm, build_ompl_rrt

        centre = starts.mean(axis=0)
        out["ompl-prm"] = lambda n, e, rng: build_ompl_prm(w, starts, n, rng)
        out["ompl-rrt"] = lambda n, e, rng: build_ompl_rrt(w, centre, n, e, rng)
    return out


def build_time_study(quick: bool = False) -> dict[str, Any]:
    """CPU milliseconds per build, per (nodes, step) and builder: mean, SD, n; and edges."""
    seeds = range(2 if quick else 5)
    starts = make_scenario(world("fig8"), agents=AGENTS, nodes=AGENTS, step=20.0,
                           sensor_range=1.0).starts
    builders = _builders(starts)
    for build in builders.values():  # warm-up: imports and compiled kernels
        build(200, 20.0, np.random.default_rng(12345))
    configs = sorted({(int(r["nodes"]), float(r["step"]))
                      for r in reference("roadmap_table1.csv")}, key=lambda c: (c[1], c[0]))
    rows = []
    for nodes, step in configs:
        row: dict[str, Any] = {"nodes": nodes, "step": step}
        for name, build in builders.items():
            ms, edges = [], []
            for s in seeds:
                t0 = time.process_time()
                rm = build(nodes, step, np.random.default_rng(s))
                ms.append(1000.0 * (time.process_time() - t0))
                edges.append(rm.n_edges)
            row[name] = {"ms": float(np.mean(ms)), "sd": float(np.std(ms, ddof=1))
                         if len(ms) > 1 else 0.0, "n": len(ms),
                         "edges": float(np.mean(edges))}
        rows.append(row)
    return {"quick": quick, "seeds": len(seeds), "builders": list(builders), "rows": rows}


def cached_build_times(out: Path, quick: bool) -> dict[str, Any]:
    """The study, read back from ``roadmap_buildtimes.json`` when made with this plan and
    the same builders available."""
    path = out / "roadmap_buildtimes.json"
    want = [b for b in BUILDERS if ompl_available() or not b.startswith("ompl")]
    if path.exists():
        old = json.loads(path.read_text(encoding="utf-8"))
        if old.get("quick") == quick and old.get("builders") == want:
            return old
    study = build_time_study(quick)
    path.write_text(json.dumps(study, indent=1) + "\n", encoding="utf-8")
    return study


__all__ = ["BUILDERS", "build_time_study", "cached_build_times"]
