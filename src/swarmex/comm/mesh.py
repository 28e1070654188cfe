"""A range-limited mesh: heartbeats, neighbour tables, flooding with de-duplication.

Seed 003's robots form a MANET (§1.2, §2.1.5): each robot announces itself with a heartbeat
every second, connects to whoever it hears, drops a neighbour that falls silent, relays
flooded messages (``SCAN`` goes "to all accessible nodes in a network") and sends the rest
to its direct neighbours. Two pieces, kept apart so the networked runtime can reuse the first:

* :class:`MeshNode`, the protocol state one robot keeps: its neighbour table (last time each
  neighbour was heard), the heartbeat timer, and the set of flood keys already seen.
  Flood de-duplication is by ``(origin, sequence)``: the first copy of a key is accepted and
  relayed to every neighbour but the one it came from; later copies are dropped. That is a
  flood's whole routing: with de-duplication every node relays each message once, and a
  message reaches every node connected to its origin through any number of hops.
* :class:`DiscNetwork`, the simulated radio: the thesis's disc model, where two robots hear
  each other when they are within ``range`` metres "regardless of the presence of obstacles"
  (§1.1). It queues and counts messages. Heartbeats are broadcasts (UDP in the thesis) that
  reach everyone in range; other messages are unicasts to a neighbour-table entry (the
  thesis's PUSH sockets) and are *lost* when the peer has moved out of range (the nanomsg
  send timeout drops them). Delivery is instantaneous, so a flood crosses the whole
  connected component within one 100 ms tick, as it would over a LAN.

Unicasts to robots beyond direct range are routed by AODV (:mod:`swarmex.comm.aodv`), whose
hellos are these heartbeats; :meth:`DiscNetwork.totals` counts its control messages
(RREQ, RREP, RERR) separately as ``aodv_messages`` / ``aodv_bytes``.

Timing constants the thesis leaves open (spec §6.9) are parameters: heartbeat period 1 s
(the thesis's), neighbour timeout 3 heartbeat periods (three missed heartbeats, AODV's
``ALLOWED_HELLO_LOSS`` is 2 plus the current one).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from swarmex.comm.aodv import CONTROL_KINDS as AODV_KINDS
from swarmex.errors import InputError


class Sized(Protocol):
    """A message as the radio counts it (read-only: a class constant or a property will do)."""

    @property
    def kind(self) -> str: ...

    @property
    def nbytes(self) -> int: ...


@dataclass
class MeshNode:
    """One robot's mesh protocol state (time in any unit, used consistently)."""

    id: int
    heartbeat_period: float = 10.0
    timeout: float = 30.0
    phase: float = 0.0  # first heartbeat time
    neighbours: dict[int, float] = field(default_factory=dict)  # id -> last heard
    seen: set[tuple[int, int]] = field(default_factory=set)
    _sorted: list[int] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.heartbeat_period <= 0 or self.timeout <= 0:
            raise InputError("heartbeat period and neighbour timeout must be positive")

    def heartbeat_due(self, t: float) -> bool:
        if t < self.phase:
            return False
        k = (t - self.phase) / self.heartbeat_period
        return abs(k - round(k)) < 1e-9

    def hear(self, src: int, t: float) -> bool:
        """A heartbeat from ``src`` arrived: refresh it; True if it is a new neighbour."""
        new = src not in self.neighbours
        self.neighbours[src] = t
        if new:
            self._sorted = None
        return new

    def expire(self, t: float) -> list[int]:
        """Drop neighbours silent for longer than the timeout; returns the dropped ids."""
        gone = [n for n, last in self.neighbours.items() if t - last > self.timeout]
        for n in gone:
            del self.neighbours[n]
        if gone:
            self._sorted = None
        return gone

    def first_time(self, key: tuple[int, int]) -> bool:
        """Flood de-duplication: True (and remember the key) the first time a key is seen."""
        if key in self.seen:
            return False
        self.seen.add(key)
        return True

    def relay_targets(self, came_from: int | None = None) -> list[int]:
        """Neighbours a flooded message is passed on to, in id order."""
        if self._sorted is None:
            self._sorted = sorted(self.neighbours)
        if came_from is None or came_from not in self.neighbours:
            return list(self._sorted)
        return [n for n in self._sorted if n != came_from]


@dataclass
class Counters:
    messages: int = 0
    bytes: int = 0
    lost: int = 0
    by_kind: dict[str, list[int]] = field(default_factory=dict)  # kind -> [messages, bytes]

    def count(self, msg: Sized, copies: int = 1, delivered: int = 1) -> None:
        size = int(msg.nbytes) * copies
        self.messages += copies
        self.bytes += size
        self.lost += copies - delivered
        row = self.by_kind.get(msg.kind)
        if row is None:
            row = self.by_kind[msg.kind] = [0, 0]
        row[0] += copies
        row[1] += size


class DiscNetwork:
    """Simulated radio: who is in range now, a FIFO of deliveries, and traffic counters."""

    def __init__(self, n: int, range_m: float) -> None:
        if not range_m > 0:
            raise InputError(f"--comm-range must be a positive number of metres, got {range_m}")
        self.n = n
        self.range_m = float(range_m)
        self.in_range = np.zeros((n, n), dtype=bool)
        self.queue: list[tuple[int, int, Any]] = []
        self._head = 0
        self.sent = [Counters() for _ in range(n)]

    def move(self, positions_m: np.ndarray) -> None:
        """Recompute the disc links from positions (metres, shape (n, 2))."""
        p = np.asarray(positions_m, dtype=np.float64)
        d2 = ((p[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)
        self.in_range = d2 <= self.range_m**2
        np.fill_diagonal(self.in_range, False)

    def broadcast(self, src: int, msg: Sized) -> None:
        """A UDP-style broadcast: one transmission, heard by everyone in range."""
        self.sent[src].count(msg)
        for dst in np.nonzero(self.in_range[src])[0]:
            self.queue.append((src, int(dst), msg))

    def unicast(self, src: int, dst: int, msg: Sized) -> bool:
        """One message over a neighbour link; lost if the peer is out of range now."""
        ok = bool(self.in_range[src, dst])
        self.sent[src].count(msg, 1, int(ok))
        if ok:
            self.queue.append((src, dst, msg))
        return ok

    def unicast_many(self, src: int, dsts: list[int], msg: Sized) -> None:
        """The same message to several neighbours (one send each, as over PUSH sockets)."""
        row = self.in_range[src]
        ok = [d for d in dsts if row[d]]
        self.sent[src].count(msg, len(dsts), len(ok))
        self.queue.extend((src, d, msg) for d in ok)

    def drain(self) -> Iterator[tuple[int, int, Any]]:
        """Deliveries in FIFO order, including those queued while draining (relays)."""
        q = self.queue
        while self._head < len(q):
            item = q[self._head]
            self._head += 1
            yield item
        q.clear()
        self._head = 0

    def totals(self) -> dict[str, Any]:
        """Traffic of the run; ``aodv_*`` is the routing control (RREQ, RREP, RERR), which
        ``messages_sent`` / ``bytes_sent`` include too."""
        by_kind: dict[str, list[int]] = {}
        for c in self.sent:
            for k, (m, b) in c.by_kind.items():
                row = by_kind.setdefault(k, [0, 0])
                row[0] += m
                row[1] += b
        control = [by_kind[k] for k in AODV_KINDS if k in by_kind]
        return {
            "messages_sent": sum(c.messages for c in self.sent),
            "bytes_sent": sum(c.bytes for c in self.sent),
            "messages_lost": sum(c.lost for c in self.sent),
            "aodv_messages": sum(m for m, _ in control),
            "aodv_bytes": sum(b for _, b in control),
            "by_kind": {k: {"messages": m, "bytes": b} for k, (m, b) in sorted(by_kind.items())},
        }
