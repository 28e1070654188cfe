"""The clock and the record: discrete events, the result record, atomic writes, statistics."""

from swarmex.engine.atomic import atomic_open, atomic_path, write_atomic
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
    "atomic_open",
    "atomic_path",
    "plain",
    "read_record",
    "write_atomic",
    "write_json_atomic",
    "write_record",
]
