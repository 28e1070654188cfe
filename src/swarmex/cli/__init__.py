"""``swarmex`` command line: thin wrappers that parse, call the library and print.

:func:`main` is the console-script entry point. It turns bad input (our
:class:`~swarmex.errors.InputError` and Click's usage errors) into exit status 2 with one
line on stderr, and Ctrl-C into status 130, never a traceback.
"""

from __future__ import annotations

import sys

import click

from swarmex.cli import commands_traversal  # noqa: F401  (registers commands)
from swarmex.cli.app import app
from swarmex.errors import InputError


def main(argv: list[str] | None = None) -> int:
    try:
        app(args=argv, prog_name="swarmex", standalone_mode=False)
    except InputError as exc:
        print(f"swarmex: error: {exc}", file=sys.stderr)
        return 2
    except click.exceptions.NoArgsIsHelp:
        return 0
    except click.UsageError as exc:
        msg = exc.format_message().replace("\n", " ")
        print(f"swarmex: error: {msg}", file=sys.stderr)
        return 2
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except click.exceptions.Abort:
        print("swarmex: interrupted", file=sys.stderr)
        return 130
    except KeyboardInterrupt:
        print("swarmex: interrupted", file=sys.stderr)
        return 130
    return 0


def entry() -> None:
    sys.exit(main())


__all__ = ["app", "entry", "main"]
