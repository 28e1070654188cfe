"""``swarmex run SCENARIO.toml``: any mission command, with its options read from a file.

The scenario (see :mod:`swarmex.experiments.scenario`) is turned into the argv of the
mission's own command, which is then invoked: there is no second parser to keep in step with
the commands, and a mission becomes runnable from files as soon as its command exists.
Options given after the file override the file's (``swarmex run s.toml --seed 3``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import app
from swarmex.errors import InputError
from swarmex.experiments.scenario import OptionShape, load_scenario, scenario_argv


def option_shapes(command: Any) -> dict[str, OptionShape]:
    """Read each option's name, path-ness and flag-ness off a (Typer-built) Click command."""
    shapes = {}
    for param in command.params:
        long = [o for o in getattr(param, "opts", ()) if o.startswith("--")]
        if not long or getattr(param, "param_type_name", "option") != "option":
            continue
        negation = next(
            (o for o in getattr(param, "secondary_opts", ()) if o.startswith("--")), None
        )
        shapes[long[0][2:]] = OptionShape(
            flag=long[0],
            is_path=_is_path(param),
            is_flag=bool(getattr(param, "is_flag", False)),
            negation=negation,
            multiple=bool(getattr(param, "multiple", False)),
            required=bool(getattr(param, "required", False)),
        )
    return shapes


def _is_path(param: Any) -> bool:
    """Whether an option holds a file path (Typer's annotation, or a Click Path type)."""
    annotation = getattr(getattr(param, "type_descriptor", None), "annotation", None)
    if annotation is not None:
        return annotation is Path or Path in getattr(annotation, "__args__", ())
    return type(getattr(param, "type", None)).__name__ == "Path"


@app.command(
    "run",
    context_settings={"allow_extra_args": True, "ignore_unknown_options": True},
)
def run_scenario(
    ctx: typer.Context,
    scenario: Path = typer.Argument(..., help="TOML file: mission = ... plus the options."),
) -> Any:
    """Run any mission from a scenario file (options after the file override it)."""
    from swarmex.cli import _cx  # the Click exceptions module Typer uses (set up by the package)

    scn = load_scenario(scenario)
    group = typer.main.get_command(app)
    command = group.commands.get(scn.command)
    if command is None:
        raise InputError(
            f"{scenario}: mission {scn.mission!r} needs the 'swarmex {scn.command}' command,"
            " which this installation does not have yet"
        )
    argv = [*scenario_argv(scn, option_shapes(command)), *ctx.args]
    try:
        return command.main(args=argv, prog_name=f"swarmex {scn.command}", standalone_mode=False)
    except InputError as exc:
        raise InputError(f"{scenario}: {exc}") from None
    except _cx.UsageError as exc:
        raise InputError(f"{scenario}: {exc.format_message()}") from None
