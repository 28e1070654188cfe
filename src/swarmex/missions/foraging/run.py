"""One foraging run end to end: validated inputs → timetable → mission → metrics → record.

Metric names follow the thesis's tables (Figs. 78–79), with the column boundaries of the
released simulator (spec §4.2):

* ``exploration_time`` — round the food is first found, deployment included;
* ``communication_time`` — from then until the *first* robot finishes its communication phase;
* ``comm_transport_overlap`` — from then until the *last* robot finishes it (some robots are
  already transporting: the thesis's COMM+TRANS);
* ``transport_time`` — from then until the k-th unit is in the nest.

The four add up to the makespan. If the k units are home before every robot was informed (small
k), the unfinished robots count as finishing at the makespan and ``all_informed`` is false.
``cells_revisited`` counts, up to the discovery, entries of exploring robots into cells that
some exploring robot had already visited (deployment walks excluded).
"""

from __future__ import annotations

import time
from collections.abc import Generator, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from swarmex.engine.record import AgentRecord, MetricInfo, ResultRecord
from swarmex.missions.foraging import recall
from swarmex.missions.foraging.comm import SEED
from swarmex.missions.foraging.grid import Cell
from swarmex.missions.foraging.hook import drive
from swarmex.missions.foraging.params import ForagingParams
from swarmex.missions.foraging.sim import (
    Compute,
    Decide,
    FrameSink,
    Outcome,
    decided_rounds,
    run_mission,
)
from swarmex.missions.foraging.timed import Timed, timed_plan

#: The team metrics of a foraging record (``record.metrics``), in rounds unless said; the
#: four phases are seed 001's (§5): they add up to total_time. A test holds this equal to
#: what the runs write.
TEAM_METRICS: dict[str, MetricInfo] = {
    "exploration_time": MetricInfo(
        "rounds until a robot first stands on the food (None: stopped before)"
    ),
    "communication_time": MetricInfo(
        "from the discovery until the first robot has passed the word on and transports"
    ),
    "comm_transport_overlap": MetricInfo(
        "from then until the last robot does (communication and transport overlap)"
    ),
    "transport_time": MetricInfo("from then until the last unit is home"),
    "total_time": MetricInfo("rounds of the whole run: the makespan"),
    "food_delivered": MetricInfo("units carried into the nest (food_units when complete)"),
    "deployment_time": MetricInfo(
        "rounds until a synchronised pattern starts exploring (0: not synchronised)"
    ),
    "all_informed": MetricInfo(
        "whether every robot finished communicating (reached transport) before the last unit"
        " was home; a robot may know the food and still be false"
    ),
    "cells_revisited": MetricInfo(
        "entries of exploring robots into cells already explored, up to the discovery"
        " (wasted search; deployment walks excluded)"
    ),
}


@dataclass
class ForageRun:
    algorithm: str
    g: int
    n: int
    food: Cell
    units: int
    transport: str
    comm: str
    timed: Timed
    outcome: Outcome
    metrics: dict[str, Any]
    wall_seconds: float
    found: tuple[Cell, ...]  # recall's memory (empty for a pattern)
    pattern: str  # the pattern played: ``algorithm``, or recall's choice


def check_inputs(
    algorithm: str,
    g: int,
    n: int,
    units: int,
    transport: str,
    comm: str = SEED,
    found: Sequence[Cell] = (),
) -> None:
    """The checks of :class:`~.params.ForagingParams` (the only place they live) for a run
    given as plain values; raises InputError naming the option."""
    ForagingParams.from_values(
        grid=g, agents=n, algorithm=algorithm, food_units=units, transport=transport, comm=comm,
        found=tuple(found),
    )  # fmt: skip


def pattern_timed(
    algorithm: str, g: int, n: int, units: int, transport: str, comm: str, found: Sequence[Cell]
) -> tuple[Timed, str]:
    """The timetable a run plays and the pattern's name: ``algorithm``'s own, or for
    ``recall`` the pattern the team chooses from ``found`` (:mod:`.recall`)."""
    if algorithm == recall.NAME:
        choice = recall.choose(g, n, found, units, transport, comm)
        return choice.timed, choice.pattern
    return timed_plan(algorithm, g, n), algorithm


def phase_metrics(o: Outcome, timed: Timed) -> dict[str, Any]:
    if o.discovery is None:  # stopped (on_frame) before the food was found
        return {
            "exploration_time": None,
            "communication_time": None,
            "comm_transport_overlap": None,
            "transport_time": None,
            "total_time": o.makespan,
            "food_delivered": o.delivered,
            "deployment_time": int(timed.t_sync),
            "all_informed": False,
            "cells_revisited": cells_revisited(timed, o.makespan),
        }
    done = [c for c in o.comm_done if c is not None]
    first = min(done) if done else o.makespan
    all_informed = len(done) == len(o.comm_done)
    last = max(done) if all_informed else o.makespan
    first, last = min(first, o.makespan), min(last, o.makespan)
    return {
        "exploration_time": o.discovery,
        "communication_time": first - o.discovery,
        "comm_transport_overlap": last - first,
        "transport_time": o.makespan - last,
        "total_time": o.makespan,
        "food_delivered": o.delivered,
        "deployment_time": int(timed.t_sync),
        "all_informed": all_informed,
        "cells_revisited": cells_revisited(timed, o.discovery),
    }


def cells_revisited(timed: Timed, until: int) -> int:
    pos = timed.pos[: min(until, timed.t_end) + 1]
    entries: list[np.ndarray] = []
    for a in range(pos.shape[1]):
        s = int(timed.explore_start[a])
        if s > until:
            continue
        tr = pos[s:, a]
        moved = np.ones(len(tr), dtype=bool)
        moved[1:] = np.any(tr[1:] != tr[:-1], axis=1)
        entries.append(tr[moved])
    if not entries:
        return 0
    allc = np.concatenate(entries)
    codes = allc[:, 0].astype(np.int64) * timed.plan.g + allc[:, 1]
    return int(len(codes) - len(np.unique(codes)))


def run_forage(
    algorithm: str,
    g: int,
    n: int,
    food: Cell,
    units: int = 100,
    transport: str = "relay-food",
    record: bool = True,
    on_frame: FrameSink | None = None,
    decide: Decide | None = None,
    comm: str = SEED,
    found: Sequence[Cell] = (),
) -> ForageRun:
    """Play one run (inputs checked first) under the communication rule ``comm``
    (:mod:`.comm`: ``seed`` or ``omniscient``); ``on_frame`` gets every round's
    :class:`~.sim.Frame` and may end the run early by raising StopRun; ``decide`` answers
    every Compute of a hooked run (:func:`forage_rounds`); ``found`` is recall's memory."""
    if decide is not None:
        rounds = forage_rounds(
            algorithm, g, n, food, units, transport, record, on_frame, comm, found=found
        )
        return drive(rounds, decide)
    check_inputs(algorithm, g, n, units, transport, comm, found)
    t0 = time.perf_counter()
    timed, pattern = pattern_timed(algorithm, g, n, units, transport, comm, found)
    outcome = run_mission(
        timed, food, units, transport, record=record, on_frame=on_frame, comm=comm
    )
    return _finish(
        algorithm, g, n, food, units, transport, comm, timed, outcome, t0, False, found, pattern
    )


def forage_rounds(
    algorithm: str,
    g: int,
    n: int,
    food: Cell,
    units: int = 100,
    transport: str = "relay-food",
    record: bool = True,
    on_frame: FrameSink | None = None,
    comm: str = SEED,
    fast: bool = True,
    stop_at: int | None = None,
    found: Sequence[Cell] = (),
) -> Generator[Compute, np.ndarray, ForageRun]:
    """:func:`run_forage` as a hooked run that the caller steps (the PettingZoo
    environment): yields each round's :class:`~.sim.Compute`, takes every robot's move
    (``send``) and returns the ForageRun (:mod:`.hook`). ``stop_at`` ends the run at that
    round (as an ``on_frame`` raising StopRun there); ``fast=False`` plays every round in
    Python (the compiled Transportation rounds give the same run: a test compares them)."""
    check_inputs(algorithm, g, n, units, transport, comm, found)
    t0 = time.perf_counter()
    timed, pattern = pattern_timed(algorithm, g, n, units, transport, comm, found)
    outcome = yield from decided_rounds(
        timed, food, units, transport, record, on_frame, comm, fast, stop_at
    )
    return _finish(
        algorithm, g, n, food, units, transport, comm, timed, outcome, t0, True, found, pattern
    )


def _finish(
    algorithm: str,
    g: int,
    n: int,
    food: Cell,
    units: int,
    transport: str,
    comm: str,
    timed: Timed,
    outcome: Outcome,
    t0: float,
    hooked: bool,
    found: Sequence[Cell],
    pattern: str,
) -> ForageRun:
    """The ForageRun of a played run (metrics; ``t0`` its start on the perf clock)."""
    walked = timed
    if hooked and len(outcome.positions):
        # robots a hook moved may leave the timetable: count revisits on the cells they walked
        # (the same rows as the timetable's while every robot follows it)
        walked = replace(timed, pos=outcome.positions, t_end=len(outcome.positions) - 1)
    metrics = phase_metrics(outcome, walked)
    wall = time.perf_counter() - t0
    return ForageRun(
        algorithm, g, n, food, units, transport, comm, timed, outcome, metrics, wall,
        tuple((int(x), int(y)) for x, y in found), pattern,
    )  # fmt: skip


def to_record(run: ForageRun, seed: int, params: dict[str, Any]) -> ResultRecord:
    o = run.outcome
    agents = []
    # one array pass for every robot's moves and (t, x, y) rows: the trajectories are the
    # record's bulk (robots x rounds), and a Python loop per row cost more than the run
    moved = np.abs(np.diff(o.positions, axis=0)).sum(axis=(0, 2)).tolist()
    steps = np.arange(len(o.positions), dtype=np.int64)[:, None]
    for a in range(run.n):
        trajectory = np.hstack((steps, o.positions[:, a].astype(np.int64))).tolist()
        jobs: list[list[Any]] = [[t, x, y, kind] for t, x, y, kind in o.jobs[a]]
        agents.append(
            AgentRecord(
                id=a,
                metrics={
                    "informed_at": o.informed_at[a],
                    "comm_done_at": o.comm_done[a],
                    "pickups": sum(1 for j in o.jobs[a] if j[3] == "pickup"),
                    "drops": sum(1 for j in o.jobs[a] if j[3] == "drop"),
                    "handovers": o.handovers[a],
                    "moves": int(moved[a]),
                    "finder": a in o.finders,
                },
                trajectory=trajectory,
                jobs=jobs,
            )
        )
    full = {
        "grid": run.g,
        "agents": run.n,
        "algorithm": run.algorithm,
        "transport": run.transport,
        "comm": run.comm,
        "food": list(run.food),
        "food_units": run.units,
        "nest": list(run.timed.plan.nest),
        **({"found": [list(c) for c in run.found]} if run.found else {}),
        **params,
    }
    return ResultRecord(
        mission="foraging",
        algorithm=run.algorithm,
        params=full,
        seed=seed,
        world={
            "kind": "grid",
            "source": f"empty {run.g}x{run.g}",
            "width": run.g,
            "height": run.g,
            "free_cells": run.g * run.g,
        },
        complete=o.complete,
        makespan=float(o.makespan),
        time_unit="step",
        metrics=run.metrics,
        agents=agents,
        wall_seconds=run.wall_seconds,
        extra={
            **({"stalled": o.extra["stalled"]} if "stalled" in o.extra else {}),
            **({"pattern": run.pattern} if run.pattern != run.algorithm else {}),
        },
    )
