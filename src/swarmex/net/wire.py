"""The wire format of the networked runtime: msgpack payloads with a CRC32 trailer.

A *frame* is ``msgpack(payload) + crc32(msgpack(payload))`` (4 bytes, big-endian,
:func:`zlib.crc32`). Seed 000 (§4.1, Fig. 4.17) ends every broadcast with a checksum and
says a message with a bad one "is skipped"; it does not name the algorithm, so CRC32 it is:
it catches every burst error shorter than 32 bits, costs 4 bytes and is in the standard
library. Every decoder here either returns a well-formed message or raises
:class:`WireError` (with :class:`ChecksumError` and :class:`EncodingError` as the two
causes a receiver counts separately) — never anything else, whatever the bytes (the fuzz
tests in ``tests/net`` feed random and truncated frames to each of them).

Traversal messages (seed 000 §4.2) are msgpack arrays whose first element is the command:

==========  =========================  ============================================
command     direction                  fields after the command
==========  =========================  ============================================
``C00``     agent → server             wanted id (0 = "D00": any vacant id; -1: a spare,
                                       only an id vacated mid-mission)
``C22``     agent → server             id (asks for the mission data)
``C01``     agent → server, relayed    id, nest node ("a new rival"), optionally the
                                       vehicle: a map with ``kind`` ("simulated" |
                                       "mavlink") and short strings or numbers
``C02``     agent → server             id (pre-arm checks passed)
``C03``     agent → server             id (armed)
``HB``      both ways                  id (agent) / mission clock (server)
``ST``      agent → server             id, statistics map (after ``C11``)
``RET``     agent → server             id, reason: the agent hands its id back (a failed
                                       pre-arm check, low battery, a lost vehicle; seed
                                       000 §4.3: a spare may take it)
``C04``…    agent → server, relayed    a :class:`Broadcast` (Fig. 4.17)
``C11``
``ID``      server → agent             the id given for ``C00``
``MIS``     server → agent             mission map, log of earlier frames (late joiners)
``ACK``     server → agent             command acknowledged, id
``REF``     server → agent             reason: the connection is refused
``ERR``     server → agent             reason: a command out of order
``GO``      server → all               mission clock (the mission starts)
``LEFT``    server → all               id, mission time: the agent is gone
``JOIN``    server → all               id, start time, event number: a spare's start
``END``     server → all               the mission is over
``LOST``    server → agent             a relayed broadcast frame whose content this agent's
                                       radio lost (fault injection, ``serve --inject-loss``):
                                       only its timing fields apply
``MON``     viewer → server            (subscribe to the monitor events)
``EV``      server → viewer            JSON text of a batch of monitor events
==========  =========================  ============================================

The broadcast of Fig. 4.17 (``ID | Current Node | Job Bit | Done Nodes Bit | Done/Not Done
Nodes List | Obstacles | Checksum``) is the array ``[cmd, id, node, job, done_bit, nodes,
doers, obstacles, t, eta, rng, walls]``: node lists are little-endian ``uint32`` byte strings
(the thesis compresses the list "according to a specific encoding protocol" it does not
give; a packed array is 4 bytes a node and decodes with one ``numpy.frombuffer``). ``t`` is
the mission time of the event, ``eta`` the time of the sender's next event (C05: arrival,
C07: end of the job), ``rng`` the state of the run's random generator after the sender's
step (see :mod:`swarmex.net.traversal` for why these three ride along). ``walls``, present
with a done-nodes list, completes it into the thesis's KM: every obstacle the sender knows
(§4.1's list is KM, done nodes *and* obstacles; the done / not-done form alone cannot tell a
receiver which unlisted nodes are walls). A broadcast without a list has 11 fields.
Beyond Fig. 4.17, a decision of ``madgta-s`` carries its end-game team plan as a 13th field
(``walls`` is then nil without a list): ``[t, lengths, vertices]``, when the plan was made,
each agent's route length (row 0, unused, first) and the routes' vertices concatenated, both
packed as the node lists are.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass
from typing import Any

import msgpack
import numpy as np

#: largest frame a receiver accepts (a late joiner's mission log can be big, not unbounded)
MAX_FRAME = 64 * 1024 * 1024
CRC_BYTES = 4

#: the broadcast commands of §4.2 (the mission and termination stages)
BROADCAST_COMMANDS = ("C04", "C05", "C06", "C07", "C08", "C09", "C10", "C11")
CONTROL_COMMANDS = (
    "C00", "C22", "C01", "C02", "C03", "HB", "ST", "RET", "ID", "MIS", "ACK", "REF", "ERR",
    "GO", "LEFT", "JOIN", "END", "MON", "EV", "LOST",
)
RNG_BYTES = 37  # PCG64: 128-bit state, 128-bit increment, has_uint32 flag, uint32


class WireError(ValueError):
    """A frame that cannot be used: bad checksum, bad encoding or bad content."""


class ChecksumError(WireError):
    """The CRC32 trailer does not match the payload (or the frame is too short to have one)."""


class EncodingError(WireError):
    """The payload is not msgpack, or not a message of the expected shape."""


# ---------------------------------------------------------------------------- frames


def pack(obj: Any) -> bytes:
    """``obj`` as a frame: msgpack payload + big-endian CRC32 of the payload."""
    payload = msgpack.packb(obj, use_bin_type=True)
    return payload + zlib.crc32(payload).to_bytes(CRC_BYTES, "big")


def unpack(frame: bytes) -> Any:
    """The object in a frame; :class:`ChecksumError` / :class:`EncodingError` otherwise."""
    if not isinstance(frame, bytes | bytearray | memoryview):
        raise EncodingError(f"a frame is bytes, got {type(frame).__name__}")
    frame = bytes(frame)
    if len(frame) <= CRC_BYTES:
        raise ChecksumError(f"frame of {len(frame)} bytes has no payload")
    if len(frame) > MAX_FRAME:
        raise EncodingError(f"frame of {len(frame)} bytes exceeds {MAX_FRAME}")
    payload, crc = frame[:-CRC_BYTES], frame[-CRC_BYTES:]
    if zlib.crc32(payload) != int.from_bytes(crc, "big"):
        raise ChecksumError("checksum mismatch")
    try:
        return msgpack.unpackb(payload, raw=False, strict_map_key=False, use_list=True)
    except Exception as exc:  # msgpack raises several types (ExtraData, FormatError, …)
        raise EncodingError(f"not msgpack: {type(exc).__name__}") from None


def corrupt(frame: bytes, rng: np.random.Generator) -> bytes:
    """A damaged copy of ``frame`` (one flipped bit, or truncated): fault injection."""
    if rng.random() < 0.5 and len(frame) > 1:
        return frame[: int(rng.integers(0, len(frame)))]
    b = bytearray(frame)
    i = int(rng.integers(0, len(b)))
    b[i] ^= 1 << int(rng.integers(0, 8))
    return bytes(b)


# ---------------------------------------------------------------------------- checks


def _int(v: Any, what: str, lo: int = -(2**62), hi: int = 2**62) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
        raise EncodingError(f"{what}: expected an integer in [{lo}, {hi}], got {v!r:.40}")
    return v


def _float(v: Any, what: str) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
        raise EncodingError(f"{what}: expected a finite number, got {v!r:.40}")
    return float(v)


def _str(v: Any, what: str, limit: int = 4096) -> str:
    if not isinstance(v, str) or len(v) > limit:
        raise EncodingError(f"{what}: expected a string")
    return v


def _nodes(v: Any, what: str) -> np.ndarray:
    if not isinstance(v, bytes) or len(v) % 4:
        raise EncodingError(f"{what}: expected a uint32 byte string")
    return np.frombuffer(v, dtype="<u4").astype(np.int64)


def pack_nodes(nodes: Any) -> bytes:
    return np.asarray(nodes, dtype="<u4").tobytes()


def message(
    obj: Any, commands: tuple[str, ...] = CONTROL_COMMANDS + BROADCAST_COMMANDS
) -> list[Any]:
    """``obj`` checked to be a non-empty array starting with one of ``commands``."""
    if not isinstance(obj, list) or not obj or not isinstance(obj[0], str):
        raise EncodingError("a message is an array starting with its command")
    if obj[0] not in commands:
        raise EncodingError(f"unknown command {obj[0]!r:.20}")
    return obj


def arity(msg: list[Any], n: int) -> list[Any]:
    if len(msg) != n:
        raise EncodingError(f"{msg[0]}: expected {n - 1} fields, got {len(msg) - 1}")
    return msg


# ---------------------------------------------------------------------------- Fig. 4.17


@dataclass(frozen=True)
class Broadcast:
    """One mission-stage message of seed 000 (Fig. 4.17 plus the timing fields)."""

    cmd: str
    id: int
    node: int
    # job bit: 1 = doing (C07) / finished (C08) a job here, 0 = passing through; on C09,
    # 1 = the agent leaves while vertices may remain (a policy with ``announce_leave``)
    job: int = 0
    done_bit: int = 1  # 1: ``nodes`` are the done nodes; 0: the not-done nodes
    nodes: np.ndarray | None = None
    doers: np.ndarray | None = None  # who did each listed node (done_bit 1 only)
    obstacles: tuple[int, ...] = ()
    t: float = 0.0
    eta: float = 0.0
    rng: bytes | None = None
    walls: np.ndarray | None = None  # the sender's known obstacles (with a done-nodes list)
    #: madgta-s's team plan riding on the decision it was made for: (made at, each agent's
    #: route length, row 0 first; the routes' vertices, concatenated in that order)
    plan: tuple[float, np.ndarray, np.ndarray] | None = None

    def to_wire(self) -> list[Any]:
        empty = b""
        out = [
            self.cmd,
            self.id,
            self.node,
            self.job,
            self.done_bit,
            empty if self.nodes is None else pack_nodes(self.nodes),
            empty if self.doers is None else pack_nodes(self.doers),
            pack_nodes(self.obstacles),
            self.t,
            self.eta,
            self.rng,
        ]
        if self.walls is not None or self.plan is not None:
            out.append(None if self.walls is None else pack_nodes(self.walls))
        if self.plan is not None:
            t, lens, nodes = self.plan
            out.append([t, pack_nodes(lens), pack_nodes(nodes)])
        return out

    def frame(self) -> bytes:
        return pack(self.to_wire())

    @classmethod
    def from_wire(cls, obj: Any) -> Broadcast:
        m = message(obj, BROADCAST_COMMANDS)
        if len(m) not in (12, 13):
            arity(m, 11)
        rng = m[10]
        if rng is not None:
            check_rng(rng)
        job, done_bit = _int(m[3], "job bit", 0, 1), _int(m[4], "done bit", 0, 1)
        nodes, doers = _nodes(m[5], "nodes"), _nodes(m[6], "doers")
        if done_bit and doers.size != nodes.size:
            raise EncodingError("doers: one per listed done node")
        return cls(
            m[0],
            _int(m[1], "id", 1, 2**31),
            _int(m[2], "node", -1, 2**32),
            job,
            done_bit,
            nodes,
            doers,
            tuple(int(v) for v in _nodes(m[7], "obstacles")),
            _float(m[8], "t"),
            _float(m[9], "eta"),
            rng,
            None if len(m) == 11 or (len(m) == 13 and m[11] is None) else _nodes(m[11], "walls"),
            _plan(m[12]) if len(m) == 13 else None,
        )


def _plan(v: Any) -> tuple[float, np.ndarray, np.ndarray]:
    """A team plan's field: ``[t, route lengths, vertices]``, the lengths adding up to the
    vertices' count."""
    if not isinstance(v, list) or len(v) != 3:
        raise EncodingError("plan: expected [t, route lengths, vertices]")
    lens, nodes = _nodes(v[1], "plan route lengths"), _nodes(v[2], "plan vertices")
    if int(lens.sum()) != nodes.size:
        raise EncodingError("plan: the route lengths do not add up to its vertices")
    return _float(v[0], "plan t"), lens, nodes


def decode_broadcast(frame: bytes) -> Broadcast:
    return Broadcast.from_wire(unpack(frame))


def decode_message(frame: bytes) -> list[Any]:
    """Any traversal message as a checked array (broadcast fields are checked too)."""
    msg = message(unpack(frame))
    if msg[0] in BROADCAST_COMMANDS:
        Broadcast.from_wire(msg)
        return msg
    return check_control(msg)


_CONTROL_ARITY = {
    "C00": 2, "C22": 2, "C01": 3, "C02": 2, "C03": 2, "ST": 3, "RET": 3, "ID": 2, "MIS": 3,
    "ACK": 3, "REF": 2, "ERR": 2, "GO": 2, "LEFT": 3, "JOIN": 4, "END": 1, "MON": 1,
    "EV": 2, "LOST": 2,
}


def check_control(msg: list[Any]) -> list[Any]:
    """Shape and field types of a control message (see the module's table)."""
    cmd = msg[0]
    if cmd == "HB":  # agent: id (int); server: mission clock (number)
        arity(msg, 2)
        _float(msg[1], "HB")
        return msg
    if cmd == "C01" and len(msg) == 4:  # with the vehicle's description
        check_vehicle(msg[3])
    else:
        arity(msg, _CONTROL_ARITY[cmd])
    if cmd == "C00":
        _int(msg[1], "C00 id", -1, 2**31)
    elif cmd in ("C22", "C02", "C03", "ID"):
        _int(msg[1], f"{cmd} id", 0, 2**31)
    elif cmd == "C01":
        _int(msg[1], "C01 id", 1, 2**31)
        _int(msg[2], "C01 node", 0, 2**32)
    elif cmd == "RET":
        _int(msg[1], "RET id", 1, 2**31)
        _str(msg[2], "RET reason")
    elif cmd == "ST":
        _int(msg[1], "ST id", 1, 2**31)
        if not isinstance(msg[2], dict):
            raise EncodingError("ST: statistics must be a map")
    elif cmd == "MIS":
        if not isinstance(msg[1], dict) or not isinstance(msg[2], list):
            raise EncodingError("MIS: a mission map and a log list")
        if not all(isinstance(f, bytes) for f in msg[2]):
            raise EncodingError("MIS: the log holds frames")
    elif cmd == "ACK":
        _str(msg[1], "ACK command", 8)
        _int(msg[2], "ACK id", 0, 2**31)
    elif cmd in ("REF", "ERR"):
        _str(msg[1], f"{cmd} reason")
    elif cmd == "GO":
        _float(msg[1], "GO clock")
    elif cmd == "LEFT":
        _int(msg[1], "LEFT id", 1, 2**31)
        _float(msg[2], "LEFT time")
    elif cmd == "JOIN":
        _int(msg[1], "JOIN id", 1, 2**31)
        _float(msg[2], "JOIN time")
        _int(msg[3], "JOIN event", 0, 2**62)
    elif cmd == "EV":
        _str(msg[1], "EV events", MAX_FRAME)
    elif cmd == "LOST" and not isinstance(msg[1], bytes):
        raise EncodingError("LOST: expected a broadcast frame")
    return msg


def check_vehicle(v: Any) -> dict[str, Any]:
    """A vehicle description (C01's optional field): a map of at most 16 short string keys to
    short strings, numbers or booleans, with a string ``kind``."""
    if not isinstance(v, dict) or len(v) > 16 or not isinstance(v.get("kind"), str):
        raise EncodingError("C01 vehicle: expected a map with a kind")
    for k, x in v.items():
        if not isinstance(k, str) or len(k) > 32:
            raise EncodingError("C01 vehicle: keys are short strings")
        if isinstance(x, str):
            _str(x, f"C01 vehicle {k}", 200)
        elif not isinstance(x, bool):
            _float(x, f"C01 vehicle {k}")
    return v


# ---------------------------------------------------------------------------- rng state


def rng_state(rng: np.random.Generator) -> bytes:
    """The 37-byte wire form of a PCG64 generator's state."""
    st = rng.bit_generator.state
    if st.get("bit_generator") != "PCG64":
        raise ValueError("only PCG64 generators travel on the wire")
    inner = st["state"]
    return (
        int(inner["state"]).to_bytes(16, "big")
        + int(inner["inc"]).to_bytes(16, "big")
        + int(st["has_uint32"]).to_bytes(1, "big")
        + int(st["uinteger"]).to_bytes(4, "big")
    )


def check_rng(data: Any) -> bytes:
    """``data`` checked to be a loadable PCG64 state (odd increment, flag 0 or 1)."""
    if not isinstance(data, bytes) or len(data) != RNG_BYTES:
        raise EncodingError("rng: expected nil or a 37-byte state")
    if not data[31] & 1 or data[32] > 1:
        raise EncodingError("rng: not a PCG64 state")
    return data


def set_rng_state(rng: np.random.Generator, data: bytes) -> None:
    """Load a state made by :func:`rng_state` into ``rng`` (a PCG64 generator)."""
    rng.bit_generator.state = {
        "bit_generator": "PCG64",
        "state": {
            "state": int.from_bytes(data[:16], "big"),
            "inc": int.from_bytes(data[16:32], "big"),
        },
        "has_uint32": data[32],
        "uinteger": int.from_bytes(data[33:37], "big"),
    }
