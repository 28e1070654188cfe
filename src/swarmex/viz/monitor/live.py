"""A simulated mission streamed to the monitor *while it runs*, from its frames.

Why: the page should show the run as it goes, from the same objects ``swarmex.run(...,
on_frame=...)`` hands a notebook and ``--render`` draws, not a finished record replayed
afterwards. The mission runs in a worker thread through the Mission contract; its
``on_frame`` turns every frame into the monitor's events (:mod:`.events` schema) and hands
them over a bounded queue to the server's loop, which publishes them paced in scaled time
(mission time t at wall t / speed). When the viewers are behind, the queue fills and the run
waits (back-pressure), so a long run never piles up in memory; when the server stops, the
next frame raises :class:`~swarmex.missions.base.StopRun` and the run ends.

The hello and world events come from a *skeleton* record: the same mission and params run
up to their first frame (a few milliseconds: the world, roadmap and agents exist by then),
so the map the page draws is rebuilt exactly as for a replayed record.

Per mission, what a frame becomes (the frame types are the missions' own):

* traversal (:class:`TraversalFrame`): a ``move`` at every start and arrival, a ``job`` when
  a job begins, and the §4.2 messages as the record replay rebuilds them — ``pos`` at the
  start and at an arrival without a job, ``job`` / ``done`` at a job's start and end, ``next``
  when the agent sets off (the frame's ``heading``);
* foraging (:class:`~swarmex.missions.foraging.sim.Frame`, one per round): a ``move`` for
  every robot whose cell changed, a ``pickup`` job when a robot starts carrying on the food
  cell and a ``drop`` when it stops in the nest, a ``status`` event when a robot starts or
  stops carrying or learns where the food is, and a ``food`` message to every robot newly
  informed away from the food, from the lowest-id robot that knew before (or found the food
  in that round) and stands at distance ≤ 1;
* roadmap (:class:`~swarmex.missions.roadmap.sim.RoadmapFrame`, one per step): a ``move``
  for every agent that moved in the step (all of them at step 0), and a ``weights`` event
  with the edges whose traversal count changed;
* exploration (:class:`~swarmex.missions.exploration.frames.Snapshot`, one per tick): a
  ``move`` for every robot whose cell changed; a ``known`` event with the cells of the team's
  merged map that became free or occupied and the frontier cells gained and lost (known-free
  cells next to unknown ones); a ``goals`` event when a robot's goal changes.
"""

from __future__ import annotations

import asyncio
import contextlib
import queue
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

from swarmex.missions.base import Mission, StopRun
from swarmex.viz.monitor.events import end_event, hello_event
from swarmex.viz.monitor.hub import CLOCK_INTERVAL, EventHub

Event = dict[str, Any]
QUEUE_BATCHES = 512  # frames' event batches buffered between the run and the server
# what each mission's live stream says about its messages (events.py "hello")
MESSAGE_MODES = {"traversal": "events", "foraging": "events", "exploration": "totals",
                 "roadmap": "none"}


def skeleton_record(mission: Mission[Any, Any], params: Any) -> dict:
    """The record of ``params`` run up to its first frame: its world, agents and params."""

    def stop(frame: Any) -> None:
        raise StopRun

    return mission.run(params, stop, trace=False).record.to_dict()


def _move(t: float, agent: Any, x: float, y: float) -> Event:
    return {"type": "move", "t": t, "agent": agent, "x": x, "y": y}


def _message(t: float, agent: Any, kind: str, x: Any, y: Any, to: Any = None) -> Event:
    return {"type": "message", "t": t, "agent": agent, "to": to, "kind": kind, "x": x, "y": y}


class TraversalEvents:
    def __call__(self, f: Any) -> list[Event]:
        xy = next(((x, y) for a, x, y in f.positions if a == f.agent), None)
        if xy is None:
            return []
        t, a = f.t, f.agent
        out: list[Event] = []
        if f.event in ("start", "arrive"):
            out.append(_move(t, a, *xy))
            if f.event == "start" or not f.job:
                out.append(_message(t, a, "pos", *xy))
        if f.job:
            out += [{"type": "job", "t": t, "agent": a, "x": xy[0], "y": xy[1]},
                    _message(t, a, "job", *xy)]
        if f.event == "job_end":
            out.append(_message(t, a, "done", *xy))
        if f.heading is not None:
            out.append(_message(t, a, "next", *f.heading))
        return out


class IndexedEvents:
    """Roadmap and exploration frames: agents by index, mapped to the record's ids."""

    def __init__(self, ids: list[Any]) -> None:
        self.ids = ids
        self.last: np.ndarray | None = None

    def __call__(self, f: Any) -> list[Event]:
        t = float(f.step if hasattr(f, "step") else f.t)
        pos = np.asarray(f.positions, dtype=float).reshape(-1, 2)
        if hasattr(f, "moved") and self.last is not None:
            who = list(f.moved)
        else:
            who = [i for i in range(len(pos))
                   if self.last is None or not np.array_equal(pos[i], self.last[i])]
        self.last = pos
        return [_move(t, self.ids[i], float(pos[i][0]), float(pos[i][1])) for i in who]


class ForagingEvents:
    def __init__(self, ids: list[Any], record: dict) -> None:
        params = record.get("params") or {}
        self.ids = ids
        fx, fy = params.get("food") or (-1, -1)
        self.food = (int(fx), int(fy))
        g = int(params.get("grid") or 0)
        self.nest = (g // 2, g // 2)
        self.last: Any = None

    def __call__(self, f: Any) -> list[Event]:
        t = float(f.t)
        pos = np.asarray(f.positions)
        out: list[Event] = []
        last = self.last
        for i in range(len(pos)):
            if last is None or not np.array_equal(pos[i], last.positions[i]):
                out.append(_move(t, self.ids[i], int(pos[i][0]), int(pos[i][1])))
        for i in range(len(pos)):  # who carries a unit, who knows where the food is
            if (last is None or f.carrying[i] != last.carrying[i]
                    or f.informed[i] != last.informed[i]):
                out.append({"type": "status", "t": t, "agent": self.ids[i],
                            "carrying": bool(f.carrying[i]), "informed": bool(f.informed[i])})
        if last is not None:
            for i in range(len(pos)):
                here = (int(pos[i][0]), int(pos[i][1]))
                if f.carrying[i] and not last.carrying[i] and here == self.food:
                    out.append({"type": "job", "t": t, "agent": self.ids[i], "x": here[0],
                                "y": here[1], "kind": "pickup"})
                elif not f.carrying[i] and last.carrying[i] and here == self.nest:
                    out.append({"type": "job", "t": t, "agent": self.ids[i], "x": here[0],
                                "y": here[1], "kind": "drop"})
            fx, fy = self.food
            # tellers: robots that knew before, and a finder that learned it this round on the
            # food cell itself (the replay's rule, events.foraging_messages: a robot next to
            # the finder in its finding round heard it, and the live stream lost that message)
            on_food = (pos[:, 0] == fx) & (pos[:, 1] == fy)
            knew = np.flatnonzero(last.informed | (f.informed & on_food))
            for k in np.flatnonzero(f.informed & ~last.informed):
                here = pos[k]
                if (int(here[0]), int(here[1])) == self.food:
                    continue  # found it itself
                near = [j for j in knew if np.abs(pos[j] - here).sum() <= 1]
                if near:
                    out.append(_message(t, self.ids[int(near[0])], "food", fx, fy,
                                        to=self.ids[int(k)]))
        self.last = f
        return out


def frontier_of(known: np.ndarray) -> np.ndarray:
    """Known-free cells with an unknown 4-neighbour (what the robots head for)."""
    unknown = known == 0
    near = np.zeros_like(unknown)
    near[1:, :] |= unknown[:-1, :]
    near[:-1, :] |= unknown[1:, :]
    near[:, 1:] |= unknown[:, :-1]
    near[:, :-1] |= unknown[:, 1:]
    return (known == 1) & near


class ExplorationEvents(IndexedEvents):
    """Moves, plus the team's merged map as it grows: a ``known`` event with the cells that
    changed (flat indices, row-major) into free, occupied and frontier, and the cells that
    stopped being frontier; and the robots' current goals."""

    def __init__(self, ids: list[Any]) -> None:
        super().__init__(ids)
        self.known: np.ndarray | None = None
        self.frontier: np.ndarray | None = None
        self.goals: list[Any] = []

    def __call__(self, f: Any) -> list[Event]:
        out = super().__call__(f)
        t = float(f.t)
        known = np.asarray(f.known, dtype=np.uint8)
        front = frontier_of(known)
        if self.known is None or self.frontier is None:
            self.known = np.zeros_like(known)
            self.frontier = np.zeros_like(front)
        changed = known != self.known
        flat = known.ravel()
        idx = np.flatnonzero(changed.ravel())
        gained = np.flatnonzero((front & ~self.frontier).ravel())
        lost = np.flatnonzero((~front & self.frontier).ravel())
        if idx.size or gained.size or lost.size:
            out.append({"type": "known", "t": t, "cols": int(known.shape[1]),
                        "free": idx[flat[idx] == 1].tolist(),
                        "occupied": idx[flat[idx] == 2].tolist(),
                        "frontier": gained.tolist(), "not_frontier": lost.tolist()})
        self.known, self.frontier = known, front
        goals = [None if g is None else [int(g[0]), int(g[1])] for g in f.goals]
        if goals != self.goals:
            out.append({"type": "goals", "t": t,
                        "goals": [None if g is None else [self.ids[i], *g]
                                  for i, g in enumerate(goals)]})
            self.goals = goals
        return out


class RoadmapEvents(IndexedEvents):
    """Moves, plus the roadmap's edge weights as they change: a ``weights`` event with
    ``[edge, traversals]`` pairs (edge = its index in the world event's ``edges``, whose
    first entries are the roadmap's edges in order)."""

    def __init__(self, ids: list[Any]) -> None:
        super().__init__(ids)
        self.weights: np.ndarray | None = None

    def __call__(self, f: Any) -> list[Event]:
        out = super().__call__(f)
        w = np.asarray(f.edge_traversals)
        before = self.weights if self.weights is not None else np.zeros_like(w)
        changed = np.flatnonzero(w != before)
        if changed.size:
            out.append({"type": "weights", "t": float(f.step),
                        "edges": [[int(e), int(w[e])] for e in changed]})
        self.weights = w
        return out


def frame_converter(record: dict) -> Callable[[Any], list[Event]]:
    """The frame → events function of the record's mission."""
    ids = [a["id"] for a in record.get("agents", [])]
    mission = record.get("mission")
    if mission == "traversal":
        return TraversalEvents()
    if mission == "foraging":
        return ForagingEvents(ids, record)
    if mission == "exploration":
        return ExplorationEvents(ids)
    if mission == "roadmap":
        return RoadmapEvents(ids)
    return IndexedEvents(ids)


async def stream_run(
    hub: EventHub,
    mission: Mission[Any, Any],
    params: Any,
    skeleton: dict,
    world: Event,
    speed: float,
    wait_for_viewer: bool = True,
    on_record: Callable[[dict], None] | None = None,
    clock_interval: float = CLOCK_INTERVAL,
) -> None:
    """Run ``params`` in a worker thread and publish its frames' events as they come."""
    if wait_for_viewer:
        await hub.viewer_joined.wait()
    mode = MESSAGE_MODES.get(str(skeleton.get("mission")), "totals")
    hub.publish([hello_event(skeleton, "simulation", speed, mode), world])
    convert = frame_converter(skeleton)
    batches: queue.Queue = queue.Queue(QUEUE_BATCHES)
    stop = threading.Event()
    sent = 0

    def hand_over(item: Any) -> None:
        while not stop.is_set():
            with contextlib.suppress(queue.Full):
                batches.put(item, timeout=0.2)
                return
        raise StopRun

    def on_frame(frame: Any) -> None:
        events = convert(frame)
        if events:
            hand_over(events)

    def work() -> None:
        try:
            record = mission.run(params, on_frame).record.to_dict()
            hand_over(("done", record))
        except StopRun:
            pass
        except BaseException as exc:  # noqa: BLE001 - reported on the server's loop
            with contextlib.suppress(StopRun):
                hand_over(("error", exc))

    worker = threading.Thread(target=work, name="swarmex-live-run", daemon=True)
    worker.start()
    loop = asyncio.get_running_loop()
    start = loop.time()
    last_t = 0.0
    def next_item() -> Any:
        """The next batch, or None after a short wait (so no executor thread is left
        blocked when the server stops)."""
        try:
            return batches.get(timeout=0.2)
        except queue.Empty:
            return None

    try:
        while True:
            item = await loop.run_in_executor(None, next_item)
            if item is None:
                if not worker.is_alive() and batches.empty():
                    return  # stopped without a record (the server is closing)
                continue
            if isinstance(item, tuple):
                kind, value = item
                if kind == "error":
                    raise value
                end = end_event(value, sent if mode == "events" else None)
                end["t"] = max(end["t"], last_t)  # never before an event already shown
                hub.publish([end])
                if on_record is not None:
                    on_record(value)
                return
            due = max(float(e["t"]) for e in item)
            if speed != float("inf"):
                while (now := (loop.time() - start) * speed) < due:
                    hub.publish([{"type": "clock", "t": now}], keep=False)
                    await asyncio.sleep(min(clock_interval, (due - now) / speed))
            sent += sum(e["type"] == "message" for e in item)
            last_t = max(last_t, due)
            hub.publish(item)
    finally:
        stop.set()
