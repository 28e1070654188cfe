"""What every long experiment shares: its progress bar and its append-only journal of runs.

Sweeps and the seed reproductions all run many missions, show the same Rich bar (done/total,
runs per second, elapsed, ETA) and keep finished runs in a JSON-lines journal
(:class:`Journal`: one line per run, flushed at once) that an interrupted run may leave with a
torn last line; both live here so they look and behave the same everywhere.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from types import TracebackType
from typing import IO, Any

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
from rich.table import Column
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
    The bar is drawn on standard error unless ``console`` says otherwise, and only when that
    console is a terminal (or a notebook's output): Rich, told it is not one, still prints
    the bar's last state when it stops, which put a truncated bar among a reproduction's
    report lines in a pipe or a log.
    """
    console = console if console is not None else Console(stderr=True)
    disable = disable or not (console.is_terminal or console.is_jupyter)
    # the counts keep their width; the bar and the run's description share what is left,
    # the description cut with an ellipsis: an unbounded description squeezed done/total
    # and the ETA to "…" and wrapped the line on an 80-column terminal
    columns: list[ProgressColumn] = [
        TextColumn(f"[bold]{label}[/bold]", table_column=Column(no_wrap=True)),
        BarColumn(bar_width=None, table_column=Column(ratio=1, min_width=10)),
        MofNCompleteColumn(table_column=Column(no_wrap=True)),
        RateColumn(table_column=Column(no_wrap=True)),
        TimeElapsedColumn(table_column=Column(no_wrap=True)),
        TextColumn("ETA", table_column=Column(no_wrap=True)),
        TimeRemainingColumn(table_column=Column(no_wrap=True)),
    ]
    if detail:
        columns.append(TextColumn("{task.description}", table_column=Column(
            ratio=2, no_wrap=True, overflow="ellipsis")))
    return Progress(*columns, console=console, transient=False, disable=disable,
                    expand=True)


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


class Journal:
    """An append-only JSON-lines file of finished runs, one row (a dict) per line, each named
    by its ``key`` field.

    :meth:`add` writes and flushes the line at once, so a finished run survives the crash or
    kill of this process; reading skips a torn last line (:func:`read_journal`), whose run is
    then simply done again. A later row for the same key replaces an earlier one.
    """

    def __init__(self, path: str | Path, key: str = "key") -> None:
        self.path = Path(path)
        self.key = key
        self._rows: dict[Any, dict[str, Any]] | None = None
        self._fh: IO[str] | None = None

    def rows(self) -> dict[Any, dict[str, Any]]:
        """Every row by key (read from the file once, then kept up to date)."""
        if self._rows is None:
            self._rows = read_journal(self.path, self.key)
        return self._rows

    def get(self, key: Any) -> dict[str, Any] | None:
        return self.rows().get(key)

    def __contains__(self, key: Any) -> bool:
        return key in self.rows()

    def add(self, row: dict[str, Any]) -> None:
        """Append one row (it names its own key) and flush it."""
        if self._fh is None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._fh = self.path.open("a", encoding="utf-8")
        self._fh.write(json.dumps(row) + "\n")
        self._fh.flush()
        if self._rows is not None:
            self._rows[row[self.key]] = row

    def close(self) -> None:
        if self._fh is not None:
            self._fh.close()
            self._fh = None

    def __enter__(self) -> Journal:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


class SweepBar:
    """A sweep's bar as ``run_sweep``'s callbacks: ``on_start(total, finished)`` adds it
    (after the workers are forked: Rich's drawing thread must not be forked with them),
    ``on_outcome(outcome)`` advances it and counts failed runs, :meth:`stop` ends it.

    Why one class: ``swarmex sweep`` and ``swarmex.sweep`` show the same bar; the Python
    call showed nothing for a sweep of an hour. ``announce(total, finished)``, if given, is
    called first (the command line prints its "N runs … → DIR" line there).
    """

    def __init__(self, console: Console | None = None, disable: bool = False,
                 announce: Any = None) -> None:
        self.progress = runs_progress("sweep", console, disable=disable, detail=True)
        self.announce = announce
        self.task: Any = None
        self.failed = 0

    def on_start(self, total: int, finished: int) -> None:
        if self.announce is not None:
            self.announce(total, finished)
        self.task = self.progress.add_task("", total=total, completed=finished)
        self.progress.start()

    def on_outcome(self, outcome: Any) -> None:
        if not outcome.ok:
            self.failed += 1
            self.progress.update(self.task, description=f"({self.failed} failed)")
        self.progress.advance(self.task)

    def stop(self) -> None:
        if self.task is not None:  # a bar never started would print a blank line
            self.progress.stop()


class FrameProgress:
    """The ``on_frame`` callback of one long run: a transient Rich bar (done/total, elapsed)
    fed from the frames, around the run's own callback (``inner``, or None).

    Why: a traversal of a large map runs for minutes (madgta-k on den520d: 200 s) and used
    to print nothing until the end. The bar appears only after :attr:`DELAY` seconds (no
    flash on the usual sub-second run) and redraws at most :attr:`EVERY` seconds apart. The
    frames are the ones ``swarmex.run(on_frame=...)`` gives: observing them changes nothing
    in the run. ``swarmex traverse`` shows it on a terminal, ``swarmex.run(progress=True)``
    on a terminal or in a notebook.
    """

    DELAY = 0.5
    EVERY = 0.1

    def __init__(self, spec: Any, console: Console, inner: Any = None) -> None:
        self.spec = spec  # a swarmex.missions.base.ProgressSpec
        self.inner = inner
        self.bar = Progress(
            f"[bold]{spec.unit}[/bold]", BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
            console=console, transient=True,
        )
        self.task = self.bar.add_task("", total=spec.total)
        self.started = False
        self.t0 = self.last = time.monotonic()

    def wants(self, t: Any) -> bool:
        """Whether the run should build the frame of ``t`` (a mission that asks, before it
        builds one): every frame a wrapped recorder keeps, else only when the bar redraws."""
        if self.inner is not None:
            inner_wants = getattr(self.inner, "wants", None)
            return True if inner_wants is None else bool(inner_wants(t))
        now = time.monotonic()
        return now - self.last >= self.EVERY and now - self.t0 >= self.DELAY

    def __call__(self, frame: Any) -> Any:
        result = self.inner(frame) if self.inner is not None else None
        now = time.monotonic()
        if now - self.last < self.EVERY or now - self.t0 < self.DELAY:
            return result
        self.last = now
        if not self.started:
            from rich.errors import LiveError

            try:
                self.bar.start()
            except LiveError:  # the compile notice's spinner is up: try again later
                return result
            self.started = True
        self.bar.update(self.task, completed=self.spec.count(frame))
        return result

    def close(self) -> None:
        if self.started:
            self.bar.stop()
            self.started = False


def frame_progress(mission: Any, params: Any, world: Any, console: Console,
                   on_frame: Any) -> Any:
    """The ``on_frame`` callback of a run on ``world`` with a :class:`FrameProgress` bar
    around ``on_frame`` counting what ``mission.progress`` says, on ``console`` when that is
    a terminal or a notebook's output; else ``on_frame`` itself. The command line's bar
    and ``swarmex.run(progress=True)`` are this one."""
    if not (console.is_terminal or console.is_jupyter):
        return on_frame  # first: a mission's spec may cost a pass over the world
    spec = mission.progress(params, world)
    if spec is None:
        return on_frame
    return FrameProgress(spec, console, on_frame)


def progress_watch(mission: Any, console: Console | None = None) -> Any:
    """The ``watch`` of :meth:`~swarmex.missions.base.Mission.run` that shows ``mission``'s
    bar (:func:`frame_progress`, on standard error unless ``console`` says otherwise):
    ``swarmex.run``, ``swarmex.rerun`` and ``swarmex.render`` with ``progress=True``."""
    out = console if console is not None else Console(stderr=True)

    def watch(params: Any, world: Any, on_frame: Any) -> Any:
        return frame_progress(mission, params, world, out, on_frame)

    return watch


def watches_if(progress: Any) -> Any:
    """Mission name -> :func:`progress_watch` when ``progress`` is True, None when False (the
    ``progress=`` of ``swarmex.rerun`` and ``swarmex.render``)."""
    if not isinstance(progress, bool):  # "no" is truthy: it would have shown the bar
        from swarmex.errors import InputError

        raise InputError(f"progress must be True or False, got {progress!r}")
    if not progress:
        return None
    from swarmex.missions.registry import get

    return lambda name: progress_watch(get(name))
