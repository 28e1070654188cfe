"""The exploration mission's messages (seed 003 §3.3.5), as small dataclasses.

Each message has ``kind`` (the thesis's type name), a ``to_dict()`` made only of ints,
floats, strings, bytes and lists (msgpack-ready: the networked runtime sends exactly this),
``from_dict()`` to rebuild it, and ``nbytes``: the size of its msgpack encoding, which is what
the ``bytes_sent`` metric adds up.

=============  =================================================  ==========================
kind           content                                            delivery
=============  =================================================  ==========================
HEARTBEAT      sender id and cell                                 radio broadcast, 1 s
SCAN           one or more local maps, each keyed (origin, seq)   flooded, de-duplicated
NEED_MAP       the requester's archive summary (ranges of seqs)   to a new neighbour
MAP            the local maps the requester lacks                 reply to NEED_MAP
GOAL           the sender's goal cell (or none), its priority     to every neighbour
               (path length to the goal) and the sender's cell
CHANGE_GOAL    the sender's goal and priority: "re-plan"          to one neighbour
=============  =================================================  ==========================

Choices (spec §6.6–6.7): a scan travels as its *local map* (a box and two bit masks: passed
and hit cells), which is what the receiver's Bayesian update needs and what the thesis calls
the scans it exchanges; ``NEED_MAP`` carries a summary of what the requester already has so
that ``MAP`` holds only the part of the archive it lacks (after it, the requester has the
sender's complete archive, as in the thesis, for a fraction of the bytes).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, ClassVar

import msgpack

from swarmex.comm.message import PackedMessage, once, packed_size
from swarmex.sensing.occupancy import LocalMap


def _scans_size(scans: tuple) -> int:
    """Encoded size of a list of scans (array header plus each scan's cached size)."""
    n = len(scans)
    return sum(s.nbytes for s in scans) + (0 if n <= 15 else 2 if n < 65536 else 4)


@lru_cache(maxsize=4096)
def _head_size(kind: str, src: int) -> int:
    """Size of a scan container's envelope with an empty scan list."""
    return packed_size({"type": kind, "src": src, "scans": []})


def scan_head_size(src: int) -> int:
    """Bytes of a ``SCAN`` from ``src`` beyond its scans' own: ``ScanMsg(src, (rec,)).nbytes``
    is ``scan_head_size(src) + rec.nbytes`` (how a flood relay is counted without sizing each
    relay message)."""
    return _head_size(ScanMsg.kind, src)


@dataclass(eq=False)
class ScanRecord:
    """One archived scan: who took it, its number, where from, and its local map."""

    origin: int
    seq: int
    x: int
    y: int
    local: LocalMap
    _wire: dict | None = field(default=None, repr=False)
    key: tuple[int, int] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.key = (self.origin, self.seq)

    def to_dict(self) -> dict:
        if self._wire is None:
            self._wire = {"o": self.origin, "s": self.seq, "x": self.x, "y": self.y,
                          **self.local.to_wire()}
        return self._wire

    @classmethod
    def from_dict(cls, d: dict) -> ScanRecord:
        return cls(int(d["o"]), int(d["s"]), int(d["x"]), int(d["y"]), LocalMap.from_wire(d))

    @once
    def nbytes(self) -> int:
        return packed_size(self.to_dict())


class Message(PackedMessage):
    """An exploration message (the table above)."""


@dataclass(eq=False)
class Heartbeat(Message):
    kind: ClassVar[str] = "HEARTBEAT"
    src: int
    x: int
    y: int

    def body(self) -> dict[str, Any]:
        return {"src": self.src, "x": self.x, "y": self.y}


@dataclass(eq=False)
class ScanMsg(Message):
    kind: ClassVar[str] = "SCAN"
    src: int  # the robot transmitting (origin or relay)
    scans: tuple[ScanRecord, ...]

    def body(self) -> dict[str, Any]:
        return {"src": self.src, "scans": [s.to_dict() for s in self.scans]}

    @once
    def nbytes(self) -> int:
        # the scans' encodings are cached, so a relay's size costs no re-packing
        scans = self.scans
        if len(scans) == 1:  # a flooded scan: no array header beyond the empty list's
            return _head_size(self.kind, self.src) + scans[0].nbytes
        return _head_size(self.kind, self.src) + _scans_size(scans)


@dataclass(eq=False)
class NeedMap(Message):
    kind: ClassVar[str] = "NEED_MAP"
    src: int
    have: tuple[tuple[int, int, int], ...]  # (origin, first seq, last seq + 1) runs

    def body(self) -> dict[str, Any]:
        return {"src": self.src, "have": [list(r) for r in self.have]}


@dataclass(eq=False)
class MapMsg(ScanMsg):
    kind: ClassVar[str] = "MAP"


@dataclass(eq=False)
class Goal(Message):
    kind: ClassVar[str] = "GOAL"
    src: int
    goal: tuple[int, int] | None  # (x, y) cell, None when the sender has finished
    priority: float  # path length (steps) from the sender's cell to its goal
    x: int
    y: int

    def body(self) -> dict[str, Any]:
        g = None if self.goal is None else list(self.goal)
        return {"src": self.src, "goal": g, "priority": self.priority, "x": self.x, "y": self.y}


@dataclass(eq=False)
class ChangeGoal(Message):
    kind: ClassVar[str] = "CHANGE_GOAL"
    src: int
    goal: tuple[int, int]
    priority: float

    def body(self) -> dict[str, Any]:
        return {"src": self.src, "goal": list(self.goal), "priority": self.priority}


KINDS: dict[str, type[Message]] = {
    c.kind: c for c in (Heartbeat, ScanMsg, NeedMap, MapMsg, Goal, ChangeGoal)
}


def from_dict(d: dict[str, Any]) -> Message:
    """Rebuild a message from its ``to_dict()`` form (e.g. after a msgpack round trip)."""
    kind = d["type"]
    cls = KINDS[kind]
    if cls in (ScanMsg, MapMsg):
        return cls(int(d["src"]), tuple(ScanRecord.from_dict(s) for s in d["scans"]))
    if cls is NeedMap:
        have = tuple((int(o), int(lo), int(hi)) for o, lo, hi in d["have"])
        return NeedMap(int(d["src"]), have)
    if cls is Goal:
        g = d["goal"]
        return Goal(int(d["src"]), None if g is None else (int(g[0]), int(g[1])),
                    float(d["priority"]), int(d["x"]), int(d["y"]))
    if cls is ChangeGoal:
        g = d["goal"]
        return ChangeGoal(int(d["src"]), (int(g[0]), int(g[1])), float(d["priority"]))
    return Heartbeat(int(d["src"]), int(d["x"]), int(d["y"]))


def encode(msg: Message) -> bytes:
    return msgpack.packb(msg.to_dict(), use_bin_type=True)


def decode(data: bytes) -> Message:
    return from_dict(msgpack.unpackb(data, raw=False))
