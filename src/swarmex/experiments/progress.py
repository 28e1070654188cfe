"""What every long experiment shares: its progress bar and its append-only journal of runs.

Sweeps and the seed reproductions all run many missions, show the same Rich bar (done/total,
runs per second, elapsed, ETA) and keep finished runs in a JSON-lines journal that an
interrupted run may leave with a torn last line; both live here so they look and behave the
same everywhere.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    ProgressColumn,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)
from rich.text import Text


class RateColumn(ProgressColumn):
    """Runs per second over Rich's recent window (Rich's own speed column formats bytes)."""

    def render(self, task: Any) -> Text:
        speed = task.finished_speed or task.speed
        return Text("  …  runs/s" if speed is None else f"{speed:6.1f} runs/s", style="cyan")


def runs_progress(
    label: str,
    console: Console | None = None,
    disable: bool = False,
    detail: bool = False,
) -> Progress:
    """The bar of a batch of runs: ``label``, bar, done/total, rate, elapsed, ETA.

    ``detail`` adds the task's description (e.g. the run in progress) after the counts.
    """
    columns: list[ProgressColumn] = [
        TextColumn(f"[bold]{label}[/bold]"),
        BarColumn(),
        MofNCompleteColumn(),
        RateColumn(),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
    ]
    if detail:
        columns.append(TextColumn("{task.description}"))
    return Progress(*columns, console=console, transient=False, disable=disable)


def read_journal(path: Path, key: str = "key") -> dict[Any, dict[str, Any]]:
    """Finished runs of a JSON-lines journal, by ``key``; a torn line (a killed run) is skipped,
    so that run is simply done again."""
    done: dict[Any, dict[str, Any]] = {}
    if path.exists():
        for line in path.read_text(encoding="utf-8").splitlines():
            try:
                row = json.loads(line)
            except json.JSONDecodeError:
                continue
            if isinstance(row, dict) and key in row:
                done[row[key]] = row
    return done
