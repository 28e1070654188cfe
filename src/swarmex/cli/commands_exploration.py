"""``swarmex explore`` and ``swarmex reproduce exploration`` (seed 003's exploration mission).

The options, their defaults and checks are the mission's (missions/exploration/params.py);
this module prints the summary line, draws the run, and adds the command-line-only options of
``--processes`` (one OS process per robot over ZeroMQ, :mod:`swarmex.net.mesh`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import console, reproduce_app
from swarmex.cli.missions import Extra, Surface, mission_command, progress_bar
from swarmex.cli.outputs import check_out_dir, study
from swarmex.errors import InputError, require
from swarmex.missions.base import Mission, Outcome
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
        watch=progress_bar(get("exploration")),
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
    from swarmex.experiments.pool import check_workers
    from swarmex.studies.exploration import reproduce

    check_workers(workers)  # 100,000 workers forked until the OOM killer came
    check_out_dir(out)
    with study(out / "runs.jsonl"):
        report = reproduce(out, quick=quick, workers=workers, progress=console.print)
    console.print(f"report: {report}")
