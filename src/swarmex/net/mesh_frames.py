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


# ---- the contents of STATUS and REPORT, checked before the display uses a field of them
#
# A robot's telemetry is a map whose fields the display turns into integers, cells and the
# record's numbers. ``int(inf)`` raises OverflowError, ``int(nan)`` ValueError, a huge
# integer passes int() and then breaks numpy or JSON: one such frame (a bug, a stray sender
# on the port) killed the display and lost the run's record. Every field is checked here,
# so a bad frame is a WireError like any other: dropped and counted.

MAX_TICK = 2**40  # ticks and move times (a century of 100 ms ticks)
MAX_COUNT = 2**53  # counters: exact in a JSON number (a double)
MAX_ROWS = 1_000_000  # moves, plan ticks, table entries

#: a REPORT's plain counters
REPORT_COUNTS = ("steps", "ticks", "moves", "plans", "replans", "scans", "archive",
                 "conflicts", "change_goals_sent", "blacklisted_regions", "link_refusals")
#: a REPORT's tables of counters by name
REPORT_TABLES = ("replan_reasons", "scans_by_origin", "unicasts", "multihop_in")
#: the traffic counters a REPORT must carry (:class:`~swarmex.net.mesh_node.Traffic`)
TRAFFIC_COUNTS = ("messages_out", "message_bytes_out", "harness_out", "harness_bytes_out",
                  "frames_out", "bytes_out", "send_timeouts", "frames_in", "bytes_in",
                  "out_of_range", "unheard_broadcasts", "lost_injected", "bad_frames")
#: a REPORT's traffic tables of (messages, bytes) by kind
TRAFFIC_TABLES = ("by_kind", "harness_by_kind")


def _flag(v: Any, what: str) -> bool:
    if not isinstance(v, bool):
        raise wire.EncodingError(f"{what}: expected true or false")
    return v


def _moves(v: Any, shape: tuple[int, int], what: str) -> list[list[int]]:
    """``[[t, x, y], ...]``: ticks in range, cells on the map."""
    if not isinstance(v, list) or len(v) > MAX_ROWS:
        raise wire.EncodingError(f"{what}: expected a list of [t, x, y]")
    out = []
    for row in v:
        if not isinstance(row, list) or len(row) != 3:
            raise wire.EncodingError(f"{what}: expected [t, x, y]")
        t = wire._int(row[0], f"{what} t", 0, MAX_TICK)
        x, y = _cell(row[1:], shape, what)
        out.append([t, x, y])
    return out


def _table(v: Any, what: str) -> dict[str, int]:
    """``{name: count}`` with short names and counts a JSON number holds exactly."""
    if not isinstance(v, dict) or len(v) > MAX_ROWS:
        raise wire.EncodingError(f"{what}: expected a map of counts")
    return {wire._str(k, f"{what} key", 64): wire._int(n, f"{what} count", 0, MAX_COUNT)
            for k, n in v.items()}


def status_fields(
    d: Any, shape: tuple[int, int]
) -> tuple[int, bool, bool, tuple[int, int], list[list[int]]]:
    """A STATUS frame's ``(t, finished, stopped, (x, y), moves)``, every field checked
    against the map's shape; :class:`~swarmex.net.wire.WireError` for anything malformed."""
    if not isinstance(d, dict):
        raise wire.EncodingError("STATUS: expected a map")
    t = wire._int(d.get("t"), "STATUS t", 0, MAX_TICK)
    finished = _flag(d.get("finished"), "STATUS finished")
    stopped = _flag(d.get("stopped", False), "STATUS stopped")
    pos = _cell([d.get("x"), d.get("y")], shape, "STATUS cell")
    return t, finished, stopped, pos, _moves(d.get("moves"), shape, "STATUS moves")


def report_fields(d: Any, shape: tuple[int, int]) -> dict[str, Any]:
    """A REPORT's fields, checked (counters, tables of counters, plan ticks, the trajectory
    on the map, the final map's bits for this map's size, the traffic counters) and copied
    into plain values; :class:`~swarmex.net.wire.WireError` for anything malformed."""
    from swarmex.net.routing import unicast_counts

    if not isinstance(d, dict):
        raise wire.EncodingError("REPORT: expected a map")
    out: dict[str, Any] = {k: wire._int(d.get(k), f"REPORT {k}", 0, MAX_COUNT)
                           for k in REPORT_COUNTS}
    fa = d.get("finished_at")
    out["finished_at"] = None if fa is None else wire._int(fa, "REPORT finished_at", 0,
                                                            MAX_TICK)
    for k in REPORT_TABLES:
        out[k] = _table(d.get(k), f"REPORT {k}")
    if not set(out["unicasts"]) <= set(unicast_counts(None, 0)):
        raise wire.EncodingError("REPORT unicasts: unknown counter")
    ticks = d.get("plan_ticks")
    if not isinstance(ticks, list) or len(ticks) > MAX_ROWS:
        raise wire.EncodingError("REPORT plan_ticks: expected a list of ticks")
    out["plan_ticks"] = [wire._int(t, "REPORT plan tick", 0, MAX_TICK) for t in ticks]
    out["trajectory"] = _moves(d.get("trajectory"), shape, "REPORT trajectory")
    free = d.get("free")
    if not isinstance(free, bytes) or len(free) != (shape[0] * shape[1] + 7) // 8:
        raise wire.EncodingError("REPORT free: expected the map's bits")
    out["free"] = free
    tr = d.get("traffic")
    if not isinstance(tr, dict):
        raise wire.EncodingError("REPORT traffic: expected a map")
    traffic: dict[str, Any] = {k: wire._int(tr.get(k), f"REPORT traffic {k}", 0, MAX_COUNT)
                               for k in TRAFFIC_COUNTS}
    for name in TRAFFIC_TABLES:
        table = tr.get(name)
        if not isinstance(table, dict) or len(table) > 256:
            raise wire.EncodingError(f"REPORT traffic {name}: expected a map")
        traffic[name] = {}
        for kind, row in table.items():
            row = _table(row, f"REPORT traffic {name}")
            if set(row) != {"messages", "bytes"}:
                raise wire.EncodingError(f"REPORT traffic {name}: expected messages and bytes")
            traffic[name][wire._str(kind, "REPORT traffic kind", 64)] = row
    out["traffic"] = traffic
    return out
