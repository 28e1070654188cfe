"""``swarmex explore`` and ``swarmex reproduce exploration`` (seed 003's exploration mission).

The options, their defaults and checks are the mission's (missions/exploration/params.py);
this module prints the summary line, draws the run, and adds the command-line-only options of
``--processes`` (one OS process per robot over ZeroMQ, :mod:`swarmex.net.mesh`).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import console, reproduce_app
from swarmex.cli.missions import Extra, Surface, mission_command
from swarmex.cli.outputs import check_out_dir, study
from swarmex.errors import InputError, require
from swarmex.missions.base import FrameCallback, Mission, Outcome
from swarmex.missions.registry import get


def report(outcome: Outcome, params: Any) -> None:
    run, grid = outcome.run, outcome.world
    m = outcome.record.metrics
    console.print(
        f"exploration/{params.strategy}: {params.robots} robot(s) on "
        f"{grid.world.width}x{grid.world.height} cells of {grid.cell:g} m — "
        f"complete={run.complete}, {run.makespan} steps, "
        f"explored {m['explored_fraction']:.2%}, mean robot steps {m['mean_steps']:.1f}, "
        f"replans {m['replans']}, messages {m['messages_sent']} ({m['bytes_sent']} B), "
        f"{run.wall_seconds:.2f} s"
    )


class StepTicker:
    """On a terminal, a one-line "exploring, step t" on stderr while an exploration runs.

    A run of 20 robots on 40 × 40 m takes about 15 s and printed nothing until its summary.
    The exploration mission asks a callback's ``wants(t)`` every tick before it builds a
    frame; the ticker answers for the recorder it wraps (an animation's), so no frame is
    built that nobody keeps and the run is the same. Redrawn at most 5 times a second and
    erased at the end; nothing at all when stderr is not a terminal (see :func:`watch`).
    """

    every = 0.2  # seconds between redraws

    def __init__(self, inner: Any = None, stream: Any = None) -> None:
        import sys

        self.inner = inner
        self.stream = sys.stderr if stream is None else stream
        self.t0 = self.shown = time.perf_counter()
        self.width = 0

    def wants(self, t: int) -> bool:
        now = time.perf_counter()
        if now - self.shown >= self.every:
            self.shown = now
            line = f"\rswarmex: exploring, step {t}, {now - self.t0:.0f} s"
            self.width = max(self.width, len(line) - 1)
            self.stream.write(line)
            self.stream.flush()
        if self.inner is None:
            return False
        wants = getattr(self.inner, "wants", None)
        return True if wants is None else bool(wants(t))

    def __call__(self, frame: Any) -> None:
        if self.inner is not None:
            self.inner(frame)

    def close(self) -> None:
        if self.width:
            self.stream.write("\r" + " " * self.width + "\r")
            self.stream.flush()
            self.width = 0


def watch(params: Any, world: Any, on_frame: FrameCallback | None) -> FrameCallback | None:
    """The ticker around ``on_frame`` when stderr is a terminal, else ``on_frame`` itself."""
    import sys

    if not sys.stderr.isatty():
        return on_frame
    return StepTicker(on_frame)


#: the options only the process mesh has, with their defaults (``swarmex mesh`` has the same)
MESH_DEFAULTS = {"time_scale": 1.0, "inject_loss": 0.0, "inject_kill": None,
                 "send_timeout": 20, "timeout": 600.0, "monitor": None}


def processes(
    mission: Mission[Any, Any], params: Any, extras: dict[str, Any], json_path: Path | None
) -> bool:
    """``--processes``: run the mesh of robot processes instead (exit 0 if complete, else 1)."""
    if not extras["processes"]:
        for name, default in MESH_DEFAULTS.items():  # e.g. the simulator has no wall clock
            if extras[name] != default:
                raise InputError(f"--{name.replace('_', '-')} needs --processes")
        return False
    if extras["render"] is not None:
        raise InputError("--render is not available with --processes (use swarmex monitor)")
    from swarmex.cli.shared import parse_kills, run_mesh

    world = mission.prepare(params)
    if extras["monitor"] is not None:  # the display process forwards to it: check here
        require("websockets", "monitor", "--monitor")
    rec = run_mesh(
        world.grid, params, extras["time_scale"], extras["inject_loss"],
        parse_kills(extras["inject_kill"]), extras["send_timeout"], extras["timeout"],
        json_path, extras["monitor"],
    )
    raise typer.Exit(0 if rec["complete"] else 1)


explore = mission_command(
    get("exploration"),
    Surface(
        report,
        extras=[
            Extra(
                "processes",
                False,
                "One OS process per robot plus a display, over ZeroMQ.",
                bool,
            ),
            Extra(
                "time_scale", 1.0, "With --processes: wall seconds per mission second.", float
            ),
            Extra(
                "inject_loss", 0.0, "With --processes: drop this fraction of messages.", float
            ),
            Extra("inject_kill", None, "With --processes: 'ID@TICK;…', robots that die.", str),
            Extra("send_timeout", 20, "With --processes: PUSH send timeout, ms.", int),
            Extra(
                "timeout", 600.0, "With --processes: give up after this many wall seconds.",
                float,
            ),
            Extra("monitor", None, "With --processes: ws://…/ingest of a live monitor.", str),
        ],
        alternative=processes,
        watch=watch,
        render_help="Picture (.png) or animation (.gif, .mp4) of the run.",
    ),
)


@reproduce_app.command("exploration")
def reproduce_exploration(
    out: Path = typer.Option(Path("reproduction/exploration"), "--out", help="Output directory."),
    quick: bool = typer.Option(False, "--quick", help="A small sweep in about a minute."),
    workers: int = typer.Option(2, "--workers", help="Worker processes."),
) -> None:
    """Rerun the thesis's chapter 4 (Figs. 4.1–4.4) and the strategy comparison."""
    from swarmex.studies.exploration import reproduce

    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")
    check_out_dir(out)
    with study(out / "runs.jsonl"):
        report = reproduce(out, quick=quick, workers=workers, progress=console.print)
    console.print(f"report: {report}")
