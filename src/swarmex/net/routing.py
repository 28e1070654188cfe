"""AODV on the process mesh's emulated radio: its frames and its link-layer feedback.

The robots of ``swarmex explore --processes`` route ``NEED_MAP``, ``MAP`` and ``CHANGE_GOAL``
with the very :class:`~swarmex.comm.aodv.AodvNode` the simulator uses (seed 003 §3.3.5), so
a unicast reaches a robot several hops away. Two things the simulator gets for free are
made here:

* **Frames.** AODV's control messages (``RREQ``, ``RREP``, ``RERR``) and the routed
  envelope (``DATA``, carrying an exploration unicast) travel as their ``to_dict()`` in the
  mesh's radio frames. :func:`check_aodv` checks every field of one before
  :func:`swarmex.comm.aodv.from_dict` rebuilds it, so a malformed frame is a counted bad
  frame, never an exception in a robot.
* **Link-layer feedback.** The simulator tells a sender at once that a unicast's next hop
  has left the range (the thesis's nanomsg send timeout), and AODV then repairs the route
  (:meth:`~swarmex.comm.aodv.AodvNode.send_failed`). In the emulation the *receiver*
  decides the range, from the cell the frame carries; so a unicast frame carries a link
  sequence number (:class:`LinkFeedback` keeps what it was for a few ticks), and a receiver
  that drops it as out of range answers ``NACK`` — what a real sender learns from the
  missing link-layer acknowledgement. A frame lost to the injected loss gets no ``NACK``
  (a loss the link layer does not see); a dead peer is found by the send timeout itself.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, fields
from typing import Any

from swarmex.comm.aodv import CONTROL_KINDS, DATA_KIND, MAX_HOPS, AodvNode, AodvStats, Rrep
from swarmex.net import wire

AODV_WIRE_KINDS = (*CONTROL_KINDS, DATA_KIND)
ROUTED_PAYLOADS = ("NEED_MAP", "MAP", "CHANGE_GOAL")  # the exploration unicasts
SEQ_LIMIT = 2**40  # sequence numbers, RREQ ids (a robot's lifetime of them)
TIME_LIMIT = 2**40  # ticks


def wants_feedback(msg: Any) -> bool:
    """A unicast whose failed delivery AODV must hear of: an application unicast, a routed
    hop (its kind is its payload's) or an RREP — the simulator's ``sim._UNICAST``."""
    return isinstance(msg, Rrep) or msg.kind in ROUTED_PAYLOADS


def unicast_counts(node: AodvNode | None, gap_requests: int) -> dict[str, int]:
    """One node's AODV unicast statistics (zeros when routing is off) and its ``NEED_MAP``
    requests to the origin of missing scans: the record's ``unicasts`` (as the simulator's
    :func:`~swarmex.missions.exploration.record.unicast_stats`, per node)."""
    out = dict.fromkeys((f.name for f in fields(AodvStats)), 0)
    if node is not None:
        out.update({k: int(v) for k, v in asdict(node.stats).items()})
    out["gap_requests"] = int(gap_requests)
    return out


def check_aodv(d: dict[str, Any], max_id: int,
               check_payload: Callable[[str, dict[str, Any]], None]) -> None:
    """Check an AODV message's fields (node ids in ``[0, max_id]``); ``check_payload(kind,
    body)`` checks a routed payload. :class:`~swarmex.net.wire.EncodingError` if malformed."""
    kind = d["type"]

    def node(key: str) -> int:
        return wire._int(d.get(key), f"{kind} {key}", 0, max_id)

    def seq(key: str, lo: int = 0) -> int:
        return wire._int(d.get(key), f"{kind} {key}", lo, SEQ_LIMIT)

    if kind == "RREQ":
        node("orig")
        node("dest")
        seq("oseq")
        seq("id")
        seq("dseq", -1)
        wire._int(d.get("hops"), "RREQ hops", 0, MAX_HOPS)
    elif kind == "RREP":
        node("orig")
        node("dest")
        seq("dseq", -1)
        wire._int(d.get("hops"), "RREP hops", 0, MAX_HOPS)
        life = wire._float(d.get("life"), "RREP lifetime")
        if not 0 <= life <= TIME_LIMIT:
            raise wire.EncodingError("RREP lifetime out of range")
    elif kind == "RERR":
        dests = d.get("dests")
        if not isinstance(dests, list) or not dests or len(dests) > max_id + 1:
            raise wire.EncodingError("RERR: expected a list of [destination, seq]")
        for pair in dests:
            if not isinstance(pair, list) or len(pair) != 2:
                raise wire.EncodingError("RERR: expected [destination, seq]")
            wire._int(pair[0], "RERR destination", 0, max_id)
            wire._int(pair[1], "RERR seq", -1, SEQ_LIMIT)
    elif kind == DATA_KIND:
        orig = node("orig")
        node("dest")
        wire._int(d.get("hops"), "DATA hops", 1, MAX_HOPS)
        if not -TIME_LIMIT <= wire._float(d.get("exp"), "DATA expiry") <= TIME_LIMIT:
            raise wire.EncodingError("DATA expiry out of range")
        p = d.get("payload")
        if not isinstance(p, dict) or p.get("type") not in ROUTED_PAYLOADS:
            raise wire.EncodingError("DATA payload: expected NEED_MAP, MAP or CHANGE_GOAL")
        if wire._int(p.get("src"), "payload src", 0, max_id) != orig:
            raise wire.EncodingError("DATA payload src differs from its origin")
        check_payload(p["type"], p)
    else:
        raise wire.EncodingError(f"not an AODV message {kind!r:.20}")


class LinkFeedback:
    """The unicast frames a node sent recently, by link sequence number, until a ``NACK``
    refuses one or ``keep`` ticks pass (a frame crosses loopback in well under a tick)."""

    def __init__(self, keep: int = 20) -> None:
        self.keep = keep
        self.next_seq = 0
        self.sent: dict[int, tuple[int, Any, int]] = {}  # seq -> (destination, message, tick)
        self.refusals = 0

    def stamp(self, dst: int, msg: Any, t: int) -> int:
        """A link sequence number for a unicast of ``msg`` to ``dst`` sent at tick ``t``."""
        self.next_seq += 1
        self.sent[self.next_seq] = (dst, msg, t)
        return self.next_seq

    def refused(self, by: int, seq: int) -> Any | None:
        """``by`` refused frame ``seq``: the message, if that frame went to ``by`` and is
        still remembered (else None: a stale or forged NACK is ignored)."""
        entry = self.sent.get(seq)
        if entry is None or entry[0] != by:
            return None
        del self.sent[seq]
        self.refusals += 1
        return entry[1]

    def prune(self, t: int) -> None:
        """Forget frames older than ``keep`` ticks (delivered, or lost without a word)."""
        if self.sent:
            first = next(iter(self.sent.values()))
            if t - first[2] > self.keep:
                self.sent = {k: v for k, v in self.sent.items() if t - v[2] <= self.keep}
