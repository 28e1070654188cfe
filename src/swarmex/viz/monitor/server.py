"""The monitor's web server: Starlette routes on uvicorn, bound to 127.0.0.1 only.

Routes: ``/`` the page, ``/monitor.js`` its script, ``/schema`` the event schema's text,
``/record`` the finished run's record (simulated missions), ``/ws`` the viewers' WebSocket
(server → browser: the hub's batches) and ``/ingest`` the producers' WebSocket (a networked
runtime → server: frames of events in the same schema, published as they come).

Why bind a socket ourselves and hand it to uvicorn: the port is known (and printed) before the
server starts, port 0 picks a free one, and nothing ever listens beyond the loopback.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import math
import socket
from collections.abc import Callable, Coroutine
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.responses import HTMLResponse, JSONResponse, PlainTextResponse, Response
from starlette.routing import Route, WebSocketRoute
from starlette.websockets import WebSocket, WebSocketDisconnect

from swarmex.viz.monitor import events as schema
from swarmex.viz.monitor.hub import EventHub
from swarmex.viz.monitor.page import INDEX_HTML, MONITOR_JS

HOST = "127.0.0.1"


def dumps(batch: Any) -> str:
    """A batch as JSON the browser can parse: Python writes ``NaN``/``Infinity`` for such
    floats, which ``JSON.parse`` rejects (losing the whole batch), so they go out as null."""
    try:
        return json.dumps(batch, allow_nan=False)
    except ValueError:
        return json.dumps(_finite(batch), allow_nan=False)


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    return value


class SnapshotDir:
    """Where ``--snapshot-every S DIR`` puts the page's PNGs: ``snapshot-NNNN-tT.png``, numbered
    in arrival order (T = the mission time the view showed)."""

    def __init__(self, every: float, folder: Path) -> None:
        self.every = float(every)
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.count = 0

    def write(self, png: bytes, t: str | None) -> Path:
        self.count += 1
        try:
            stamp = f"-t{float(t):.1f}" if t is not None else ""
        except ValueError:
            stamp = ""
        path = self.folder / f"snapshot-{self.count:04d}{stamp}.png"
        path.write_bytes(png)
        return path


def create_app(hub: EventHub, record: dict | Callable[[], dict | None] | None = None,
               snapshots: SnapshotDir | None = None) -> Starlette:
    """The page, its script, the schema, ``/record`` (a record, or a function giving the
    current one: a live run has its record only once it ends), the WebSockets, and
    ``/config`` + ``/snapshot`` (the page's PNGs of its view, written into ``snapshots``)."""
    dropped = [0]  # ingested frames or events refused (see ingest)

    async def index(_request: Any) -> Response:
        return HTMLResponse(INDEX_HTML)

    async def script(_request: Any) -> Response:
        return Response(MONITOR_JS, media_type="text/javascript")

    async def favicon(_request: Any) -> Response:
        return Response(status_code=204)

    async def schema_doc(_request: Any) -> Response:
        return PlainTextResponse(schema.__doc__ or "")

    async def record_json(_request: Any) -> Response:
        current = record() if callable(record) else record
        if current is None:
            return JSONResponse({"error": "no record: a live mission"}, status_code=404)
        return JSONResponse(current)

    async def config(_request: Any) -> Response:
        return JSONResponse({"snapshot_every": snapshots.every if snapshots else None,
                             "ingest_dropped": dropped[0]})

    async def snapshot(request: Any) -> Response:
        if snapshots is None:
            return JSONResponse({"error": "no --snapshot-every"}, status_code=404)
        body = await request.body()
        if not body.startswith(b"\x89PNG"):
            return JSONResponse({"error": "not a PNG"}, status_code=400)
        path = snapshots.write(body, request.query_params.get("t"))
        return JSONResponse({"wrote": path.name})

    async def viewer(ws: WebSocket) -> None:
        await ws.accept()
        q = hub.subscribe()
        try:
            while True:
                batch = await q.get()
                if batch is None:
                    break
                await ws.send_text(dumps(batch))
        except (WebSocketDisconnect, RuntimeError):  # the viewer left mid-send
            pass
        finally:
            hub.unsubscribe(q)
            with contextlib.suppress(Exception):
                await ws.close()

    async def ingest(ws: WebSocket) -> None:
        """A producer's frames: a JSON event or list of events each. A frame that is not
        JSON, or an event whose time is not a finite number, is dropped (and counted in
        ``/config``'s ``ingest_dropped``); the producer's socket stays open, since one bad
        frame must not cost it the rest of its mission."""
        await ws.accept()
        try:
            while True:
                message = await ws.receive()
                if message.get("type") == "websocket.disconnect":
                    break
                text = message.get("text")
                if text is None:  # a binary frame: not an event
                    dropped[0] += 1
                    continue
                try:
                    data = json.loads(text)
                except json.JSONDecodeError:
                    dropped[0] += 1
                    continue
                batch = data if isinstance(data, list) else [data]
                good = [e for e in batch if _event_ok(e)]
                dropped[0] += len(batch) - len(good)
                hub.publish(good)
        except WebSocketDisconnect:
            pass

    return Starlette(
        routes=[
            Route("/", index),
            Route("/monitor.js", script),
            Route("/schema", schema_doc),
            Route("/favicon.ico", favicon),
            Route("/record", record_json),
            Route("/config", config),
            Route("/snapshot", snapshot, methods=["POST"]),
            WebSocketRoute("/ws", viewer),
            WebSocketRoute("/ingest", ingest),
        ]
    )


def _event_ok(event: Any) -> bool:
    """An ingested event the page can use: an object with a type, and a time that, if
    given, is a finite number (a NaN was kept, sent to viewers as null, and broke the
    stream's time order; an event without ``t``, or with ``t: null``, has no time)."""
    if not isinstance(event, dict) or "type" not in event:
        return False
    t = event.get("t")
    return t is None or (isinstance(t, int | float) and not isinstance(t, bool)
                         and math.isfinite(t))


def bind(port: int = 0) -> socket.socket:
    """A listening-ready TCP socket on 127.0.0.1 (``port`` 0 = a free port)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((HOST, port))
    except OSError as exc:
        sock.close()
        from swarmex.errors import InputError

        raise InputError(f"--port {port}: cannot listen on {HOST}: {exc.strerror}") from None
    return sock


class MonitorServer:
    """One monitor: a hub, its app, a bound socket; :meth:`run` serves until stopped."""

    def __init__(self, port: int = 0, record: dict | None = None,
                 snapshots: SnapshotDir | None = None) -> None:
        self.sock = bind(port)
        self.port = int(self.sock.getsockname()[1])
        self.record = record
        self.snapshots = snapshots
        self.hub: EventHub | None = None
        self._server: Any = None
        self._loop: asyncio.AbstractEventLoop | None = None

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.port}/"

    async def run(
        self,
        producer: Any = None,
        linger: float | None = None,
        on_ready: Any = None,
    ) -> None:
        """Serve; ``producer(hub)`` is a coroutine function feeding the hub (None: ingest only).

        With ``linger`` the server stops that many seconds after the mission's end event.
        """
        import uvicorn

        self._loop = asyncio.get_running_loop()
        self.hub = EventHub()
        config = uvicorn.Config(
            create_app(self.hub, lambda: self.record, self.snapshots),
            log_level="warning",
            lifespan="off",
            timeout_graceful_shutdown=2,
            ws_ping_interval=None,
        )
        self._server = uvicorn.Server(config)
        tasks: list[asyncio.Task] = [asyncio.create_task(self._close_on_exit(self.hub))]
        if producer is not None:
            tasks.append(asyncio.create_task(_guard(producer(self.hub))))
        if linger is not None:
            tasks.append(asyncio.create_task(self._stop_after_end(self.hub, linger)))
        if on_ready is not None:
            tasks.append(asyncio.create_task(self._ready(on_ready)))
        try:
            await self._server.serve(sockets=[self.sock])
        finally:
            for t in tasks:
                t.cancel()
            self.sock.close()

    async def _ready(self, callback: Any) -> None:
        while not self._server.started:
            await asyncio.sleep(0.01)
        callback(self)

    async def _close_on_exit(self, hub: EventHub) -> None:
        """When uvicorn is asked to stop (Ctrl-C, SIGTERM), end the viewers' streams too.

        Otherwise their handlers wait for events forever and shutdown hangs until its timeout.
        """
        while not self._server.should_exit:
            await asyncio.sleep(0.1)
        hub.close()

    async def _stop_after_end(self, hub: EventHub, linger: float) -> None:
        await hub.ended.wait()
        await asyncio.sleep(linger)
        self.stop_now()

    def stop_now(self) -> None:
        """Close the viewers' streams and stop serving (call on the server's loop)."""
        if self.hub is not None:
            self.hub.close()
        if self._server is not None:
            self._server.should_exit = True

    def stop(self) -> None:
        """Thread-safe stop, for a server running in another thread (tests)."""
        if self._loop is not None and not self._loop.is_closed():
            with contextlib.suppress(RuntimeError):
                self._loop.call_soon_threadsafe(self.stop_now)


async def _guard(coro: Coroutine) -> None:
    """Run a producer; its failure is printed rather than lost in a background task."""
    try:
        await coro
    except asyncio.CancelledError:
        raise
    except Exception as exc:  # pragma: no cover - a producer bug must not stay silent
        import sys

        from swarmex.errors import InputError

        why = str(exc) if isinstance(exc, InputError) else repr(exc)  # bad input: its line
        print(f"swarmex monitor: event producer failed: {why}", file=sys.stderr)
