"""The Typer application object every command module registers itself on, and its lazy
command list.

Why lazy: a command module imports what its command needs (a mission's Params, the network
runtime, the monitor), and the mission Params pull in numba, its kernels and more. Importing
every command module to print ``swarmex --help`` cost 0.6-1 s; a user typing ``swarmex
traverse ...`` should not pay for ``explore`` either. So the top-level group knows each
command by an :data:`INDEX` entry (its name, the modules that register it, the one-line help
``--help`` lists) and imports the modules only when the command is looked up to run it (or
to print its own ``--help``). ``tests/e2e/test_cli_startup.py`` checks that the index says
what the commands themselves say, and that ``swarmex --help`` imports none of the heavy
libraries.
"""

from __future__ import annotations

import importlib
import sys
from dataclasses import dataclass
from typing import Any, NoReturn

import typer
from rich.console import Console
from typer.core import TyperCommand, TyperGroup


@dataclass(frozen=True)
class Entry:
    """What ``swarmex --help`` shows of a command before its module is imported."""

    modules: tuple[str, ...]  # importing all of these registers the command (complete)
    help: str  # the first paragraph of the command's own help
    hidden: bool = False


_C = "swarmex.cli."
# the four command modules that each register one `swarmex reproduce STUDY` subcommand
_REPRODUCE = tuple(
    _C + m
    for m in ("commands_exploration", "commands_foraging", "commands_reproduce", "commands_roadmap")
)
# in the order `swarmex --help` lists them
INDEX: dict[str, Entry] = {
    "explore": Entry(
        (_C + "commands_exploration",),
        "Explore an unknown world with a team of laser robots sharing scans over a mesh.",
    ),
    "forage": Entry(
        (_C + "commands_foraging",),
        "Find food on a g×g grid, spread the word, carry k units home (seed 002).",
    ),
    "monitor": Entry(
        (_C + "commands_monitor",),
        "Serve the live monitor page of a simulated (or networked) mission on 127.0.0.1.",
    ),
    "serve": Entry(
        (_C + "commands_net",),
        "Seed 000's mission server: ids, mission data, relay, monitor, result record.",
    ),
    "agent": Entry(
        (_C + "commands_net",),
        "One traversal UAV as a client of 'swarmex serve' (seed 000's client.py).",
    ),
    "watch": Entry(
        (_C + "commands_net",),
        "The live view of a networked mission in the terminal (or fed to the web monitor).",
    ),
    "mesh": Entry(
        (_C + "commands_net",),
        "'swarmex explore --processes' under another name (one process per robot).",
        hidden=True,
    ),
    "roadmap": Entry(
        (_C + "commands_roadmap",),
        "Coverage or goal search by a team on a WMA-RRT (or PRM) roadmap.",
    ),
    "run": Entry(
        (_C + "commands_run",),
        "Run any mission from a scenario file (options after the file override it).",
    ),
    "rerun": Entry(
        (_C + "commands_rerun",),
        "Run records again (same mission, parameters, seed); exit 1 if any comes out different.",
    ),
    "render": Entry(
        (_C + "commands_rerun",),
        "Draw a record's run: a .png picture or a .gif/.mp4 animation (it runs it again).",
    ),
    "sweep": Entry(
        (_C + "commands_sweep",),
        "Run the product of a spec's parameter lists and seeds; resumable; one Parquet table.",
    ),
    "plot": Entry(
        (_C + "commands_sweep",),
        "Draw a sweep's metric against a parameter: means with 95 % CI bands or bars.",
    ),
    "traverse": Entry(
        (_C + "commands_traversal",),
        "Every agent does a job at every free cell (seed 000, MADGTA and baselines).",
    ),
    "demo": Entry(
        (_C + "commands_traversal",),
        "Run MADGTA on an embedded generated map, print a summary and draw the paths.",
    ),
    "uav-emulator": Entry(
        (_C + "commands_uav",),
        "A MAVLink copter emulator (ArduCopter's GUIDED/RTL interface) for dry runs.",
    ),
    "reproduce": Entry(_REPRODUCE, "Rerun a seed's experiments and compare with its tables."),
}


def _loaded(entry: Entry) -> bool:
    return all(m in sys.modules for m in entry.modules)


class Interrupted(Exception):  # noqa: N818 - a signal, not an error
    """Ctrl-C inside a command (raised past Typer, which would swallow the interrupt)."""


class _Listed(TyperCommand):
    """A command not imported yet: its name and help, for ``swarmex --help`` only."""


class LazyGroup(TyperGroup):
    """The top-level group: commands of :data:`INDEX` are imported when first looked up."""

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        built = dict(self.commands)
        listed: dict[str, Any] = {}
        for name, entry in INDEX.items():
            if _loaded(entry) and name in built:
                listed[name] = built.pop(name)
            else:  # (`reproduce` is built early, by add_typer, but empty until loaded)
                built.pop(name, None)
                listed[name] = _Listed(name=name, help=entry.help, hidden=entry.hidden)
        listed.update(built)  # commands registered outside the index (e.g. by tests)
        self.commands = listed
        self._listing = False

    def format_help(self, ctx: Any, formatter: Any) -> None:
        """The help lists the index's entries without importing their modules."""
        self._listing = True
        try:
            super().format_help(ctx, formatter)
        finally:
            self._listing = False

    def invoke(self, ctx: Any) -> Any:
        """Run the command; Ctrl-C leaves as :class:`Interrupted`.

        Why: Typer turns a ``KeyboardInterrupt`` into a silent ``Exit(130)`` before
        :func:`swarmex.cli.main` can see it, so an interrupted run ended without a word."""
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            raise Interrupted from None

    def get_command(self, ctx: Any, cmd_name: str) -> Any:
        command = self.commands.get(cmd_name)
        if isinstance(command, _Listed) and not self._listing:
            command = self.commands[cmd_name] = load(cmd_name)
        return command


def load(name: str) -> Any:
    """The Click command ``swarmex NAME``, its modules imported (``None`` if unknown)."""
    entry = INDEX.get(name)
    for module in entry.modules if entry else ():
        importlib.import_module(module)
    return typer.main.get_group(app).commands.get(name)


def load_all() -> None:
    """Import every command module (tests and tools that walk the whole command tree)."""
    for entry in INDEX.values():
        for module in entry.modules:
            importlib.import_module(module)


app = typer.Typer(
    name="swarmex",
    cls=LazyGroup,
    help="Teams of agents that explore, cover and search unknown environments.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def installed_version() -> str:
    """The version pip installed (the wheel's metadata), else the source tree's.

    Why the metadata first: it is what ``pip show swarmex`` and a bug report's "which
    version?" mean; a source checkout run with ``PYTHONPATH=src`` has no metadata and falls
    back to ``swarmex.__version__`` (kept equal to pyproject's by a test)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("swarmex")
    except PackageNotFoundError:
        from swarmex import __version__

        return __version__


def _print_version(value: bool) -> None:
    if value:
        print(f"swarmex {installed_version()}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", help="Print swarmex's version and exit.", is_eager=True,
        callback=_print_version,
    ),
) -> None:
    """Teams of agents that explore, cover and search unknown environments."""


reproduce_app = typer.Typer(help="Rerun a seed's experiments and compare with its tables.")
app.add_typer(reproduce_app, name="reproduce")



def _console(stderr: bool = False) -> Console:
    """A console that wraps text to the terminal it writes to, and not at all elsewhere.

    Why: off a terminal Rich wraps at 80 columns, which split output paths and summary lines
    in the middle of a name in logs and pipes (a script greps them whole). Tables still fit
    the width Rich picks."""
    out = Console(stderr=stderr)
    if not (out.is_terminal or out.is_jupyter):
        out.soft_wrap = True
    return out


console = _console()
err_console = _console(stderr=True)


def interrupted(detail: str) -> NoReturn:
    """End a command stopped by Ctrl-C with one line on stderr saying what was kept, and exit
    status 130.

    A command that keeps finished work (a sweep, a reproduction) catches the interrupt and
    says what it kept here; for the others, :class:`Interrupted` reaches main(), which prints
    the plain "swarmex: interrupted".
    """
    err_console.print(f"swarmex: interrupted; {detail}", highlight=False, soft_wrap=True)
    raise typer.Exit(130)
