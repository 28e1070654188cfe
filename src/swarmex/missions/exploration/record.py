"""Metrics of an exploration run and its DESIGN.md result record.

Names follow the thesis where it has them (ch. 4): exploration time in *steps* (100 ms
ticks); a team member's exploration time is the tick at which its own map last showed no
reachable frontier (``steps``), and Fig. 4.1 plots their mean (``mean_steps``); Fig. 4.4
plots the interval, in steps, between consecutive plan generations of "an average robot"
(``plan_intervals_avg``: the k-th interval averaged over the robots that have a k-th one).

``explored_fraction`` is the share of the true free cells reachable from the starts (8-moves
without corner cutting) that some robot's map holds as free at the end. Cells behind a gap
the robot cannot pass count too: the laser may or may not have seen them, and the number
says honestly what is missing.
"""

from __future__ import annotations

from dataclasses import asdict, fields
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.comm.aodv import CONTROL_KINDS, AodvStats
from swarmex.engine.record import AgentRecord, MetricInfo, ResultRecord
from swarmex.missions.exploration.messages import KINDS
from swarmex.missions.exploration.params import TICK_SECONDS
from swarmex.missions.exploration.robot import REPLAN_REASONS
from swarmex.missions.exploration.sim import ExplorationRun


def intervals(ticks: list[int]) -> list[int]:
    return [int(b - a) for a, b in zip(ticks, ticks[1:], strict=False)]


def average_robot(series: list[list[int]]) -> list[float]:
    """Element-wise mean of ragged series (index k over the series that reach k)."""
    longest = max((len(s) for s in series), default=0)
    out = []
    for k in range(longest):
        vals = [s[k] for s in series if len(s) > k]
        out.append(float(np.mean(vals)))
    return out


def robot_steps(run: ExplorationRun) -> list[int]:
    """Each robot's exploration time: when it finished, or the run's end if it never did."""
    return [
        int(r.stats.finished_at) if r.stats.finished_at is not None else int(run.makespan)
        for r in run.robots
    ]


def unicast_stats(run: ExplorationRun) -> dict[str, int]:
    """The AODV unicast queue's fate, summed over the team (zeros when AODV is off): sent by
    applications, delivered (and how many over two or more hops), dropped at their expiry
    without a route, dropped by the hop limit, route discoveries (RREQs originated) and
    link breaks; plus the ``NEED_MAP`` requests to the origin of missing scans."""
    out = dict.fromkeys((f.name for f in fields(AodvStats)), 0)
    for r in run.robots:
        if r.aodv is not None:
            for k, v in asdict(r.aodv.stats).items():
                out[k] += int(v)
    out["gap_requests"] = int(sum(r.stats.gap_requests for r in run.robots))
    return out


#: The team metrics of an exploration record (``record.metrics``); a step is one tick of
#: TICK_SECONDS. A test holds this equal to what the runs write.
TEAM_METRICS: dict[str, MetricInfo] = {
    "explored_fraction": MetricInfo("share of the reachable free cells the team's maps show free"),
    "reachable_free_cells": MetricInfo("free cells reachable from a start (the area to explore)"),
    "steps": MetricInfo("steps each robot ran until it finished", numeric=False),
    "mean_steps": MetricInfo("mean of steps over the robots"),
    "makespan_seconds": MetricInfo("the makespan in seconds (steps × tick)"),
    "moves": MetricInfo("cell moves, all robots"),
    "plans": MetricInfo("goal choices and path plans, all robots"),
    "replans": MetricInfo("plans made again before the goal was reached, all robots"),
    "replan_reasons": MetricInfo("replans counted by reason", numeric=False,
                                 keys=REPLAN_REASONS, counts=True),
    "conflicts": MetricInfo("goal conflicts between robots, all robots"),
    "change_goals_sent": MetricInfo("CHANGE_GOAL messages sent"),
    "blacklisted_regions": MetricInfo("frontier regions given up as unreachable, all robots"),
    "messages_sent": MetricInfo("messages sent, relays included"),
    "bytes_sent": MetricInfo("bytes sent, relays included"),
    "messages_lost": MetricInfo("messages the radio dropped (range, loss)"),
    "messages_by_kind": MetricInfo(
        "messages and bytes per message kind", numeric=False,
        keys=tuple(f"{k}.{v}" for k in (*KINDS, *CONTROL_KINDS) for v in ("messages", "bytes")),
        counts=True,
    ),
    "aodv_messages": MetricInfo(
        "AODV routing control messages (RREQ, RREP, RERR; also in messages_sent)"
    ),
    "aodv_bytes": MetricInfo("bytes of those"),
    "unicasts": MetricInfo(
        "multi-hop unicast counters (sent, delivered, expired, …)", numeric=False,
        keys=(*(f.name for f in fields(AodvStats)), "gap_requests"),
        counts=True,
    ),
    "plan_intervals_avg": MetricInfo(
        "steps between plans, averaged over the robots, plan by plan", numeric=False
    ),
    "finished_robots": MetricInfo("robots that ended because nothing was left to explore"),
}


def exploration_metrics(run: ExplorationRun) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    net = run.network.totals()
    steps = robot_steps(run)
    per_robot: list[dict[str, Any]] = []
    reasons: dict[str, int] = {}
    reach = run.reachable
    n_reach = max(1, int(reach.sum()))
    for r, st in zip(run.robots, steps, strict=True):
        s = r.stats
        for k, v in s.reasons.items():
            reasons[k] = reasons.get(k, 0) + v
        sent = run.network.sent[r.id]
        per_robot.append(
            {
                "steps": st,
                "moves": s.moves,
                "plans": s.plans,
                "replans": s.replans,
                "replan_reasons": dict(sorted(s.reasons.items())),
                "plan_intervals": intervals(s.plan_ticks),
                "scans": s.scans,
                "archive": len(r.belief.archive),
                "conflicts": s.conflicts,
                "change_goals_sent": s.change_goals_sent,
                "blacklisted_regions": s.blacklisted_regions,
                "messages_sent": sent.messages,
                "bytes_sent": sent.bytes,
                "explored_fraction_own": float(((r.belief.grid.logodds < 0) & reach).sum())
                / n_reach,
            }
        )
    team = {
        "explored_fraction": run.explored_fraction(),
        "reachable_free_cells": int(reach.sum()),
        "steps": steps,
        "mean_steps": float(np.mean(steps)),
        "makespan_seconds": run.makespan * TICK_SECONDS,
        "moves": int(sum(p["moves"] for p in per_robot)),
        "plans": int(sum(p["plans"] for p in per_robot)),
        "replans": int(sum(p["replans"] for p in per_robot)),
        "replan_reasons": dict(sorted(reasons.items())),
        "conflicts": int(sum(p["conflicts"] for p in per_robot)),
        "change_goals_sent": int(sum(p["change_goals_sent"] for p in per_robot)),
        "blacklisted_regions": int(sum(p["blacklisted_regions"] for p in per_robot)),
        "messages_sent": net["messages_sent"],
        "bytes_sent": net["bytes_sent"],
        "messages_lost": net["messages_lost"],
        "messages_by_kind": net["by_kind"],
        "aodv_messages": net["aodv_messages"],
        "aodv_bytes": net["aodv_bytes"],
        "unicasts": unicast_stats(run),
        "plan_intervals_avg": average_robot([p["plan_intervals"] for p in per_robot]),
        "finished_robots": int(sum(r.finished for r in run.robots)),
    }
    return team, per_robot


def exploration_record(run: ExplorationRun) -> ResultRecord:
    team, per_robot = exploration_metrics(run)
    params = run.params.as_dict()
    params["starts"] = [list(s) for s in run.starts]
    params["cell"] = run.grid.cell
    if run.params.map is not None and not isinstance(run.params.map, str | Path):
        params["generated"] = run.grid.world.source  # a world object: no file to name
    agents = [
        AgentRecord(
            id=r.id,
            metrics=m,
            trajectory=[[t, x, y] for t, x, y in run.trajectories[r.id]],
        )
        for r, m in zip(run.robots, per_robot, strict=True)
    ]
    return ResultRecord(
        mission="exploration",
        algorithm=run.params.strategy,
        params=params,
        seed=run.params.seed,
        world=run.grid.describe(),
        complete=run.complete,
        makespan=float(run.makespan),
        time_unit="step",
        metrics=team,
        agents=agents,
        wall_seconds=run.wall_seconds,
        extra={"tick_seconds": TICK_SECONDS},
    )
