"""``swarmex run SCENARIO.toml``: any mission command, with its options read from a file.

The scenario's values (see :mod:`swarmex.experiments.scenario`) go straight to the mission's
Params parsers, the same ones ``swarmex.run`` and the command line use, so a file value means
what the Python value means (``grid = [6, 5]`` is ``grid=(6, 5)``). Options given after the
file override the file's (``swarmex run s.toml --seed 3``).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import app
from swarmex.errors import InputError
from swarmex.experiments.scenario import (
    in_file,
    load_scenario,
    mission_shapes,
    scenario_values,
)


@app.command(
    "run",
    context_settings={"allow_extra_args": True, "ignore_unknown_options": True},
)
def run_scenario(
    ctx: typer.Context,
    scenario: Path = typer.Argument(..., help="TOML file: mission = ... plus the options."),
) -> Any:
    """Run any mission from a scenario file (options after the file override it)."""
    from swarmex.cli.app import load
    from swarmex.cli.missions import COMMANDS, EXTRAS, invoke
    from swarmex.experiments.scenario import resolve_path

    scn = load_scenario(scenario)
    load(scn.command)  # command modules are imported on first use (cli/app.py)
    if scn.mission not in COMMANDS:
        raise InputError(
            f"{scenario}: mission {scn.mission!r} needs the 'swarmex {scn.command}' command,"
            " which this installation does not have yet"
        )
    options = dict(scn.options)
    if "seeds" in options:  # a sweep's spec: its lists are axes, not one run's values
        raise InputError(f"{scenario} is a sweep spec (it has seeds): run it with"
                         f" 'swarmex sweep {scenario} --out DIR'")
    outputs = {k: options.pop(k) for k in ("json", "render") if k in options}
    # the command's own options (explore's processes, time-scale, …): as on its command line
    extras: dict[str, Any] = {}
    for extra in EXTRAS.get(scn.mission, ()):
        for key in (extra.name, extra.name.replace("_", "-")):
            if key in options:
                extras[extra.name] = _extra_value(extra, options.pop(key), scenario)
    try:
        values = scenario_values(type(scn)(scn.path, scn.mission, options),
                                 mission_shapes(scn.mission))
        values.update(extras)
        for key, value in outputs.items():
            values[key] = resolve_path(scn.path.parent, str(value))
        return invoke(scn.mission, values, ctx.args)
    except InputError as exc:
        raise _blamed(scenario, exc, ctx.args) from None


def _blamed(scenario: Path, exc: InputError, overrides: list[str]) -> InputError:
    """``exc`` naming the scenario file, unless it is about an option given after the file
    (which wins over the file's value): "s.toml: --agents must be at least 1" for
    ``--agents 0`` on the command line sent the user to a file that was right."""
    given = {arg.partition("=")[0] for arg in overrides if arg.startswith("--")}
    if given & set(re.findall(r"--[a-z][a-z0-9-]*", str(exc))):
        return exc
    return in_file(scenario, exc)


def _extra_value(extra: Any, value: Any, scenario: Path) -> Any:
    """A scenario's value of a command-line-only option, of the option's type."""
    kind = extra.annotation
    ok = isinstance(value, bool) if kind is bool else (
        isinstance(value, int | float) and not isinstance(value, bool)
        if kind in (int, float) else True
    )
    if not ok:
        flag = extra.flag or "--" + extra.name.replace("_", "-")
        raise InputError(f"{scenario}: {flag} must be {kind.__name__}, got {value!r}")
    return float(value) if kind is float else value
