"""The event hub: producers publish event batches, every viewer gets all of them.

Why a hub with a history: a viewer may open the page before, during or after a mission (or
reload it); it first receives everything published since the last ``hello`` and then the live
events, so every viewer converges on the same state whatever it joined. Producers are the
scaled-time replay of a simulated run (:func:`replay`) or, for a networked mission, whatever
writes to the ``/ingest`` WebSocket — the hub does not know which.

All methods run on the server's asyncio loop (single-threaded, so no locks).
"""

from __future__ import annotations

import asyncio
import bisect
from typing import Any

Event = dict[str, Any]
HISTORY_CHUNK = 2000  # events per frame when a late viewer catches up
CLOCK_INTERVAL = 0.2  # wall seconds between clock ticks when nothing else happens


class EventHub:
    def __init__(self) -> None:
        self.history: list[Event] = []
        self.subscribers: set[asyncio.Queue] = set()
        self.viewer_joined = asyncio.Event()
        self.ended = asyncio.Event()
        self.closed = False

    def publish(self, events: list[Event], keep: bool = True) -> None:
        """Send a batch to every viewer; ``keep`` adds it to the history (clock ticks don't)."""
        if not events:
            return
        for i, ev in enumerate(events):
            if ev.get("type") == "hello":  # a new mission: history starts again from it
                self.history.clear()
                self.ended.clear()
                events = events[i:]
        if keep:
            self.history.extend(events)
        for q in self.subscribers:
            q.put_nowait(events)
        if any(ev.get("type") == "end" for ev in events):
            self.ended.set()

    def subscribe(self) -> asyncio.Queue:
        """A queue preloaded with the history, then fed every live batch; None = closing."""
        q: asyncio.Queue = asyncio.Queue()
        for lo in range(0, len(self.history), HISTORY_CHUNK):
            q.put_nowait(self.history[lo : lo + HISTORY_CHUNK])
        if self.closed:
            q.put_nowait(None)
        self.subscribers.add(q)
        self.viewer_joined.set()
        return q

    def unsubscribe(self, q: asyncio.Queue) -> None:
        self.subscribers.discard(q)

    def close(self) -> None:
        """Tell every viewer connection to finish (the server is stopping)."""
        self.closed = True
        for q in self.subscribers:
            q.put_nowait(None)


async def replay(
    hub: EventHub,
    events: list[Event],
    speed: float,
    wait_for_viewer: bool = True,
    clock_interval: float = CLOCK_INTERVAL,
) -> None:
    """Publish a finished run's events paced in scaled time: mission time t at wall t / speed.

    Untimed events (hello, world) go first. Every event due by now goes out in one batch, and
    between events a clock tick keeps the viewers' clocks moving. ``speed`` = inf publishes
    everything at once.
    """
    if wait_for_viewer:
        await hub.viewer_joined.wait()
    loop = asyncio.get_running_loop()
    head = [e for e in events if "t" not in e]
    timed = [e for e in events if "t" in e]
    times = [float(e["t"]) for e in timed]
    hub.publish(head)
    if speed == float("inf"):
        hub.publish(timed)
        return
    start = loop.time()
    i, n = 0, len(timed)

    def mission_now() -> float:
        return (loop.time() - start) * speed

    while i < n:
        now = mission_now()
        j = bisect.bisect_right(times, now, lo=i)
        if j > i:
            hub.publish(timed[i:j])
            i = j
        else:
            hub.publish([{"type": "clock", "t": now}], keep=False)
        if i < n:
            wait = (times[i] - mission_now()) / speed
            await asyncio.sleep(max(0.0, min(clock_interval, wait)))
