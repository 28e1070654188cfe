"""``swarmex`` command line: thin wrappers that parse, call the library and print.

:func:`main` is the console-script entry point. It turns bad input (our
:class:`~swarmex.errors.InputError` and Click's usage errors) into exit status 2 with one
line on stderr, and Ctrl-C into status 130, never a traceback.
"""

from __future__ import annotations

import sys

import typer

# each module registers its commands on the shared app when imported
from swarmex.cli import (  # noqa: F401
    commands_exploration,
    commands_foraging,
    commands_monitor,
    commands_net,
    commands_reproduce,
    commands_roadmap,
    commands_run,
    commands_sweep,
    commands_traversal,
    commands_uav,
)
from swarmex.cli.app import app
from swarmex.errors import InputError

try:  # recent Typer vendors Click as typer._click; older releases use Click itself
    from typer._click import exceptions as _cx
except ImportError:  # pragma: no cover - depends on the installed Typer
    from click import exceptions as _cx  # type: ignore[no-redef]

_NO_ARGS = getattr(_cx, "NoArgsIsHelpError", getattr(_cx, "NoArgsIsHelp", ()))


def main(argv: list[str] | None = None) -> int:
    try:
        result = app(args=argv, prog_name="swarmex", standalone_mode=False)
    except InputError as exc:
        print(f"swarmex: error: {exc}", file=sys.stderr)
        return 2
    except _NO_ARGS:
        return 0
    except _cx.UsageError as exc:
        msg = exc.format_message().replace("\n", " ")
        print(f"swarmex: error: {msg}", file=sys.stderr)
        return 2
    except typer.Exit as exc:
        return int(getattr(exc, "exit_code", getattr(exc, "code", 0)) or 0)
    except KeyboardInterrupt:
        print("swarmex: interrupted", file=sys.stderr)
        return 130
    except SystemExit as exc:  # typer.Exit / broken pipes under standalone_mode=False
        return exc.code if isinstance(exc.code, int) else 0
    return result if isinstance(result, int) else 0


def entry() -> None:
    sys.exit(main())


__all__ = ["app", "entry", "main"]
