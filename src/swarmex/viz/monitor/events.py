"""The monitor's event stream: one JSON schema for simulated and networked missions.

The page (and any other viewer) only ever sees these events, so whatever produces them — the
simulation replayed in scaled time here, or the networked runtime's processes later — drives
the same display. A WebSocket frame carries a JSON *array* of events (batches keep the frame
rate independent of the event rate); every event is an object with a ``type``. Events with a
``t`` (mission time, in the hello's ``time_unit``) arrive in non-decreasing ``t``.

=========  ==========================================================================
type       fields
=========  ==========================================================================
hello      ``schema`` ("swarmex.monitor/1"), ``mission``, ``algorithm``, ``source``
           ("simulation" | "network"), ``time_unit``, ``agents`` (ids), ``speed``
           (mission seconds per wall second, null when live), ``title``. Starts a mission:
           a viewer clears its state.
world      ``kind`` ("grid" | "graph" | "polygons"), ``width``, ``height``, ``source``,
           ``cells``: rows of ``.`` (free) and ``@`` (blocked), row 0 first, or null when
           the layout is unknown (the viewer then draws the bounds only).
move       ``t``, ``agent``, ``x``, ``y``: the agent is at (x, y) (a cell, x = column, or a
           point in metres). The first move of an agent is its start.
job        ``t``, ``agent``, ``x``, ``y``: the agent starts a job / picks food / … there;
           ``kind`` when the record names it (foraging: "pickup", "drop").
message    ``t``, ``agent`` (sender), ``to`` (receiver id, null for a broadcast), ``kind``,
           ``x``, ``y`` (the vertex it is about, if any).
clock      ``t``: time passes with nothing else to say (lets the clock tick).
end        ``t``, ``complete``, ``makespan``, ``time_unit``, ``metrics`` (the record's
           totals), ``agents`` (``[{"id", "metrics"}]``): the mission is over.
=========  ==========================================================================

For a simulated traversal the messages are those of the thesis's protocol (§4.2), rebuilt from
the record, which stores the times they were sent at: C01 ``pos`` at the start and at every
arrival without a job, C07 ``job`` when a job starts, C08 ``done`` when it ends, C05 ``next``
when a move is decided. Their count equals the record's ``messages`` total (checked by the
tests). Other missions' records are replayed without message events.
"""

from __future__ import annotations

import bisect
from typing import Any

import numpy as np

SCHEMA = "swarmex.monitor/1"


def hello_event(record: dict, source: str = "simulation", speed: float | None = None) -> dict:
    world = record.get("world") or {}
    return {
        "type": "hello",
        "schema": SCHEMA,
        "mission": record.get("mission"),
        "algorithm": record.get("algorithm"),
        "source": source,
        "time_unit": record.get("time_unit", "s"),
        "agents": [a["id"] for a in record.get("agents", [])],
        "speed": speed,
        "title": f"{record.get('mission')} · {record.get('algorithm')} · {world.get('source', '')}",
    }


def world_event(record: dict, free: np.ndarray | None = None) -> dict:
    """The map: ``free`` is the True-is-free array ``[y, x]`` when the layout is known."""
    world = record.get("world") or {}
    cells = None
    if free is not None:
        chars = np.where(free, ord("."), ord("@")).astype(np.uint8)
        cells = [row.tobytes().decode("ascii") for row in chars]
    return {
        "type": "world",
        "kind": world.get("kind", "grid"),
        "width": world.get("width") if free is None else int(free.shape[1]),
        "height": world.get("height") if free is None else int(free.shape[0]),
        "source": world.get("source", ""),
        "cells": cells,
    }


def end_event(record: dict) -> dict:
    times = [p[0] for a in record.get("agents", []) for p in a.get("trajectory", [])]
    makespan = record.get("makespan")
    t = max([*times, makespan if makespan is not None else 0.0])
    return {
        "type": "end",
        "t": t,
        "complete": bool(record.get("complete")),
        "makespan": makespan,
        "time_unit": record.get("time_unit", "s"),
        "metrics": record.get("metrics", {}),
        "agents": [{"id": a["id"], "metrics": a.get("metrics", {})} for a in record["agents"]],
    }


def record_events(
    record: dict, free: np.ndarray | None = None, speed: float | None = None
) -> list[dict[str, Any]]:
    """A finished run's record as the monitor's event stream, in mission-time order."""
    timed: list[dict[str, Any]] = []
    job_time = (record.get("params") or {}).get("job_time")
    for agent in record.get("agents", []):
        aid = agent["id"]
        for t, x, y, *_ in agent.get("trajectory", []):
            timed.append({"type": "move", "t": t, "agent": aid, "x": x, "y": y})
        for t, x, y, *extra in agent.get("jobs", []):  # foraging adds the event's kind
            job = {"type": "job", "t": t, "agent": aid, "x": x, "y": y}
            if extra and isinstance(extra[0], str):
                job["kind"] = extra[0]
            timed.append(job)
        if record.get("mission") == "traversal" and job_time is not None:
            timed += traversal_messages(agent, float(job_time))
    timed.sort(key=lambda e: e["t"])  # stable: per agent, a move precedes its job
    end = end_event(record)
    end["t"] = max([end["t"], *(e["t"] for e in timed)])
    return [hello_event(record, "simulation", speed), world_event(record, free), *timed, end]


def traversal_messages(agent: dict, job_time: float) -> list[dict[str, Any]]:
    """The §4.2 messages one traversal agent sent, from its trajectory and jobs (module doc)."""
    aid = agent["id"]
    traj = agent.get("trajectory", [])
    jobs = agent.get("jobs", [])
    job_at = {tuple(j[:3]) for j in jobs}
    job_times = sorted(j[0] for j in jobs)
    out = []

    def msg(t: float, kind: str, x: float, y: float) -> None:
        out.append(
            {"type": "message", "t": t, "agent": aid, "to": None, "kind": kind, "x": x, "y": y}
        )

    for t, x, y, *_ in jobs:
        msg(t, "job", x, y)
        msg(t + job_time, "done", x, y)
    for i, (t, x, y, *_) in enumerate(traj):
        if i == 0 or (t, x, y) not in job_at:
            msg(t, "pos", x, y)
        if i + 1 < len(traj):  # the decision to move on: after the last job here, if any
            t_next, nx, ny = traj[i + 1][:3]
            k = bisect.bisect_left(job_times, t_next) - 1  # jobs are done where the agent is
            leave = job_times[k] + job_time if k >= 0 and job_times[k] >= t else t
            msg(leave, "next", nx, ny)
    return out
