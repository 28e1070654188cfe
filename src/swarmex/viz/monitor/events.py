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
           (mission seconds per wall second, null when live or unpaced: ``--speed inf``),
           ``title``. Starts a mission: a viewer clears its state. Optional ``messages``:
           "events" (every message sent comes as a ``message`` event), "totals" (no
           per-message times: only the end's totals are known, so a rate is n/a) or "none"
           (the mission sends no messages); absent means "events". Optional ``vehicles``
           (``[{"id", "kind", …}]``: what each agent flies, "simulated" | "mavlink", in a
           networked traversal; a hybrid mission mixes them).
world      ``kind`` ("grid" | "graph" | "polygons"), ``width``, ``height``, ``source``,
           ``cells``: rows of ``.`` (free) and ``@`` (blocked), row 0 first, or null when
           the layout is unknown or not a grid (the viewer then draws the bounds only).
           Optional: ``bounds`` ([xmin, ymin, xmax, ymax], polygon worlds), ``y_up``
           (true: y grows upwards, as in a polygon JSON file; default false: row 0 on top),
           ``polygons`` (the blocked region as rings ``[[x, y], …]``: the exteriors and the
           holes of the obstacles' union, to be filled with the even-odd rule), ``edges``
           (segments ``[x1, y1, x2, y2]`` drawn under the agents: a roadmap), ``marks``
           (``[{"kind": "nest" | "food" | "goal", "x", "y", …}]``: fixed places).
move       ``t``, ``agent``, ``x``, ``y``: the agent is at (x, y) (a cell, x = column, or a
           point in metres). The first move of an agent is its start.
job        ``t``, ``agent``, ``x``, ``y``: the agent starts a job / picks food / … there;
           ``kind`` when the record names it (foraging: "pickup", "drop").
message    ``t``, ``agent`` (sender), ``to`` (receiver id, null for a broadcast), ``kind``,
           ``x``, ``y`` (the vertex it is about, if any). Optional: ``vehicle`` on a ``join``
           (what the spare flies), ``reason`` on a ``left`` (why the agent went).
status     ``t``, ``agent``, ``carrying``, ``informed`` (booleans): a foraging robot started or
           stopped carrying a unit, or learned where the food is (live runs).
known      ``t``, ``cols``, ``free``, ``occupied``, ``frontier``, ``not_frontier``: flat
           row-major cell indices of the exploration team's merged map that became free or
           occupied, and that became or stopped being frontier cells (live runs).
goals      ``t``, ``goals``: per robot ``[id, x, y]`` or null: the exploration robots'
           current goals (live runs).
weights    ``t``, ``edges``: ``[[i, n], …]``: roadmap edge i (index into the world's ``edges``)
           has now been traversed n times (live runs).
clock      ``t``: time passes with nothing else to say (lets the clock tick).
end        ``t``, ``complete``, ``makespan``, ``time_unit``, ``metrics`` (the record's
           totals), ``agents`` (``[{"id", "metrics"}]``): the mission is over. Optional
           ``messages``: the number of messages sent in all (null: unknown or none).
=========  ==========================================================================

Messages rebuilt from a record (only where the record holds when they were sent):

* traversal: the thesis's protocol (§4.2); the record stores the times they were sent at:
  C01 ``pos`` at the start and at every arrival without a job, C07 ``job`` when a job starts,
  C08 ``done`` when it ends, C05 ``next`` when a move is decided. Their count equals the
  record's ``messages`` total (checked by the tests).
* foraging: one ``food`` message (``to`` = the robot told, ``x``, ``y`` = the food) for every
  robot that learned the food's location from another robot, at its ``informed_at`` round.
  The sender is the one the simulator's Look picks: the lowest-id robot that knew the
  location before that round (or found it by standing on the food in that round) and stood
  at distance ≤ 1. Robots that find the food themselves get no message; repeated exchanges
  between robots that both know carry no news and are not shown.
* exploration: the record keeps per-robot and per-kind totals only, not send times, so the
  hello says ``messages: "totals"`` and no times are invented; the end event carries the
  total and each agent's ``messages_sent``.
* roadmap: the agents share a blackboard and send no messages (``messages: "none"``).
"""

from __future__ import annotations

import bisect
import math
from typing import Any

import numpy as np

from swarmex.engine.record import message_total
from swarmex.worlds.mapfiles import source_name

SCHEMA = "swarmex.monitor/1"


def hello_event(
    record: dict,
    source: str = "simulation",
    speed: float | None = None,
    messages: str | None = None,
) -> dict:
    """The mission's first event; ``messages`` says what the page can show of its messages."""
    world = record.get("world") or {}
    hello = {
        "type": "hello",
        "schema": SCHEMA,
        "mission": record.get("mission"),
        "algorithm": record.get("algorithm"),
        "source": source,
        "time_unit": record.get("time_unit", "s"),
        "agents": [a["id"] for a in record.get("agents", [])],
        "speed": speed if speed is None or math.isfinite(speed) else None,  # JSON has no inf
        "title": f"{record.get('mission')} · {record.get('algorithm')} ·"
                 f" {source_name(str(world.get('source', '')))}",
    }
    if messages is not None:
        hello["messages"] = messages
    return hello


def world_event(
    record: dict,
    free: np.ndarray | None = None,
    *,
    bounds: list[float] | None = None,
    y_up: bool | None = None,
    polygons: list[list[list[float]]] | None = None,
    edges: list[list[float]] | None = None,
    marks: list[dict[str, Any]] | None = None,
) -> dict:
    """The map: ``free`` is the True-is-free array ``[y, x]`` when the layout is known.

    The keyword fields are the schema's optional ones (module doc); each is left out when not
    given, so a viewer of the first schema version sees exactly the event it knew.
    """
    world = record.get("world") or {}
    cells = None
    if free is not None:
        chars = np.where(free, ord("."), ord("@")).astype(np.uint8)
        cells = [row.tobytes().decode("ascii") for row in chars]
    event: dict[str, Any] = {
        "type": "world",
        "kind": world.get("kind", "grid"),
        "width": world.get("width") if free is None else int(free.shape[1]),
        "height": world.get("height") if free is None else int(free.shape[0]),
        "source": world.get("source", ""),
        "cells": cells,
    }
    optional = {"bounds": bounds, "y_up": y_up, "polygons": polygons, "edges": edges}
    event.update({k: v for k, v in optional.items() if v is not None})
    if marks is not None:
        event["marks"] = marks
    return event


def end_event(record: dict, messages: int | None = None) -> dict:
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
        "messages": messages if messages is not None else message_total(record),
    }


def record_events(
    record: dict,
    free: np.ndarray | None = None,
    speed: float | None = None,
    world: dict | None = None,
) -> list[dict[str, Any]]:
    """A finished run's record as the monitor's event stream, in mission-time order.

    ``world`` is the world event to send (``swarmex.cli.commands_monitor.record_world``
    rebuilds it from the record's parameters); without it the map is ``free`` or the bounds.
    """
    timed: list[dict[str, Any]] = []
    mission = record.get("mission")
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
        if mission == "traversal" and job_time is not None:
            timed += traversal_messages(agent, float(job_time))
    if mission == "foraging":
        timed += foraging_messages(record)
    rebuilt = mission == "foraging" or (mission == "traversal" and job_time is not None)
    sent = sum(e["type"] == "message" for e in timed)
    mode = "totals" if message_total(record) is not None else "none"
    if rebuilt:
        mode = "events"  # every message sent is in the stream (possibly none at all)
    timed.sort(key=lambda e: e["t"])  # stable: per agent, a move precedes its job
    end = end_event(record, sent if mode == "events" else None)
    end["t"] = max([end["t"], *(e["t"] for e in timed)])
    world_ev = world if world is not None else world_event(record, free)
    hello = hello_event(record, "network" if "network" in record else "simulation", speed, mode)
    vehicles = record.get("vehicles")
    if isinstance(vehicles, list) and vehicles:  # a networked record: what each id flew
        hello["vehicles"] = vehicles
    return [hello, world_ev, *timed, end]


def foraging_messages(record: dict) -> list[dict[str, Any]]:
    """The food-location messages of a foraging record (module doc): who told whom, when.

    The record keeps each robot's ``informed_at`` round and its position at every round, which
    is all the simulator's Look used to pick the teller, so the sender is rebuilt, not guessed.
    """
    params = record.get("params") or {}
    food = params.get("food")
    agents = record.get("agents", [])
    if not food or not agents:
        return []
    fx, fy = int(food[0]), int(food[1])

    def at(agent: dict, t: int) -> tuple[int, int] | None:
        traj = agent.get("trajectory", [])
        if not traj:
            return None
        step = traj[min(max(t, 0), len(traj) - 1)]
        if step[0] != t:  # not one entry per round: find the round's entry
            found = [s for s in traj if s[0] == t]
            if not found:
                return None
            step = found[-1]
        return int(step[1]), int(step[2])

    informed: dict[Any, Any] = {
        a["id"]: (a.get("metrics") or {}).get("informed_at") for a in agents
    }
    out = []
    for a in sorted(
        agents, key=lambda a: informed[a["id"]] if informed[a["id"]] is not None else 0
    ):
        t = informed[a["id"]]
        if t is None:
            continue
        here = at(a, t)
        if here is None or here == (fx, fy):
            continue  # found the food itself (or the record lacks the round): no message
        teller = None
        for b in agents:  # id order, as the Look's list of robots that know
            tb = informed[b["id"]]
            if b is a or tb is None or tb > t:
                continue
            there = at(b, t)
            if there is None or (tb == t and there != (fx, fy)):
                continue  # told in this same round by someone else: not yet a teller
            if abs(there[0] - here[0]) + abs(there[1] - here[1]) <= 1:
                teller = b["id"]
                break
        if teller is None:
            continue  # not what the simulator does: show nothing rather than invent a sender
        out.append(
            {
                "type": "message",
                "t": t,
                "agent": teller,
                "to": a["id"],
                "kind": "food",
                "x": fx,
                "y": fy,
            }
        )
    return out


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
