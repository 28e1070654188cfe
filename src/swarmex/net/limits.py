"""The checks the networked commands share (``serve``, ``agent``, ``watch``, ``mesh`` /
``explore --processes``, ``uav-emulator``): one place for each bound, so that every command
refuses the same value with the same line (an :class:`~swarmex.errors.InputError`).

Kept free of heavy imports: the command-line modules import it at start.
"""

from __future__ import annotations

from swarmex.errors import InputError, check_number

#: msgpack's largest integer: a seed travels in the mission data (``serve``, C22) and in the
#: mesh's scenario file (``explore --processes``); a larger one was a traceback from the
#: packer (in the middle of serve's handshake, the agents waited for their timeout)
WIRE_SEED_MAX = 2**64 - 1

#: the longest wall time (seconds) a timeout, heartbeat or time scale may ask for, about 11
#: days. Why a bound: the waits become poll/select timeouts in whole milliseconds, which
#: overflow a C int past 2**31 ms (24.8 days), and 1e308 s was an OverflowError traceback.
#: 1e6 s leaves room for the launchers' own margins added to a timeout.
WALL_SECONDS_MAX = 1e6

#: ``--send-timeout`` (ms): a PUSH that cannot deliver within it drops the frame. ZeroMQ
#: takes an int (10^11 crashed every robot with an OverflowError), and a robot blocked for
#: over a minute on one send has stopped being a robot
SEND_TIMEOUT_MAX_MS = 60_000

#: robots of one process mesh: each is its own OS process (numpy, numba and the robot's own
#: maps: about 175 MB resident), so 64 already need about 11 GB; 300 asked for forked 300
#: processes. The in-process simulator has no such cap (its memory check is per cell)
MESH_MAX_ROBOTS = 64


def check_wall_seconds(value: float, option: str, *, zero_ok: bool = False,
                       unit: str = "s (about 11 days)") -> None:
    """``value`` is a wall-clock duration (or, with ``unit`` saying so, wall seconds per
    mission second): finite, > 0 (>= 0 with ``zero_ok``), at most :data:`WALL_SECONDS_MAX`."""
    if zero_ok:
        check_number(value, option, at_least=0)
    else:
        check_number(value, option, above=0)
    if value > WALL_SECONDS_MAX:
        low = ">= 0" if zero_ok else "> 0"
        raise InputError(f"{option} must be {low} and at most {WALL_SECONDS_MAX:.0f} {unit},"
                         f" got {value:g}")


def check_wire_seed(seed: int, where: str) -> None:
    """A seed that travels in ``where`` as a msgpack integer (at most 64 bits)."""
    if seed > WIRE_SEED_MAX:
        raise InputError(f"--seed must be at most {WIRE_SEED_MAX} (it travels in {where}"
                         f" as a 64-bit integer), got {seed}")


def check_ingest_url(url: str | None, option: str) -> None:
    """The web monitor's ingest WebSocket (``--monitor``, ``--forward``), checked before
    anything starts: a malformed one used to surface only as a warning at the end."""
    if url is not None and not url.startswith(("ws://", "wss://")):
        raise InputError(f"{option}: expected ws://HOST:PORT/ingest, got {url!r}")


def check_mesh_robots(robots: int) -> None:
    """One OS process per robot: at most :data:`MESH_MAX_ROBOTS`."""
    if robots > MESH_MAX_ROBOTS:
        raise InputError(
            f"--robots must be at most {MESH_MAX_ROBOTS} with one process per robot"
            f" (--processes, swarmex mesh), got {robots}; the in-process simulator"
            " (swarmex explore without --processes) has no such cap"
        )


def check_send_timeout(ms: int) -> None:
    """``--send-timeout``: 1..:data:`SEND_TIMEOUT_MAX_MS` milliseconds."""
    if isinstance(ms, bool) or not isinstance(ms, int) or not 1 <= ms <= SEND_TIMEOUT_MAX_MS:
        raise InputError(f"--send-timeout must be in 1..{SEND_TIMEOUT_MAX_MS} ms, got {ms}")
