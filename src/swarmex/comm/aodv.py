"""AODV route discovery for the exploration mesh (seed 003 §1.4.3, §3.3.5; RFC 3561).

The thesis routes unicast messages with AODV (Perkins et al.): "If the routing table does
not contain the route to the necessary destination, the thread starts the route discovery
by AODV routing protocol. The message is stored in the queue until it finds a route to the
destination or the message lifetime expires." :class:`AodvNode` is that protocol state for
one node, payload-agnostic and clock-agnostic (times in any unit, here 100 ms ticks), so the
simulator and the process mesh (:mod:`swarmex.net.routing`) drive the same code:

* **route table** — one :class:`Route` per destination with the seed's fields: destination
  sequence number (``-1`` = unknown), state (valid/invalid), hop count, next hop, precursors
  (neighbours actively using the route) and lifetime;
* **RREQ** ``(orig, rreq_id)``-unique, with originator and destination sequence numbers and
  a hop count, sent "to all its neighbours" (every neighbour-table entry, as the thesis's
  broadcast queue does) and relayed once per node; each relay records a *reverse route* to
  the originator;
* **RREP** from the destination (or an intermediate node holding a valid route whose
  destination sequence number is known and at least the RREQ's) unicast back along the
  reverse route; each hop records the *forward route* and the precursors;
* **RERR** on a link break: the thesis's "RREP packet with infinite metric" sent "to a set
  of nodes that are taken from the route in the neighbour's routing table" — the precursors
  of every route that used the broken link. Standard AODV names it RERR, and so do we;
* **hello** = the mesh's heartbeats (thesis §3.3.5: "the routing table [is updated] based on
  these heartbeating messages"): a heartbeat gives a valid one-hop route, a neighbour
  timeout breaks the link;
* **unicast queue** — a payload with no valid route waits, stamped with its expiry, while
  discovery runs; a failed discovery is retried with binary exponential back-off (the
  seed's §1.4.2 rule for repeated requests to one destination) until a route appears or the
  lifetime passes, when the payload is dropped and counted.

Readings of what the seed leaves open (recorded in ``docs/exploration.md`` too):

* A payload for a **direct neighbour** goes as itself, without an envelope: the transmitter
  is its origin and the receiver its destination. Only a multi-hop payload travels in a
  :class:`Routed` envelope (origin, destination, expiry), one copy per hop.
* **Link-layer feedback.** A send to a next hop that has left the radio range fails (the
  thesis's nanomsg send timeout); the node then treats the link as broken (RERR to the
  precursors) and puts the payload back in *its own* unicast queue with its original expiry,
  starting a new discovery (RFC 3561's local repair, applied at any hop). So a payload is
  delivered once, or dropped at its expiry by whichever node holds it — never duplicated.
* Heartbeats carry no sequence number, so one-hop routes learnt from them have an unknown
  destination sequence number and intermediate nodes never answer for them: the destination
  itself answers (it is then one hop from the last relay anyway).
* No expanding-ring search and no RREQ jitter: delivery in the simulator is instantaneous,
  so a discovery takes no simulated time and the result is deterministic.
* On the wire (the process mesh, :mod:`swarmex.net.mesh`) every message is its ``to_dict()``
  and :func:`from_dict` rebuilds it; a :class:`Routed` envelope's ``expires`` is then
  compared with the clock of each process it crosses. Those clocks all start at the same GO
  and tick at the same period, so they differ by a few ticks — small against the 10 s
  lifetime of a unicast.
* Constants (spec §6.9; the seed gives none): an active route lives 3 s (RFC 3561's
  ACTIVE_ROUTE_TIMEOUT), refreshed by use; the destination's own RREP grants 6 s (RFC's
  MY_ROUTE_TIMEOUT); a reverse route 3 s (slightly more than RFC's 2.8 s NET_TRAVERSAL_TIME,
  the seed's "slightly greater than the maximum time required for a packet to pass through
  the entire network"); the first retry after one heartbeat period (no new neighbour, hence
  no new route, can appear sooner), then doubling.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, ClassVar

from swarmex.comm.message import PackedMessage, once, packed_size

Out = list[tuple[int, Any]]  # (neighbour, message) transmissions


class AodvMessage(PackedMessage):
    """AODV control message: ``kind``, ``to_dict()`` (msgpack-ready) and ``nbytes``."""

    src: int  # the transmitting neighbour (one hop)


@dataclass(eq=False)
class Rreq(AodvMessage):
    kind: ClassVar[str] = "RREQ"
    src: int
    orig: int
    orig_seq: int
    rreq_id: int
    dest: int
    dest_seq: int  # -1: unknown
    hops: int

    def body(self) -> dict[str, Any]:
        return {
            "src": self.src,
            "orig": self.orig,
            "oseq": self.orig_seq,
            "id": self.rreq_id,
            "dest": self.dest,
            "dseq": self.dest_seq,
            "hops": self.hops,
        }


@dataclass(eq=False)
class Rrep(AodvMessage):
    kind: ClassVar[str] = "RREP"
    src: int
    orig: int  # the RREQ's originator, whom this reply travels to
    dest: int
    dest_seq: int
    hops: int  # from the transmitter to ``dest``
    lifetime: float

    def body(self) -> dict[str, Any]:
        return {
            "src": self.src,
            "orig": self.orig,
            "dest": self.dest,
            "dseq": self.dest_seq,
            "hops": self.hops,
            "life": self.lifetime,
        }


@dataclass(eq=False)
class Rerr(AodvMessage):
    kind: ClassVar[str] = "RERR"
    src: int
    unreachable: tuple[tuple[int, int], ...]  # (destination, its sequence number)

    def body(self) -> dict[str, Any]:
        return {"src": self.src, "dests": [list(u) for u in self.unreachable]}


@dataclass(eq=False)
class Routed:
    """A multi-hop unicast: the payload plus origin, destination and expiry.

    Its ``kind`` is the payload's, so traffic counters book the hops of a routed ``MAP``
    under ``MAP`` (with the envelope's bytes): routing *control* is what RREQ/RREP/RERR count.
    """

    src: int
    orig: int
    dest: int
    expires: float
    payload: Any
    hops: int = 1  # hops travelled, this one included (a guard against loops)

    @property
    def kind(self) -> str:
        return str(self.payload.kind)

    def _with(self, payload: Any) -> dict[str, Any]:
        return {
            "type": "DATA",
            "src": self.src,
            "orig": self.orig,
            "dest": self.dest,
            "exp": self.expires,
            "hops": self.hops,
            "payload": payload,
        }

    def to_dict(self) -> dict[str, Any]:
        return self._with(self.payload.to_dict())

    @once
    def nbytes(self) -> int:
        # the envelope around a placeholder (None packs to one byte), plus the payload's size
        return packed_size(self._with(None)) - 1 + int(self.payload.nbytes)


CONTROL_KINDS = ("RREQ", "RREP", "RERR")  # routing control, counted apart by DiscNetwork
DATA_KIND = "DATA"  # the wire type of a :class:`Routed` envelope


def _number(v: Any) -> float:
    """A time as sent: an int stays an int, so the rebuilt message packs to the same bytes
    (and ``nbytes``, which the traffic counters add up, is the sender's)."""
    return v if isinstance(v, int) and not isinstance(v, bool) else float(v)


def from_dict(d: dict[str, Any], payload: Callable[[dict[str, Any]], Any]) -> AodvMessage | Routed:
    """Rebuild an AODV message (or a routed envelope, its payload by ``payload``) from its
    ``to_dict()`` form; KeyError / TypeError / ValueError on a malformed one (the caller,
    a wire decoder, has checked the field types already)."""
    kind = d["type"]
    src = int(d["src"])
    if kind == "RREQ":
        return Rreq(src, int(d["orig"]), int(d["oseq"]), int(d["id"]), int(d["dest"]),
                    int(d["dseq"]), int(d["hops"]))
    if kind == "RREP":
        return Rrep(src, int(d["orig"]), int(d["dest"]), int(d["dseq"]), int(d["hops"]),
                    _number(d["life"]))
    if kind == "RERR":
        return Rerr(src, tuple((int(a), int(b)) for a, b in d["dests"]))
    if kind == DATA_KIND:
        return Routed(src, int(d["orig"]), int(d["dest"]), _number(d["exp"]),
                      payload(d["payload"]), int(d["hops"]))
    raise ValueError(f"not an AODV message type: {kind!r:.20}")
MAX_HOPS = 64  # a routed payload is dropped after this many hops (RFC 3561's IP TTL role)


@dataclass
class Route:
    dest: int
    seq: int  # -1: unknown
    valid: bool
    hops: int
    next_hop: int
    expires: float
    precursors: set[int] = field(default_factory=set)


@dataclass
class Pending:
    dest: int
    payload: Any
    expires: float
    orig: int
    hops: int = 0  # hops already travelled


@dataclass
class AodvStats:
    sent: int = 0  # payloads handed to AODV by this node's application
    delivered: int = 0  # payloads that reached this node as their destination
    delivered_multihop: int = 0  # ... over two or more hops
    expired: int = 0  # payloads dropped here at their expiry (no route in time)
    dropped_hops: int = 0  # payloads dropped here after MAX_HOPS hops (a routing loop)
    discoveries: int = 0  # RREQs originated (first tries and retries)
    link_breaks: int = 0


@dataclass(frozen=True)
class AodvTiming:
    """Protocol constants in the caller's time unit (defaults: 100 ms ticks)."""

    active_route: float = 30.0  # 3 s
    my_route: float = 60.0  # 6 s, granted by the destination's RREP
    reverse_route: float = 30.0  # 3 s > NET_TRAVERSAL_TIME
    hello_route: float = 30.0  # the neighbour timeout
    retry: float = 10.0  # first RREQ retry: one heartbeat period; then doubling

    @classmethod
    def for_mesh(cls, heartbeat_period: float, neighbour_timeout: float) -> AodvTiming:
        """The constants tied to the mesh's heartbeats (every member of a mesh uses these):
        routes live one neighbour timeout, the destination's own RREP grants two, and a
        failed discovery is first retried after one heartbeat period."""
        return cls(
            active_route=neighbour_timeout,
            my_route=2 * neighbour_timeout,
            reverse_route=neighbour_timeout,
            hello_route=neighbour_timeout,
            retry=heartbeat_period,
        )


class AodvNode:
    """One node's AODV state. Every call returns the transmissions to make, in order.

    ``neighbours(but)`` lists the current neighbour-table entries (id order) other than
    ``but``; the mesh's heartbeats keep that table, and :meth:`hello` / :meth:`link_broken`
    tell AODV about its changes.
    """

    def __init__(
        self,
        nid: int,
        neighbours: Callable[[int | None], list[int]],
        timing: AodvTiming | None = None,
    ) -> None:
        self.id = nid
        self.neighbours = neighbours
        self.timing = timing or AodvTiming()
        self.seq = 0
        self.rreq_id = 0
        self.routes: dict[int, Route] = {}
        self.seen: dict[tuple[int, int], float] = {}  # (orig, rreq_id) -> forget after
        self.queue: list[Pending] = []
        self.retry_at: dict[int, tuple[float, int]] = {}  # dest -> (next RREQ time, tries)
        self.stats = AodvStats()

    # ------------------------------------------------------------------ routes
    def route(self, dest: int, t: float) -> Route | None:
        """The valid, unexpired route to ``dest``, or None (an expired one is invalidated)."""
        r = self.routes.get(dest)
        if r is None or not r.valid:
            return None
        if r.expires < t:
            r.valid = False
            return None
        return r

    def _update(self, dest: int, seq: int, hops: int, nxt: int, expires: float) -> bool:
        """RFC 3561 §6.2: take the new route if fresher, or as fresh and shorter, or if the
        old one is invalid or of unknown freshness. True if the table changed."""
        r = self.routes.get(dest)
        if r is None:
            self.routes[dest] = Route(dest, seq, True, hops, nxt, expires)
            return True
        better = (
            not r.valid
            or r.seq < 0
            or (seq >= 0 and seq > r.seq)
            or (seq == r.seq and hops < r.hops)
        )
        if better:
            same_hop = r.valid and r.next_hop == nxt
            r.seq = max(r.seq, seq)
            r.valid, r.hops, r.next_hop = True, hops, nxt
            r.expires = max(r.expires, expires) if same_hop else expires
            return True
        if r.next_hop == nxt and r.hops == hops:
            r.expires = max(r.expires, expires)
        return False

    # --------------------------------------------------------------- sending
    def send(self, dest: int, payload: Any, t: float, lifetime: float) -> Out:
        """Application unicast: forward now if a route exists, else queue and discover."""
        self.stats.sent += 1
        return self._forward(self.id, dest, payload, t + lifetime, t)

    def _forward(
        self, orig: int, dest: int, payload: Any, expires: float, t: float, hops: int = 0
    ) -> Out:
        r = self.route(dest, t)
        if r is None:
            self.queue.append(Pending(dest, payload, expires, orig, hops))
            return self._discover(dest, t)
        return self._transmit(r, Pending(dest, payload, expires, orig, hops), t)

    def _transmit(self, r: Route, p: Pending, t: float) -> Out:
        """One hop of ``p`` along route ``r``; using a route keeps it (and the link to its
        next hop) alive for another active-route time (RFC 3561 §6.2)."""
        r.expires = max(r.expires, t + self.timing.active_route)
        nh = self.routes.get(r.next_hop)
        if nh is not None and nh.valid:
            nh.expires = max(nh.expires, t + self.timing.active_route)
        if r.hops == 1 and p.orig == self.id:
            return [(p.dest, p.payload)]  # a direct neighbour: no envelope needed
        env = Routed(self.id, p.orig, p.dest, p.expires, p.payload, p.hops + 1)
        return [(r.next_hop, env)]

    def _discover(self, dest: int, t: float) -> Out:
        due = self.retry_at.get(dest)
        if due is not None and t < due[0]:
            return []  # a discovery is under way; the queue waits for its RREP
        tries = 0 if due is None else due[1] + 1
        self.retry_at[dest] = (t + self.timing.retry * (2**tries), tries)
        self.seq += 1
        self.rreq_id += 1
        self.stats.discoveries += 1
        self.seen[(self.id, self.rreq_id)] = t + self.timing.reverse_route
        old = self.routes.get(dest)
        msg = Rreq(
            self.id, self.id, self.seq, self.rreq_id, dest, -1 if old is None else old.seq, 0
        )
        return [(n, msg) for n in self.neighbours(None)]

    def _flush(self, t: float) -> Out:
        """Send every queued payload that now has a route."""
        if not self.queue:
            return []
        out: Out = []
        keep: list[Pending] = []
        routes = self.routes
        for p in self.queue:  # route() inlined: a flood's every RREQ flushes every queue
            r = routes.get(p.dest)
            if r is None or not r.valid:
                keep.append(p)
            elif r.expires < t:
                r.valid = False
                keep.append(p)
            else:
                self.retry_at.pop(p.dest, None)
                out.extend(self._transmit(r, p, t))
        self.queue = keep
        return out

    # ------------------------------------------------------------- receiving
    def hello(self, nbr: int, t: float) -> Out:
        """A heartbeat from ``nbr``: a valid one-hop route (hello message)."""
        return self._flush(t) if self._heard(nbr, t) else []

    def _heard(self, nbr: int, t: float) -> bool:
        """Any AODV message proves the one-hop link to its transmitter (RFC 3561 §6.5).
        False if it only refreshed the valid one-hop route already held; else the table was
        offered the route, and queued payloads may now have one."""
        r = self.routes.get(nbr)
        if r is not None and r.valid and r.hops == 1 and r.next_hop == nbr:
            r.expires = max(r.expires, t + self.timing.hello_route)
            return False
        self._update(nbr, -1 if r is None else r.seq, 1, nbr, t + self.timing.hello_route)
        return True

    def receive(self, src: int, msg: Any, t: float) -> tuple[Out, list[tuple[int, Any]]]:
        """An AODV message from neighbour ``src``: (transmissions, delivered payloads as
        ``(origin, payload)``)."""
        self._heard(src, t)
        if isinstance(msg, Rreq):
            out = self._on_rreq(src, msg, t)
        elif isinstance(msg, Rrep):
            out = self._on_rrep(src, msg, t)
        elif isinstance(msg, Rerr):
            out = self._on_rerr(src, msg, t)
        elif isinstance(msg, Routed):
            if msg.dest == self.id:
                self.stats.delivered += 1
                self.stats.delivered_multihop += 1
                return self._flush(t), [(msg.orig, msg.payload)]
            if msg.expires < t:
                self.stats.expired += 1
                return [], []
            if msg.hops >= MAX_HOPS:
                self.stats.dropped_hops += 1
                return [], []
            out = self._forward(msg.orig, msg.dest, msg.payload, msg.expires, t, msg.hops)
        else:
            raise TypeError(f"not an AODV message: {type(msg).__name__}")
        return out + self._flush(t), []

    def delivered_direct(self) -> None:
        """Count a payload that came straight from its origin (one hop, no envelope)."""
        self.stats.delivered += 1

    def _on_rreq(self, src: int, m: Rreq, t: float) -> Out:
        key = (m.orig, m.rreq_id)
        if key in self.seen or m.orig == self.id:
            return []
        self.seen[key] = t + self.timing.reverse_route
        hops = m.hops + 1
        self._update(m.orig, m.orig_seq, hops, src, t + self.timing.reverse_route)
        if m.dest == self.id:
            self.seq = max(self.seq, m.dest_seq)
            back = self.routes[m.orig].next_hop
            return [(back, Rrep(self.id, m.orig, self.id, self.seq, 0, self.timing.my_route))]
        r = self.route(m.dest, t)
        if r is not None and r.seq >= 0 and r.seq >= m.dest_seq:
            back_route = self.routes[m.orig]
            r.precursors.add(back_route.next_hop)
            back_route.precursors.add(r.next_hop)
            return [
                (back_route.next_hop, Rrep(self.id, m.orig, m.dest, r.seq, r.hops, r.expires - t))
            ]
        known = self.routes.get(m.dest)
        dseq = m.dest_seq if known is None else max(m.dest_seq, known.seq)
        fwd = Rreq(self.id, m.orig, m.orig_seq, m.rreq_id, m.dest, dseq, hops)
        return [(n, fwd) for n in self.neighbours(src)]

    def _on_rrep(self, src: int, m: Rrep, t: float) -> Out:
        hops = m.hops + 1
        self._update(m.dest, m.dest_seq, hops, src, t + m.lifetime)
        if m.orig == self.id:
            return []  # the caller flushes the queue onto the new route
        back = self.route(m.orig, t)
        if back is None:
            return []  # the reverse route is gone: the originator will retry
        fwd = self.routes[m.dest]
        fwd.precursors.add(back.next_hop)
        back.precursors.add(fwd.next_hop)
        return [(back.next_hop, Rrep(self.id, m.orig, m.dest, m.dest_seq, hops, m.lifetime))]

    def _on_rerr(self, src: int, m: Rerr, t: float) -> Out:
        lost, tell = self._invalidate(
            (r, max(r.seq, seq))
            for dest, seq in m.unreachable
            if (r := self.routes.get(dest)) is not None and r.valid and r.next_hop == src
        )
        return self._rerr(lost, tell)

    def _invalidate(
        self, broken: Iterable[tuple[Route, int]]
    ) -> tuple[list[tuple[int, int]], set[int]]:
        """Mark each route broken with its new destination sequence number: the
        ``(destination, seq)`` pairs lost and the precursors to tell (taken off the routes)."""
        lost: list[tuple[int, int]] = []
        tell: set[int] = set()
        for r, seq in broken:
            r.valid = False
            r.seq = seq
            lost.append((r.dest, seq))
            tell |= r.precursors
            r.precursors.clear()
        return lost, tell

    def _rerr(self, lost: list[tuple[int, int]], tell: set[int]) -> Out:
        """One RERR listing ``lost``, to each of ``tell`` (id order)."""
        if not lost or not tell:
            return []
        msg = Rerr(self.id, tuple(lost))
        return [(n, msg) for n in sorted(tell)]

    # ----------------------------------------------------------- maintenance
    def link_broken(self, nbr: int, t: float) -> Out:
        """The link to ``nbr`` is gone (heartbeat timeout or a failed send): invalidate
        every route through it and tell their precursors (RERR, the thesis's "RREP with
        infinite metric")."""
        lost, tell = self._invalidate(
            # RFC 3561 §6.11: a broken route's (known) sequence number is raised
            (r, r.seq + 1 if r.seq >= 0 else r.seq)
            for r in (self.routes[d] for d in sorted(self.routes))
            if r.valid and r.next_hop == nbr
        )
        if not lost:
            return []
        self.stats.link_breaks += 1
        tell.discard(nbr)
        return self._rerr(lost, tell)

    def send_failed(self, nbr: int, msg: Any, t: float, lifetime: float) -> Out:
        """A transmission to ``nbr`` could not be delivered (out of range): the link is
        broken; a payload goes back into this node's queue with its expiry (``lifetime``
        from now for a direct payload, which carries none) and a new discovery starts
        (local repair); a failed RREP or RERR is dropped (the originator retries)."""
        out = self.link_broken(nbr, t)
        if isinstance(msg, Routed):
            self.queue.append(Pending(msg.dest, msg.payload, msg.expires, msg.orig, msg.hops - 1))
            out += self._discover(msg.dest, t)
        elif not isinstance(msg, AodvMessage):  # a direct payload sent without envelope
            self.queue.append(Pending(nbr, msg, t + lifetime, self.id))
            out += self._discover(nbr, t)
        return out

    def tick(self, t: float) -> Out:
        """Drop expired payloads (counted), retry discoveries that are due, forget old
        RREQ ids. Call once per time step."""
        out: Out = []
        if self.queue:
            keep = []
            for p in self.queue:
                if p.expires < t:
                    self.stats.expired += 1
                else:
                    keep.append(p)
            self.queue = keep
            out += self._flush(t)
            for dest in sorted({p.dest for p in self.queue}):
                out += self._discover(dest, t)
        if not self.queue and self.retry_at:
            self.retry_at.clear()
        if self.seen and len(self.seen) > 64 and min(self.seen.values()) < t:
            self.seen = {k: v for k, v in self.seen.items() if v >= t}  # (rebuilt only if
            # something expired: the same table, without a dict per tick in a large team)
        return out
