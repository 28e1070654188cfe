"""The live web monitor: a page that shows a running mission from a stream of JSON events.

:mod:`~swarmex.viz.monitor.events` defines the stream (and turns a result record into it),
:mod:`~swarmex.viz.monitor.hub` fans it out to viewers in scaled time,
:mod:`~swarmex.viz.monitor.live` runs a mission in a worker thread and turns its frames into
the stream as they come,
:mod:`~swarmex.viz.monitor.server` serves the page and the WebSockets on 127.0.0.1, and
:mod:`~swarmex.viz.monitor.page` is the canvas front end. ``swarmex monitor`` wires them up.
"""

from swarmex.viz.monitor.events import SCHEMA, record_events
from swarmex.viz.monitor.hub import EventHub, replay

__all__ = ["SCHEMA", "EventHub", "record_events", "replay"]
