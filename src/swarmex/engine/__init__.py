"""The clock and the record: discrete events, the run loop helpers, the result record."""

from swarmex.engine.events import Event, EventQueue
from swarmex.engine.record import (
    AgentRecord,
    ResultRecord,
    plain,
    read_record,
    write_json_atomic,
    write_record,
)

__all__ = [
    "AgentRecord",
    "Event",
    "EventQueue",
    "ResultRecord",
    "plain",
    "read_record",
    "write_json_atomic",
    "write_record",
]
