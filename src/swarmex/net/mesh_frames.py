"""The mesh's frames: radio frames between nodes and the control link's frames.

A radio frame ``[R, src, x, y, body]`` carries the sender's cell so that the receiver can
apply the radio range; a control frame is the experiment harness's (HELLO, GO, STATUS, ...).
Both are encoded with :mod:`swarmex.net.wire` and decoded here, checked field by field
against the map's shape, so that a node never acts on a malformed frame and every decoder
raises only :class:`~swarmex.net.wire.WireError`. Kept apart from the processes because the
checks are pure functions of bytes (the fuzz tests drive them without sockets).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from swarmex.comm.aodv import AodvMessage, Routed
from swarmex.comm.message import PackedMessage
from swarmex.net import wire
from swarmex.net.routing import AODV_WIRE_KINDS, check_aodv

if TYPE_CHECKING:  # imported where used: each process loads only what it needs
    from swarmex.missions.exploration.messages import Message

CONTROL = ("HELLO", "GO", "BEAT", "STATUS", "STOP", "REPORT", "NACK")
RADIO_KIND = "R"
DISPLAY = 10_000  # the display's node id (robots are 0..n-1)


def encode_radio(src: int, pos: tuple[int, int], msg: PackedMessage | Routed,
                 link: int | None = None) -> bytes:
    """A radio frame ``[R, src, x, y, body]``, plus the link sequence number of a unicast
    whose refusal the sender wants to hear of (:mod:`swarmex.net.routing`)."""
    frame = [RADIO_KIND, src, int(pos[0]), int(pos[1]), msg.to_dict()]
    if link is not None:
        frame.append(int(link))
    return wire.pack(frame)


def radio_link(obj: list[Any]) -> int | None:
    """The link sequence number of a checked radio frame (None: no feedback wanted)."""
    return int(obj[5]) if len(obj) == 6 else None


def _cell(v: Any, shape: tuple[int, int], what: str) -> tuple[int, int]:
    if not isinstance(v, list) or len(v) != 2:
        raise wire.EncodingError(f"{what}: expected [x, y]")
    x, y = wire._int(v[0], what), wire._int(v[1], what)
    if not (0 <= x < shape[1] and 0 <= y < shape[0]):
        raise wire.EncodingError(f"{what}: ({x},{y}) is outside the map")
    return x, y


def _check_scans(scans: Any, shape: tuple[int, int]) -> None:
    if not isinstance(scans, list) or not scans or len(scans) > 1_000_000:
        raise wire.EncodingError("scans: expected a non-empty list")
    h, w = shape
    for s in scans:
        if not isinstance(s, dict):
            raise wire.EncodingError("scan: expected a map")
        wire._int(s.get("o"), "scan origin", 0, DISPLAY)
        wire._int(s.get("s"), "scan seq", 0, 2**40)
        _cell([s.get("x"), s.get("y")], shape, "scan cell")
        box = s.get("box")
        if not isinstance(box, list) or len(box) != 4:
            raise wire.EncodingError("scan box: expected [x0, y0, w, h]")
        x0, y0, bw, bh = (wire._int(v, "scan box", 0, 1 << 30) for v in box)
        if x0 + bw > w or y0 + bh > h:
            raise wire.EncodingError("scan box outside the map")
        nbytes = (bw * bh + 7) // 8
        for key in ("free", "occ"):
            b = s.get(key)
            if not isinstance(b, bytes) or len(b) != nbytes:
                raise wire.EncodingError(f"scan {key}: expected {nbytes} bytes")


def decode_radio(
    frame: bytes, shape: tuple[int, int]
) -> tuple[int, tuple[int, int], Message | AodvMessage | Routed]:
    """``(src, (x, y), message)`` of a radio frame (an exploration message, or AODV's when
    routing is on), fully checked against the map's shape;
    :class:`~swarmex.net.wire.WireError` for anything malformed."""
    return radio_message(wire.unpack(frame), shape)


def radio_message(
    obj: Any, shape: tuple[int, int]
) -> tuple[int, tuple[int, int], Message | AodvMessage | Routed]:
    """:func:`decode_radio` after the unpacking."""
    from swarmex.comm import aodv
    from swarmex.missions.exploration.messages import from_dict

    if not isinstance(obj, list) or len(obj) not in (5, 6) or obj[0] != RADIO_KIND:
        raise wire.EncodingError("not a radio frame")
    src = wire._int(obj[1], "radio src", 0, DISPLAY)
    pos = _cell([obj[2], obj[3]], shape, "sender cell")
    if len(obj) == 6:
        wire._int(obj[5], "link seq", 1)
    d = obj[4]
    if not isinstance(d, dict) or not isinstance(d.get("type"), str):
        raise wire.EncodingError("radio body: expected a typed map")
    kind = d["type"]
    if wire._int(d.get("src"), "message src", 0, DISPLAY) != src:
        raise wire.EncodingError("message src differs from the frame's sender")
    try:
        if kind in AODV_WIRE_KINDS:
            check_aodv(d, DISPLAY, lambda k, p: _check_body(k, p, shape))
            return src, pos, aodv.from_dict(d, from_dict)
        _check_body(kind, d, shape)
        return src, pos, from_dict(d)
    except wire.WireError:
        raise
    except (KeyError, TypeError, ValueError, IndexError, OverflowError) as exc:
        raise wire.EncodingError(f"radio body: {type(exc).__name__}") from None


def _check_body(kind: str, d: dict[str, Any], shape: tuple[int, int]) -> None:
    """Check an exploration message's fields against the map's shape."""
    if kind in ("SCAN", "MAP"):
        _check_scans(d.get("scans"), shape)
    elif kind == "HEARTBEAT":
        _cell([d.get("x"), d.get("y")], shape, "heartbeat cell")
    elif kind == "NEED_MAP":
        have = d.get("have")
        if not isinstance(have, list) or len(have) > 1_000_000:
            raise wire.EncodingError("NEED_MAP: expected a list of runs")
        for r in have:
            if not isinstance(r, list) or len(r) != 3:
                raise wire.EncodingError("NEED_MAP run: expected [origin, lo, hi]")
            for v in r:
                wire._int(v, "NEED_MAP run", 0, 2**40)
    elif kind == "GOAL":
        if d.get("goal") is not None:
            _cell(d.get("goal"), shape, "goal")
        wire._float(d.get("priority"), "priority")
        _cell([d.get("x"), d.get("y")], shape, "goal sender cell")
    elif kind == "CHANGE_GOAL":
        _cell(d.get("goal"), shape, "goal")
        wire._float(d.get("priority"), "priority")
    else:
        raise wire.EncodingError(f"unknown radio message {kind!r:.20}")


def decode_control(frame: bytes) -> list[Any]:
    """A control-link frame (HELLO, GO, STATUS, STOP, REPORT), shape-checked."""
    return control_message(wire.unpack(frame))


def control_message(obj: Any) -> list[Any]:
    """:func:`decode_control` after the unpacking."""
    if not isinstance(obj, list) or not obj or obj[0] not in CONTROL:
        raise wire.EncodingError("not a control frame")
    cmd = obj[0]
    arity = {"HELLO": 3, "GO": 1, "BEAT": 1, "STATUS": 3, "STOP": 1, "REPORT": 3,
             "NACK": 3}[cmd]
    if len(obj) != arity:
        raise wire.EncodingError(f"{cmd}: expected {arity - 1} fields")
    if cmd in ("HELLO", "STATUS", "REPORT"):
        wire._int(obj[1], f"{cmd} id", 0, DISPLAY - 1)
    if cmd == "HELLO":
        wire._str(obj[2], "HELLO endpoint", 200)
    if cmd == "NACK":  # [NACK, refusing node, link seq]
        wire._int(obj[1], "NACK id", 0, DISPLAY)
        wire._int(obj[2], "NACK seq", 1)
    if cmd in ("STATUS", "REPORT") and not isinstance(obj[2], dict):
        raise wire.EncodingError(f"{cmd}: expected a map")
    return obj
