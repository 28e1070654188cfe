"""Seed 000 §5.1.1 metrics, snake_case, and the traversal result record.

Per agent: ``nodes_done``, ``nodes_traveled``, ``nodes_without_job``, ``travel_time``,
``job_time``, ``total_time``, ``additional_time``. Totals: ``total_time_all`` (Σ total_time,
the §3.1 objective), ``nodes_without_job_all``; ``makespan`` is the largest ``total_time``.

``nodes_traveled`` counts edge moves plus one when the agent did the job at its own nest
(spec §6.10: the thesis's numbers only fit that reading — with one shared nest only the first
agent gets the +1). ``total_time`` excludes ``additional_time`` (takeoff + RTL + landing), as
in Tables 5.1–5.2. Extra figures the thesis does not have: ``duplicate_jobs`` (jobs done on a
vertex someone had already done: 0 under a perfect broadcast), ``mission_end`` (clock time of
the last job or move, including the staggered starts), messages and bytes.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

from swarmex.engine.record import AgentRecord, MetricInfo, ResultRecord
from swarmex.missions.traversal.sim import AgentLog, TraversalRun
from swarmex.worlds.mapfiles import source_name

#: The team metrics of a traversal record (``record.metrics``; ``optimal`` writes the same,
#: and its four solver figures), in seconds unless said. A test holds this equal to what
#: the runs write.
TEAM_METRICS: dict[str, MetricInfo] = {
    "total_time_all": MetricInfo(
        "Σ of every agent's total_time (travel + jobs, s): the §3.1 objective"
    ),
    "nodes_without_job_all": MetricInfo("moves onto a vertex without doing its job, all agents"),
    "nodes_done_all": MetricInfo("jobs done, all agents"),
    "travel_time_all": MetricInfo("time spent moving, all agents (s)"),
    "job_time_all": MetricInfo("time spent on jobs, all agents (s)"),
    "additional_time_all": MetricInfo(
        "takeoff + return to launch + landing, all agents (s; not in total_time)"
    ),
    "max_total_time": MetricInfo("the largest agent total_time (s): the makespan"),
    "mission_end": MetricInfo(
        "clock time of the last job or move, staggered starts included (s; None: no agent ended)"
    ),
    "reachable_nodes": MetricInfo("vertices reachable from a nest (the jobs to do)"),
    "nodes_missed": MetricInfo("reachable vertices where no job was done"),
    "duplicate_jobs": MetricInfo("jobs on a vertex already done (0 under a perfect broadcast)"),
    "messages": MetricInfo("messages the agents sent"),
    "message_bytes": MetricInfo("bytes of those messages"),
    "objective_value": MetricInfo("optimal: the MILP objective of the plan found (s)"),
    "lower_bound": MetricInfo("optimal: the solver's proven lower bound on it (s)"),
    "mip_gap": MetricInfo("optimal: (value − bound) / value, 0 when proven optimal"),
    "proven_optimal": MetricInfo("optimal: whether the solver proved the plan optimal"),
}


def agent_metrics(log: AgentLog, unit_length: float) -> dict:
    done = len(log.jobs) - log.failed_jobs
    traveled = log.moves + (1 if log.nest_job else 0)
    spec = log.spec
    rtl = log.rtl_length * unit_length / spec.travel_speed
    return {
        "nodes_done": done,
        "nodes_traveled": traveled,
        "nodes_without_job": traveled - done,
        # plain floats: the sum of numpy step times printed as np.float64(...) in a
        # record's metrics in Python (the JSON was the same; so is the value)
        "travel_time": float(log.travel_time),
        "job_time": float(log.job_time),
        "total_time": float(log.travel_time + log.job_time),
        "additional_time": spec.takeoff_time + rtl + spec.landing_time,
        "failed_jobs": log.failed_jobs,
        "finished_at": log.finished_at,
    }


def run_metrics(run: TraversalRun, unit_length: float) -> tuple[dict, list[dict]]:
    per_agent = [agent_metrics(a, unit_length) for a in run.agents]
    total_times = [m["total_time"] for m in per_agent]
    extra_jobs = np.maximum(run.job_count - 1, 0)
    ends = [a.finished_at for a in run.agents if np.isfinite(a.finished_at)]
    totals = {
        "total_time_all": float(np.sum(total_times)),
        "nodes_without_job_all": int(sum(m["nodes_without_job"] for m in per_agent)),
        "nodes_done_all": int(sum(m["nodes_done"] for m in per_agent)),
        "travel_time_all": float(sum(m["travel_time"] for m in per_agent)),
        "job_time_all": float(sum(m["job_time"] for m in per_agent)),
        "additional_time_all": float(sum(m["additional_time"] for m in per_agent)),
        "max_total_time": float(max(total_times)),
        "mission_end": float(max(ends)) if ends else None,
        "reachable_nodes": int(run.reachable.sum()),
        "nodes_missed": int(np.sum(run.job_count[run.reachable] == 0)),
        "duplicate_jobs": int(extra_jobs.sum()),
        "messages": run.messages,
        "message_bytes": run.message_bytes,
    }
    return totals, per_agent


def traversal_record(run: TraversalRun, params: dict, unit_length: float = 1.0) -> ResultRecord:
    totals, per_agent = run_metrics(run, unit_length)
    world = run.world
    pos = world.graph.pos
    agents = []
    for log, met in zip(run.agents, per_agent, strict=True):
        traj = [[t, *pos[v].tolist()] for t, v in log.trajectory]
        jobs = [[t, *pos[v].tolist()] for t, v in log.jobs]
        agents.append(AgentRecord(log.id, met, traj, jobs))
    return ResultRecord(
        mission="traversal",
        algorithm=run.algorithm,
        params=params,
        seed=run.seed,
        world=world.describe(),
        complete=run.complete,
        makespan=totals["max_total_time"],
        time_unit="s",
        metrics=totals,
        agents=agents,
        wall_seconds=run.wall_seconds,
    )


def run_fingerprint(run: TraversalRun) -> str:
    """A SHA-256 of everything a run decided: its record (without ``wall_seconds`` and
    ``swarmex_version``, which are not behaviour), the thesis-style paths, decision branch
    counts, first doer per vertex and message totals. Speed work must leave it unchanged
    (tests/missions/traversal/test_regression_fingerprint.py, bench/bench_traversal_den520d.py).
    """
    rec = traversal_record(run, params={}).to_dict()
    rec.pop("wall_seconds", None)
    rec.pop("swarmex_version", None)
    world = rec.get("world") or {}
    if isinstance(world.get("source"), str):  # where the map file lies is not behaviour
        world["source"] = source_name(world["source"])
    rec["_paths"] = run.path_strings()
    rec["_branches"] = [a.decisions_by_branch for a in run.agents]
    rec["_done_by"] = run.done_by.tolist()
    rec["_messages"] = [run.messages, run.message_bytes]
    blob = json.dumps(rec, sort_keys=True, separators=(",", ":"), allow_nan=True)
    return hashlib.sha256(blob.encode()).hexdigest()

