"""Every ``swarmex …`` command written out in the README's and docs' code blocks parses
against the command line as it is: its command exists, every option it names exists and
takes the value given, and no required option is missing.

Why parse and not run: most of those commands are long reproductions, networked runs or
ones that need files the reader makes; what rots silently when the code moves is their
spelling (a renamed or removed option), which Click's own parser checks without running
anything. Synopses (``[--seed S]``, ``A | B``, ``…``) and placeholders (``<file>``) are
not commands and are skipped, and so are commands in the prose's inline code, which are
mostly partial on purpose (``swarmex serve --heartbeat 12``).
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
import typer

from swarmex.cli.app import app, load_all

try:  # recent Typer vendors Click as typer._click; older releases use Click itself
    from typer._click import exceptions as cx
except ImportError:  # pragma: no cover - depends on the installed Typer
    from click import exceptions as cx  # type: ignore[no-redef]

ROOT = Path(__file__).resolve().parents[1]
FENCED = re.compile(r"```[a-z]*\n(.*?)```", re.S)
COMMAND = re.compile(r"(?:^|&&\s*|\.venv/bin/)swarmex\s+(.*)")
SYNOPSIS = ("[", "|", "…", "...", "<", "$(")


def documented_commands() -> list[tuple[str, str]]:
    """(file, command line after ``swarmex``) for each command in a fenced code block."""
    out: list[tuple[str, str]] = []
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        for block in FENCED.findall(path.read_text(encoding="utf-8")):
            for line in re.sub(r"\\\n\s*", " ", block).splitlines():
                line = line.strip()
                found = COMMAND.search(line)
                if line.startswith("#") or found is None:
                    continue
                rest = re.split(r"\s+#|\s&&|\s>|\s2>", found.group(1))[0].strip()
                rest = rest.rstrip("&").strip()
                if rest and not any(mark in rest for mark in SYNOPSIS):
                    out.append((str(path.relative_to(ROOT)), rest))
    return out


COMMANDS = documented_commands()


def test_the_docs_have_commands_to_check() -> None:
    """The extraction itself works (an empty list would pass every case vacuously)."""
    assert len(COMMANDS) >= 25
    assert any(cmd.startswith("demo") for _f, cmd in COMMANDS)


@pytest.mark.parametrize(("where", "line"), COMMANDS, ids=[f"{f}: {c[:50]}" for f, c in COMMANDS])
def test_a_documented_command_parses(where: str, line: str) -> None:
    load_all()
    group = typer.main.get_group(app)
    args = shlex.split(line)
    command = group.commands.get(args[0])
    assert command is not None, f"{where}: no command {args[0]!r}"
    rest = args[1:]
    if hasattr(command, "commands"):  # a group: swarmex reproduce NAME
        command = command.commands.get(rest[0])
        assert command is not None, f"{where}: no command {args[:2]!r}"
        rest = rest[1:]
    for arg in rest:  # a file the repository ships must be there
        if arg.startswith("examples/"):
            assert (ROOT / arg).is_file(), f"{where}: swarmex {line}: no {arg}"
    try:
        command.make_context(args[0], list(rest))
    except cx.ClickException as exc:
        pytest.fail(f"{where}: swarmex {line}\n{exc.format_message()}")


def test_a_misspelt_option_is_caught() -> None:
    """The check can fail: a command with an option that does not exist is refused."""
    load_all()
    traverse = typer.main.get_group(app).commands["traverse"]
    with pytest.raises(cx.NoSuchOption):
        traverse.make_context("traverse", ["--grid", "5x5", "--agent", "2"])
