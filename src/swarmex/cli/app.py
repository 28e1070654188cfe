"""The Typer application object every command module registers itself on."""

from __future__ import annotations

import typer
from rich.console import Console

app = typer.Typer(
    name="swarmex",
    help="Teams of agents that explore, cover and search unknown environments.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
reproduce_app = typer.Typer(help="Rerun a seed's experiments and compare with its tables.")
app.add_typer(reproduce_app, name="reproduce")

console = Console()
err_console = Console(stderr=True)
