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

Scale (issue 14): a relay to every neighbour is one :class:`Fanout` entry, not one per
neighbour; the radio queues it as one batch (a bitmask of receivers) and counts its copies
arithmetically, and :class:`FloodLedger` — a simulator-side index of which node has seen which
flood key and which nodes know which sender — lets the simulator drop, a batch at a time, the
copies a receiver would drop itself without effect. A flood therefore costs the simulator
O(nodes) per scan rather than O(nodes × neighbours), with every copy still counted. Links are
found through a k-d tree (:class:`scipy.spatial.cKDTree`) once the team is large, the exact
distance test deciding as before.

Unicasts to robots beyond direct range are routed by AODV (:mod:`swarmex.comm.aodv`), whose
hellos are these heartbeats; :meth:`DiscNetwork.totals` counts its control messages
(RREQ, RREP, RERR) separately as ``aodv_messages`` / ``aodv_bytes``.

Timing constants the thesis leaves open (spec §6.9) are parameters: heartbeat period 1 s
(the thesis's), neighbour timeout 3 heartbeat periods (three missed heartbeats, AODV's
``ALLOWED_HELLO_LOSS`` is 2 plus the current one).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol, overload

import numpy as np

from swarmex.comm.aodv import CONTROL_KINDS as AODV_KINDS
from swarmex.errors import InputError


class Sized(Protocol):
    """A message as the radio counts it (read-only: a class constant or a property will do)."""

    @property
    def kind(self) -> str: ...

    @property
    def nbytes(self) -> int: ...


def bits(mask: int) -> Iterator[int]:
    """The set bits of ``mask``, lowest first (node ids of a bitmask, in id order)."""
    while mask:
        low = mask & -mask
        yield low.bit_length() - 1
        mask ^= low


class Fanout(Sequence[int]):
    """One message to several neighbours (a flood relay, a ``GOAL``): the ids in order.

    A plain sequence to the networked runtime (it sends one frame per id); to the simulated
    radio, a bitmask (:attr:`mask`) it queues and counts as one batch. Built by
    :meth:`MeshNode.fanout` from the node's cached neighbour list, so making one costs
    O(1) whatever the number of neighbours.
    """

    __slots__ = ("_but", "_ids", "_mask", "_n")

    def __init__(self, ids: tuple[int, ...], mask: int = -1, but: int | None = None) -> None:
        self._ids = ids
        self._but = but if but is not None and but in ids else None
        self._mask = mask  # -1: not known yet
        self._n = len(ids) - (self._but is not None)

    def __len__(self) -> int:
        return self._n

    @overload
    def __getitem__(self, i: int) -> int: ...

    @overload
    def __getitem__(self, i: slice) -> Sequence[int]: ...

    def __getitem__(self, i: int | slice) -> int | Sequence[int]:
        return self.ids()[i]

    def __iter__(self) -> Iterator[int]:
        but = self._but
        return iter(self._ids) if but is None else (i for i in self._ids if i != but)

    def ids(self) -> tuple[int, ...]:
        if self._but is None:
            return self._ids
        return tuple(i for i in self._ids if i != self._but)

    @property
    def mask(self) -> int:
        """The receivers as a bitmask (bit i = node i; ids must be non-negative)."""
        if self._mask < 0:
            self._mask = sum(1 << i for i in self._ids)
        return self._mask & ~(1 << self._but) if self._but is not None else self._mask

    def __repr__(self) -> str:
        return f"Fanout({list(self)})"


@dataclass
class FloodLedger:
    """Who has seen which flood key, and who knows which sender: one simulator's index.

    Every :class:`MeshNode` of a simulated team reports to it (``MeshNode.ledger``); nodes
    never read it. The simulator uses it to skip, for a whole batch of copies at once, the
    copies a receiver would drop without effect (all keys seen, sender already a neighbour).
    """

    holders: dict[tuple[int, int], int] = field(default_factory=dict)  # key -> node bitmask
    listeners: dict[int, int] = field(default_factory=dict)  # src -> nodes that list it

    def have_all(self, keys: Iterator[tuple[int, int]]) -> int:
        """Bitmask of the nodes that have seen every one of ``keys``."""
        out = -1
        get = self.holders.get
        for k in keys:
            out &= get(k, 0)
            if not out:
                return 0
        return out if out >= 0 else 0


class LedgerSeen:
    """A node's seen flood keys kept as its bit in a :class:`FloodLedger`'s ``holders``.

    In a simulated team of n nodes that all see every key, n sets of every key cost n
    entries per key, cold in memory at every first sight; the ledger keeps one bitmask per
    key already. A node reads and adds its keys there instead (:meth:`MeshNode.use_ledger`),
    through the same ``in`` / ``add`` a set offers."""

    __slots__ = ("bit", "holders")

    def __init__(self, ledger: FloodLedger, node: int) -> None:
        self.holders = ledger.holders
        self.bit = 1 << node

    def __contains__(self, key: object) -> bool:
        return bool(self.holders.get(key, 0) & self.bit)  # type: ignore[call-overload]

    def add(self, key: tuple[int, int]) -> None:
        h = self.holders
        h[key] = h.get(key, 0) | self.bit

    def __iter__(self) -> Iterator[tuple[int, int]]:
        bit = self.bit
        return (k for k, m in self.holders.items() if m & bit)

    def __len__(self) -> int:
        return sum(1 for _ in self)


@dataclass
class MeshNode:
    """One robot's mesh protocol state (time in any unit, used consistently)."""

    id: int
    heartbeat_period: float = 10.0
    timeout: float = 30.0
    phase: float = 0.0  # first heartbeat time
    neighbours: dict[int, float] = field(default_factory=dict)  # id -> last heard
    seen: set[tuple[int, int]] | LedgerSeen = field(default_factory=set)
    ledger: FloodLedger | None = field(default=None, repr=False, compare=False)
    _sorted: tuple[int, ...] | None = field(default=None, repr=False)
    _mask: int = field(default=-1, repr=False)

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
            self._changed()
            if self.ledger is not None:
                lst = self.ledger.listeners
                lst[src] = lst.get(src, 0) | (1 << self.id)
        return new

    def _changed(self) -> None:
        self._sorted = None
        self._mask = -1

    def expire(self, t: float) -> list[int]:
        """Drop neighbours silent for longer than the timeout; returns the dropped ids."""
        gone = [n for n, last in self.neighbours.items() if t - last > self.timeout]
        for n in gone:
            del self.neighbours[n]
            if self.ledger is not None:
                self.ledger.listeners[n] &= ~(1 << self.id)
        if gone:
            self._changed()
        return gone

    def use_ledger(self, ledger: FloodLedger) -> None:
        """Report to ``ledger`` and keep the seen keys there (:class:`LedgerSeen`): a
        simulator's team, whose ledger indexes every node's keys anyway."""
        self.ledger = ledger
        h = ledger.holders
        bit = 1 << self.id
        for key in self.seen:
            h[key] = h.get(key, 0) | bit
        self.seen = LedgerSeen(ledger, self.id)

    def first_time(self, key: tuple[int, int]) -> bool:
        """Flood de-duplication: True (and remember the key) the first time a key is seen."""
        seen = self.seen
        if type(seen) is LedgerSeen:
            h = seen.holders
            m = h.get(key, 0)
            if m & seen.bit:
                return False
            h[key] = m | seen.bit
            return True
        if key in seen:
            return False
        seen.add(key)
        if self.ledger is not None:
            h = self.ledger.holders
            h[key] = h.get(key, 0) | (1 << self.id)
        return True

    def _ids(self) -> tuple[int, ...]:
        if self._sorted is None:
            self._sorted = tuple(sorted(self.neighbours))
        return self._sorted

    def relay_targets(self, came_from: int | None = None) -> list[int]:
        """Neighbours a flooded message is passed on to, in id order."""
        ids = self._ids()
        if came_from is None or came_from not in self.neighbours:
            return list(ids)
        return [n for n in ids if n != came_from]

    def fanout(self, came_from: int | None = None) -> Fanout:
        """:meth:`relay_targets` as one :class:`Fanout` (no per-neighbour work)."""
        ids = self._ids()
        if self._mask < 0 and self.ledger is not None:  # only a simulator needs the mask
            self._mask = sum(1 << i for i in ids)
        return Fanout(ids, self._mask, came_from)

    def neighbour_mask(self) -> int:
        """The neighbour table as a bitmask (bit i = node i), cached until it changes: what
        a simulator's flood needs of a relay, without building a :class:`Fanout`."""
        if self._mask < 0:
            self._mask = sum(1 << i for i in self._ids())
        return self._mask


@dataclass
class Counters:
    messages: int = 0
    bytes: int = 0
    lost: int = 0
    by_kind: dict[str, list[int]] = field(default_factory=dict)  # kind -> [messages, bytes]

    def count(self, msg: Sized, copies: int = 1, delivered: int = 1) -> None:
        self.count_sized(msg.kind, int(msg.nbytes), copies, delivered)

    def count_sized(self, kind: str, nbytes: int, copies: int = 1, delivered: int = 1) -> None:
        """:meth:`count` with the message's kind and size given (a caller that knows them
        without sizing the message object)."""
        size = nbytes * copies
        self.messages += copies
        self.bytes += size
        self.lost += copies - delivered
        row = self.by_kind.get(kind)
        if row is None:
            row = self.by_kind[kind] = [0, 0]
        row[0] += copies
        row[1] += size


class Batch:
    """Copies of one message queued together: the receivers as a bitmask (id order)."""

    __slots__ = ("mask",)

    def __init__(self, mask: int) -> None:
        self.mask = mask


KDTREE_FROM = 256  # team size from which links are found with a k-d tree


class DiscNetwork:
    """Simulated radio: who is in range now, a FIFO of deliveries, and traffic counters."""

    def __init__(self, n: int, range_m: float) -> None:
        if not range_m > 0:
            raise InputError(f"--comm-range must be a positive number of metres, got {range_m}")
        self.n = n
        self.range_m = float(range_m)
        self.in_range = np.zeros((n, n), dtype=bool)
        self.queue: list[tuple[int, Any, Any]] = []  # (src, dst id or Batch, message)
        self._head = 0
        self.sent = [Counters() for _ in range(n)]
        self._rows: list[int | None] = [0] * n  # in_range rows as bitmasks, None: stale

    def move(self, positions_m: np.ndarray) -> None:
        """Recompute the disc links from positions (metres, shape (n, 2)).

        A pair is linked when its squared distance is at most the squared range, computed
        the same way whichever route finds the candidates: all pairs for a small team, the
        pairs a k-d tree returns within a hair more than the range for a large one.
        """
        p = np.asarray(positions_m, dtype=np.float64)
        n = p.shape[0]
        if n < KDTREE_FROM:
            d2 = ((p[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)
            self.in_range = d2 <= self.range_m * self.range_m  # inf, not OverflowError, if huge
            np.fill_diagonal(self.in_range, False)
        else:
            from scipy.spatial import cKDTree  # only large teams pay for the import

            pairs = cKDTree(p).query_pairs(self.range_m * (1 + 1e-9), output_type="ndarray")
            i, j = pairs[:, 0], pairs[:, 1]
            ok = ((p[i] - p[j]) ** 2).sum(axis=1) <= self.range_m * self.range_m
            links = np.zeros((n, n), dtype=bool)
            links[i[ok], j[ok]] = True
            links[j[ok], i[ok]] = True
            self.in_range = links
        self._rows = [None] * n

    def row_mask(self, src: int) -> int:
        """The nodes in range of ``src`` as a bitmask."""
        m = self._rows[src]
        if m is None:
            row = np.packbits(self.in_range[src], bitorder="little").tobytes()
            m = self._rows[src] = int.from_bytes(row, "little")
        return m

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

    def unicast_many(self, src: int, dsts: Sequence[int], msg: Sized) -> None:
        """The same message to several neighbours (one send each, as over PUSH sockets).

        A :class:`Fanout` is queued as one :class:`Batch` and counted with bit operations."""
        if isinstance(dsts, Fanout):
            self.send_mask(src, dsts.mask, msg, msg.kind, int(msg.nbytes))
            return
        row = self.in_range[src]
        good = [d for d in dsts if row[d]]
        self.sent[src].count(msg, len(dsts), len(good))
        self.queue.extend((src, d, msg) for d in good)

    def send_mask(self, src: int, mask: int, msg: Any, kind: str, nbytes: int) -> None:
        """One message of ``kind`` and ``nbytes`` from ``src`` to each node of ``mask``: one
        send counted per copy, queued as one :class:`Batch` of those in range."""
        ok = mask & self.row_mask(src)
        self.sent[src].count_sized(kind, nbytes, mask.bit_count(), ok.bit_count())
        if ok:
            self.queue.append((src, Batch(ok), msg))

    def drain_batches(self) -> Iterator[tuple[int, Any, Any]]:
        """Queue entries in FIFO order, including those queued while draining (relays):
        ``(src, dst, msg)`` with ``dst`` a node id or a :class:`Batch` of them."""
        q = self.queue
        while self._head < len(q):
            item = q[self._head]
            self._head += 1
            yield item
        q.clear()
        self._head = 0

    def drain(self) -> Iterator[tuple[int, int, Any]]:
        """Deliveries in FIFO order, one per copy (batches expanded in id order)."""
        for src, dst, msg in self.drain_batches():
            if type(dst) is Batch:
                for d in bits(dst.mask):
                    yield src, d, msg
            else:
                yield src, dst, msg

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
