"""Monitor events from the networked runtime, and the ways to get them to a viewer.

The events follow the live monitor's schema (``swarmex.monitor/1``: ``hello``, ``world``,
``move``, ``job``, ``message``, ``clock``, ``end``; see :mod:`swarmex.viz.monitor.events`,
restated here so this module does not depend on the web stack). A viewer cannot tell a
networked mission from a replayed simulation except by ``hello.source == "network"``.

Three ways out, all fed by the same batches:

* viewers on the mission's own port: a DEALER sends ``MON`` and gets every batch so far,
  then the live ones, as ``["EV", json]`` frames (``swarmex watch``);
* :class:`IngestForwarder`: pushes batches to the web monitor's ``/ingest`` WebSocket
  (``swarmex serve --monitor ws://…`` or ``swarmex watch --forward ws://…``) from a thread,
  so a slow or absent monitor never stalls the mission;
* :func:`network_producer`: an asyncio producer for the monitor's own server loop, for a
  ``swarmex monitor --connect tcp://…`` option.
"""

from __future__ import annotations

import asyncio
import json
import queue
import threading
import time
from collections.abc import Awaitable, Callable, Iterator
from typing import Any

import numpy as np

from swarmex.engine.record import message_total

SCHEMA = "swarmex.monitor/1"
Event = dict[str, Any]


def hello(mission: str, algorithm: str, agents: list[int], title: str,
          speed: float | None, time_unit: str = "s",
          vehicles: list[dict[str, Any]] | None = None, messages: str = "events") -> Event:
    """``vehicles`` (optional): ``[{"id", "kind", …}]``, what each agent flies ("simulated",
    "mavlink"): a hybrid mission's viewer tells them apart. ``messages``: what the stream
    shows of the messages, "events" (each one) or "totals" (the end's count only)."""
    out: Event = {
        "type": "hello",
        "schema": SCHEMA,
        "mission": mission,
        "algorithm": algorithm,
        "source": "network",
        "time_unit": time_unit,
        "agents": agents,
        "speed": speed,
        "title": title,
        "messages": messages,
    }
    if vehicles is not None:
        out["vehicles"] = vehicles
    return out


def world(free: np.ndarray | None, width: int, height: int, source: str,
          kind: str = "grid") -> Event:
    cells = None
    if free is not None:
        chars = np.where(free, ord("."), ord("@")).astype(np.uint8)
        cells = [row.tobytes().decode("ascii") for row in chars]
    return {"type": "world", "kind": kind, "width": width, "height": height,
            "source": source, "cells": cells}


def move(t: float, agent: int, x: float, y: float) -> Event:
    return {"type": "move", "t": t, "agent": agent, "x": x, "y": y}


def job(t: float, agent: int, x: float, y: float) -> Event:
    return {"type": "job", "t": t, "agent": agent, "x": x, "y": y}


def message(t: float, agent: int, kind: str, x: float | None = None,
            y: float | None = None, to: int | None = None,
            extra: dict[str, Any] | None = None) -> Event:
    """``extra``: optional fields (a ``join`` says the spare's ``vehicle``, a ``left`` its
    ``reason``)."""
    ev = {"type": "message", "t": t, "agent": agent, "to": to, "kind": kind, "x": x, "y": y}
    if extra:
        ev.update(extra)
    return ev


def end(record: dict[str, Any], after: list[Event] | None = None) -> Event:
    """The end event; its ``t`` is no earlier than any event in ``after`` (times must not go
    back, and the makespan can be earlier than the last message: staggered starts)."""
    last = max((float(e["t"]) for e in after or () if "t" in e), default=0.0)
    return {
        "type": "end",
        "t": max(float(record.get("makespan") or 0.0), last),
        "complete": bool(record.get("complete")),
        "makespan": record.get("makespan"),
        "time_unit": record.get("time_unit", "s"),
        "metrics": record.get("metrics", {}),
        "messages": message_total(record),
        "agents": [{"id": a["id"], "metrics": a.get("metrics", {})}
                   for a in record.get("agents", [])],
    }


def dumps(batch: list[Event]) -> str:
    return json.dumps(batch, separators=(",", ":"), allow_nan=False, default=_plain)


def _plain(v: Any) -> Any:
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.floating):
        return float(v)
    raise TypeError(f"not JSON: {type(v).__name__}")


class IngestForwarder:
    """Sends event batches to a monitor's ``/ingest`` WebSocket from a background thread.

    Why a thread and a queue: the mission loop must never wait on a viewer. Batches queue up
    while the socket connects (a monitor started a moment later still gets the ``hello``);
    if the monitor is unreachable the forwarder gives up after ``connect_timeout`` and drops
    what it holds, counted in :attr:`dropped`. Why ``warn``: events that go nowhere must be
    said once (a mistyped URL sent a whole mission into the void without a word);
    :meth:`shortfall` sums it up at the end.
    """

    def __init__(self, url: str, connect_timeout: float = 5.0,
                 warn: Callable[[str], object] | None = None) -> None:
        from swarmex.errors import require

        # here, not in the thread: without the extra its import failed there as a traceback
        require("websockets", "monitor", "a monitor's ingest URL")
        self.url = url
        self.connect_timeout = connect_timeout
        self.queue: queue.Queue[str | None] = queue.Queue()
        self.sent = 0
        self.dropped = 0
        self.error: str | None = None
        self.warn = warn
        self._thread = threading.Thread(target=self._run, name="ingest", daemon=True)
        self._thread.start()

    def send(self, batch: list[Event]) -> None:
        if batch:
            self.queue.put(dumps(batch))

    def close(self, timeout: float = 3.0) -> None:
        """Send what is queued (for at most ``timeout`` seconds once connected; a monitor
        still being reached gets the rest of ``connect_timeout`` first)."""
        self.queue.put(None)
        self._thread.join(timeout + self.connect_timeout)

    def shortfall(self) -> str | None:
        """One line when some batches did not reach the monitor (after :meth:`close`)."""
        if not self.dropped:
            return None
        return (f"{self.dropped} of {self.sent + self.dropped} event batches did not reach the "
                f"monitor at {self.url} ({self.error})")

    def _run(self) -> None:
        from websockets.sync.client import connect

        deadline = time.monotonic() + self.connect_timeout
        while True:
            try:
                conn = connect(self.url, open_timeout=1.0)
            except Exception as exc:  # refused, DNS, handshake: retry until the deadline
                self.error = f"{type(exc).__name__}: {exc}"
                if time.monotonic() >= deadline:
                    if self.warn is not None:
                        self.warn(f"swarmex: the monitor at {self.url} is unreachable "
                                  f"({self.error}); the mission goes on without it")
                    break
                time.sleep(0.2)
                continue
            with conn as ws:
                self._pump(ws)
            return
        while self.queue.get() is not None:  # no monitor: count what could not go out
            self.dropped += 1

    def _pump(self, ws: Any) -> None:
        while (item := self.queue.get()) is not None:
            try:
                ws.send(item)
                self.sent += 1
            except Exception as exc:  # the monitor went away: drop the rest, counted
                if not self.dropped and self.warn is not None:  # said once
                    self.warn(f"swarmex: the monitor at {self.url} went away "
                              f"({type(exc).__name__}: {exc}); the mission goes on without it")
                self.error = f"{type(exc).__name__}: {exc}"
                self.dropped += 1


def viewer_batches(address: str, timeout: float = 10.0,
                   stop: Callable[[], bool] | None = None,
                   wait_first: bool = False) -> Iterator[list[Any]]:
    """Yield event batches from a mission server (or exploration display) at ``address``.

    Ends after an ``end`` event, or when nothing (not even a heartbeat) came for
    ``timeout`` seconds; with ``wait_first``, the wait for the server's first word has no
    limit (a monitor is often started before its mission).
    """
    import zmq

    from swarmex.net import wire

    ctx: zmq.Context[zmq.Socket[bytes]] = zmq.Context.instance()
    sock = ctx.socket(zmq.DEALER)
    sock.setsockopt(zmq.LINGER, 0)
    sock.setsockopt(zmq.RCVHWM, 0)
    sock.connect(address)
    try:
        sock.send(wire.pack(["MON"]))
        last = time.monotonic()
        heard = False
        next_hb = last + 1.0
        while True:
            if stop is not None and stop():
                return
            if sock.poll(200):
                frame = sock.recv()
                last = time.monotonic()
                heard = True
                try:
                    msg = wire.unpack(frame)
                except wire.WireError:
                    continue
                if isinstance(msg, list) and len(msg) == 2 and msg[0] == "EV":
                    try:
                        batch = json.loads(msg[1])
                    except (TypeError, ValueError):
                        continue
                    if isinstance(batch, list):
                        yield batch
                        if any(isinstance(e, dict) and e.get("type") == "end" for e in batch):
                            return
            now = time.monotonic()
            if now >= next_hb:  # the server drops viewers it has not heard from
                sock.send(wire.pack(["MON"]))
                next_hb = now + 1.0
            if now - last > timeout and (heard or not wait_first):
                return
    finally:
        sock.close(0)


def network_producer(address: str, timeout: float = 10.0,
                     say: Callable[[str], object] | None = None,
                     on_lost: Callable[[], object] | None = None,
                     ) -> Callable[[Any], Awaitable[None]]:
    """A producer for the web monitor's server loop: publishes a live mission's batches.

    ``MonitorServer.run(producer, …)`` calls ``producer(hub)``; this one reads the mission's
    events on a worker thread (the ZeroMQ socket is blocking) and publishes them on the loop.
    It waits for the mission as long as it takes (``say`` reports when it is first heard);
    a mission that then falls silent for ``timeout`` seconds before its end is reported with
    ``say`` and ``on_lost`` is called (the monitor then stops as after an end).
    """

    async def produce(hub: Any) -> None:
        loop = asyncio.get_running_loop()
        q: asyncio.Queue[list[Any] | None] = asyncio.Queue()
        done = threading.Event()

        ended = heard = False

        def pump() -> None:
            nonlocal ended, heard
            try:
                for batch in viewer_batches(address, timeout, stop=done.is_set, wait_first=True):
                    if not heard and say is not None:
                        say(f"swarmex monitor: receiving the mission at {address}")
                    heard = True
                    ended = ended or any(isinstance(e, dict) and e.get("type") == "end"
                                         for e in batch)
                    loop.call_soon_threadsafe(q.put_nowait, batch)
            finally:
                loop.call_soon_threadsafe(q.put_nowait, None)

        worker = threading.Thread(target=pump, daemon=True)
        worker.start()
        try:
            while True:
                batch = await q.get()
                if batch is None:
                    break
                hub.publish(batch)
            if not ended and not done.is_set():
                if say is not None:
                    say(f"swarmex monitor: the mission at {address} fell silent before its end"
                        f" (nothing for {timeout:g} s); the page keeps what it showed")
                if on_lost is not None:
                    on_lost()
        finally:
            done.set()

    return produce
