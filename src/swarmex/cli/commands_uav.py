"""``swarmex uav-emulator`` and the vehicle side of ``swarmex agent --vehicle`` (docs/uav.md).

The emulator is a MAVLink copter on a UDP port (:mod:`swarmex.net.uav_emulator`): the dry
run of a real flight, and what the tests fly hybrid missions against.
"""

from __future__ import annotations

import typer

from swarmex.cli.app import app
from swarmex.cli.shared import _say
from swarmex.errors import InputError, require
from swarmex.net.vehicle import Safety, Vehicle


def open_agent_vehicle(link: str, safety: Safety) -> tuple[Vehicle, Safety]:
    """``--vehicle`` and the safety limits (checked by the caller, with or without a
    vehicle) → the vehicle to fly and its limits (InputError for a bad link; the ``uav``
    extra named when pymavlink is missing)."""
    from swarmex.net.agent import open_vehicle

    return open_vehicle(link, safety), safety


def _home(text: str) -> tuple[float, float, float]:
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) not in (2, 3):
        raise InputError(f"--home: expected LAT,LON[,ALT], got {text!r}")
    return values[0], values[1], values[2] if len(values) == 3 else 100.0


@app.command("uav-emulator")
def uav_emulator(
    listen: str = typer.Option(
        "udp:127.0.0.1:14550", "--listen",
        help="udp:HOST:PORT to listen on (port 0: a free one, printed).",
    ),
    speedup: float = typer.Option(
        1.0, "--speedup", help="Emulated seconds per wall second (pair with serve --time-scale)."
    ),
    battery: float = typer.Option(100.0, "--battery", help="Charge at start, percent."),
    drain: float = typer.Option(6.0, "--drain", help="Percent of charge per minute of flight."),
    satellites: int = typer.Option(12, "--satellites", help="GPS satellites (< 6: no 3-D fix)."),
    fail_prearm: str | None = typer.Option(
        None, "--fail-prearm", help='Fault: refuse arming with "PreArm: TEXT".'
    ),
    drop_link_after: float | None = typer.Option(
        None, "--drop-link-after",
        help="Fault: fall silent this many emulated seconds after take-off (then failsafe RTL).",
    ),
    home: str = typer.Option(
        "43.268304,-79.911135,100", "--home", help="LAT,LON[,ALT] of home (seed 000's field)."
    ),
    idle_exit: float | None = typer.Option(
        None, "--exit-when-idle",
        help="Exit after this many seconds on the ground once its ground station (an agent)"
        " has fallen silent; before one first speaks it waits.",
    ),
    timeout: float | None = typer.Option(None, "--timeout", help="Exit after this long (s)."),
) -> None:
    """A MAVLink copter emulator (ArduCopter's GUIDED/RTL interface) for dry runs."""
    require("pymavlink", "uav", "swarmex uav-emulator")
    from swarmex.net.uav_emulator import Emulator, EmulatorConfig, parse_listen

    host, port = parse_listen(listen)
    cfg = EmulatorConfig(
        speedup=speedup, battery=battery, drain=drain, satellites=satellites,
        fail_prearm=fail_prearm or None, drop_link_after=drop_link_after, home=_home(home),
        idle_exit=idle_exit, timeout=timeout,
    )
    code = Emulator(host, port, cfg, _say).run()
    raise typer.Exit(code)
