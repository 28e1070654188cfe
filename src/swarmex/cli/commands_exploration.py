"""``swarmex explore`` and ``swarmex reproduce exploration`` (seed 003's exploration mission)."""

from __future__ import annotations

from pathlib import Path

import typer

from swarmex.cli.app import app, console, reproduce_app
from swarmex.cli.outputs import RENDER_SUFFIXES, check_output
from swarmex.cli.shared import load_world, run_mesh
from swarmex.errors import InputError


class FrameRecorder:
    """Keeps at most ``limit`` evenly spaced snapshots, halving the rate when full."""

    def __init__(self, limit: int = 200) -> None:
        self.limit = limit
        self.every = 1
        self.frames: list = []

    def __call__(self, t: int, run) -> None:
        from swarmex.viz.exploration import snapshot

        if t % self.every:
            return
        if self.frames and self.frames[-1].t == t:
            return
        self.frames.append(snapshot(t, run))
        if len(self.frames) > self.limit:
            self.every *= 2
            self.frames = [f for f in self.frames if f.t % self.every == 0]

    def finish(self, run) -> None:
        from swarmex.viz.exploration import snapshot

        if not self.frames or self.frames[-1].t != run.makespan:
            self.frames.append(snapshot(run.makespan, run))


@app.command()
def explore(
    map_path: Path = typer.Option(
        None, "--map", help="MovingAI .map or ROS map (.yaml beside its .pgm)."
    ),
    empty: str = typer.Option(None, "--empty", help="Empty walled world WxH in metres."),
    cell: float = typer.Option(
        None, "--cell", help="Cell size in metres (default 0.05; a ROS map has its own)."
    ),
    robots: int = typer.Option(..., "--robots", help="Team size."),
    laser_range: float = typer.Option(2.0, "--laser-range", help="Laser range, metres."),
    comm_range: float = typer.Option(10.0, "--comm-range", help="Radio range, metres."),
    strategy: str = typer.Option(
        "greedy-exclusion",
        "--strategy",
        help="greedy | greedy-exclusion | utility | minpos | hungarian",
    ),
    starts: str = typer.Option(None, "--starts", help="Start cells 'x,y;x,y;…'."),
    seed: int = typer.Option(0, "--seed"),
    robot_radius: float = typer.Option(0.1, "--robot-radius", help="Robot radius, metres."),
    beams: int = typer.Option(360, "--beams", help="Laser beams per 360° scan."),
    max_ticks: int = typer.Option(None, "--max-ticks", help="Stop after this many steps."),
    json_path: Path = typer.Option(None, "--json", help="Write the result record here."),
    render: Path = typer.Option(
        None, "--render", help="Picture (.png) or animation (.gif, .mp4) of the run."
    ),
    processes: bool = typer.Option(
        False, "--processes", help="One OS process per robot plus a display, over ZeroMQ."
    ),
    time_scale: float = typer.Option(
        1.0, "--time-scale", help="With --processes: wall seconds per mission second."
    ),
    inject_loss: float = typer.Option(
        0.0, "--inject-loss", help="With --processes: drop this fraction of messages."
    ),
    aodv: bool = typer.Option(
        True, "--aodv/--no-aodv", help="Route multi-hop unicasts with AODV (simulator)."
    ),
    conflict_yield: bool = typer.Option(
        False, "--conflict-yield", help="A goal conflict's loser must leave the winner's zone."
    ),
    plan_pause: int = typer.Option(
        0, "--plan-pause", help="Steps a robot stands still after each plan (0: none)."
    ),
) -> None:
    """Explore an unknown world with a team of laser robots sharing scans over a mesh."""
    from swarmex.engine.record import write_record
    from swarmex.missions.exploration import ExplorationParams, parse_starts, run_exploration
    from swarmex.missions.exploration.record import exploration_record

    check_output(json_path, "--json")
    check_output(render, "--render", RENDER_SUFFIXES)
    grid = load_world(map_path, empty, cell)
    params = ExplorationParams(
        robots=robots,
        laser_range=laser_range,
        comm_range=comm_range,
        strategy=strategy,
        robot_radius=robot_radius,
        beams=beams,
        starts=parse_starts(starts),
        seed=seed,
        max_ticks=max_ticks,
        aodv=aodv,
        conflict_yield=conflict_yield,
        plan_pause=plan_pause,
    )
    if processes:
        if render is not None:
            raise InputError("--render is not available with --processes (use swarmex monitor)")
        rec = run_mesh(grid, params, time_scale, loss=inject_loss, json_path=json_path)
        raise typer.Exit(0 if rec["complete"] else 1)
    if inject_loss:
        raise InputError("--inject-loss needs --processes")
    animate = render is not None and render.suffix.lower() in (".gif", ".mp4")
    recorder = FrameRecorder() if animate else None
    run = run_exploration(grid, params, on_frame=recorder, frame_every=1 if recorder else 0)
    record = exploration_record(run)
    m = record.metrics
    console.print(
        f"exploration/{strategy}: {robots} robot(s) on {grid.world.width}x{grid.world.height} "
        f"cells of {grid.cell:g} m — complete={run.complete}, {run.makespan} steps, "
        f"explored {m['explored_fraction']:.2%}, mean robot steps {m['mean_steps']:.1f}, "
        f"replans {m['replans']}, messages {m['messages_sent']} ({m['bytes_sent']} B), "
        f"{run.wall_seconds:.2f} s"
    )
    if json_path is not None:
        write_record(record, json_path)
    if render is not None:
        from swarmex.viz.exploration import exploration_animation, exploration_png

        if recorder is not None:
            recorder.finish(run)
            exploration_animation(recorder.frames, run, render)
        else:
            exploration_png(run, render)


@reproduce_app.command("exploration")
def reproduce_exploration(
    out: Path = typer.Option(Path("out/reproduce-exploration"), "--out"),
    quick: bool = typer.Option(False, "--quick", help="A small sweep in about a minute."),
    workers: int = typer.Option(2, "--workers", help="Worker processes."),
) -> None:
    """Rerun the thesis's chapter 4 (Figs. 4.1–4.4) and the strategy comparison."""
    from swarmex.studies.exploration import reproduce

    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")
    report = reproduce(out, quick=quick, workers=workers, progress=console.print)
    console.print(f"report: {report}")
