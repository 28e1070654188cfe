"""Helpers that more than one command module uses, so that no command module imports another.

``--connect`` is checked the same way by ``monitor``, ``agent`` and ``watch``.

``swarmex explore --processes`` and ``swarmex mesh`` both launch the process mesh (their
worlds come from the exploration mission, ``missions/exploration/mission.py``).
"""

from __future__ import annotations

import time
from pathlib import Path

import typer

from swarmex.cli.app import console, err_console, interrupted
from swarmex.cli.outputs import check_output
from swarmex.errors import InputError


def check_connect(address: str) -> None:
    """``--connect`` must be a ZeroMQ endpoint the mission server publishes on: otherwise the
    monitor's reader thread died with a ZMQError traceback and the page waited for nothing."""
    if address.startswith(("ipc://", "inproc://")) and len(address.split("://", 1)[1]) > 0:
        return
    host, sep, port = address.removeprefix("tcp://").rpartition(":")
    if address.startswith("tcp://") and host and sep and port.isdigit() and 0 < int(port) < 65536:
        return
    raise InputError(f"--connect: expected tcp://HOST:PORT, got {address!r}")


def _say(text: str) -> None:
    console.print(text, highlight=False, soft_wrap=True)
    console.file.flush()


def _warn(text: str) -> None:
    """A failure's line, on standard error (scripts read the report on standard output)."""
    err_console.print(text, highlight=False, soft_wrap=True)
    err_console.file.flush()


def parse_kills(text: str | None) -> dict[int, int]:
    """``"ID@TICK;…"`` → {robot id: tick at which it dies}."""
    out: dict[int, int] = {}
    for part in (text or "").split(";"):
        if not part.strip():
            continue
        rid, sep, tick = part.partition("@")
        try:
            out[int(rid)] = int(tick)
        except ValueError:
            raise InputError(f"--inject-kill: expected ID@TICK, got {part.strip()!r}") from None
        if not sep or out[int(rid)] < 0:
            raise InputError(f"--inject-kill: expected ID@TICK, got {part.strip()!r}")
    return out


def run_mesh(grid, params, time_scale: float = 1.0, loss: float = 0.0,
             kills: dict[int, int] | None = None, send_timeout_ms: int = 20,
             timeout: float = 600.0, json_path: Path | None = None,
             monitor_url: str | None = None) -> dict:
    """``explore --processes``: validate the network options, run, print the summary line.

    Every check comes before the first process starts (serve's and watch's checks, shared
    through :mod:`swarmex.net.limits`): a bad seed, send timeout or wall time used to surface
    as a traceback from a robot or the launcher, a bad ``--monitor`` only at the end."""
    from swarmex.net.limits import (
        check_ingest_url,
        check_mesh_robots,
        check_send_timeout,
        check_wall_seconds,
        check_wire_seed,
    )
    from swarmex.net.mesh import EXIT_DISPLAY_DIED, DisplayDied, run_processes
    from swarmex.net.mesh_scenario import MeshOptions

    check_mesh_robots(params.robots)  # one OS process each: 300 forked 300
    check_wall_seconds(time_scale, "--time-scale", unit="(wall seconds per mission second)")
    check_wall_seconds(timeout, "--timeout")
    if not 0.0 <= loss < 1.0:
        raise InputError(f"--inject-loss must be in [0, 1), got {loss}")
    check_send_timeout(send_timeout_ms)
    check_wire_seed(params.seed, "the mesh's scenario file")
    check_ingest_url(monitor_url, "--monitor")
    kills = kills or {}
    for rid in kills:
        if not 0 <= rid < params.robots:
            raise InputError(f"--inject-kill: no robot {rid} (ids 0..{params.robots - 1})")
    check_output(json_path, "--json")
    options = MeshOptions(time_scale=time_scale, loss=loss, send_timeout_ms=send_timeout_ms,
                          timeout=timeout, inject_kill=kills)
    started = time.time()
    try:
        record = run_processes(grid, params, options, json_path, monitor_url, _say)
    except KeyboardInterrupt:
        if json_path is not None and json_path.exists() and json_path.stat().st_mtime >= started:
            interrupted(f"the record of the run so far is in {json_path}")
        interrupted("nothing written")
    except DisplayDied as exc:  # one line (it was a RuntimeError's traceback)
        _warn(f"swarmex: {exc}; nothing written")
        raise typer.Exit(EXIT_DISPLAY_DIED) from None
    m = record["metrics"]
    console.print(
        f"exploration/{params.strategy} as processes: {params.robots} robot(s) — "
        f"complete={record['complete']}, {record['makespan']:.0f} steps, explored "
        f"{m['explored_fraction']:.2%}, robots lost {m['robots_lost']}, messages "
        f"{m['messages_sent']} ({m['bytes_sent']} B), {record['wall_seconds']:.1f} s",
        highlight=False,
    )
    return record
