"""``swarmex roadmap`` and ``swarmex reproduce roadmap`` (seed 004: WMA-RRT against PRM)."""

from __future__ import annotations

from pathlib import Path

import typer

from swarmex.cli.app import app, console, reproduce_app
from swarmex.cli.outputs import RENDER_SUFFIXES, check_output


@app.command()
def roadmap(
    env: Path = typer.Option(..., "--env", help="JSON polygons, MovingAI .map or image."),
    task: str = typer.Option("coverage", "--task", help="coverage | search"),
    planner: str = typer.Option(
        "wma-rrt", "--planner", help="wma-rrt | prm | wma-rrt-takeover (improved helpers)"
    ),
    agents: int = typer.Option(..., "--agents", help="Number of agents (= branches)."),
    nodes: int = typer.Option(..., "--nodes", help="Roadmap nodes K (Main Root excluded)."),
    step: float = typer.Option(..., "--step", help="Step size ε between nodes."),
    sensor_range: str = typer.Option(
        ...,
        "--sensor-range",
        help="Sensor range R, a multiple of the step ('1eps', '2eps'), or 'inf'.",
    ),
    goal: str = typer.Option(None, "--goal", help="Goal 'x,y' (search)."),
    starts: str = typer.Option(None, "--starts", help="Starts 'x,y;x,y;…'."),
    seed: int = typer.Option(0, "--seed"),
    step_budget: int = typer.Option(
        None, "--step-budget", help="Stop after this many steps (PRM default: 2K)."
    ),
    raster: int = typer.Option(256, "--raster", help="Coverage raster cells on the long side."),
    json_out: Path = typer.Option(None, "--json", help="Write the result record here."),
    render: Path = typer.Option(None, "--render", help="Write a .png, .gif or .mp4 of the run."),
) -> None:
    """Coverage or goal search by a team on a WMA-RRT (or PRM) roadmap."""
    from swarmex.engine.record import write_record
    from swarmex.missions.roadmap.scenario import make_scenario, run_scenario

    check_output(json_out, "--json")
    check_output(render, "--render", RENDER_SUFFIXES)
    sc = make_scenario(
        env,
        agents=agents,
        nodes=nodes,
        step=step,
        sensor_range=sensor_range,
        task=task,
        planner=planner,
        goal=goal,
        starts=starts,
        seed=seed,
        step_budget=step_budget,
        raster_cells=raster,
    )
    run, rec = run_scenario(sc)
    m = rec.metrics
    line = (
        f"{rec.algorithm} {sc.task}: complete={rec.complete} steps={m['steps']} "
        f"coverage={100 * m['coverage']:.1f}% nodes={m['tree_nodes']} "
        f"components={m['components']} cycles={m['cycles']} "
        f"edge_revisits={m['edge_revisits']} path={m['path_length']:.0f}"
    )
    if sc.task == "search":
        line += f" goal_found={m['goal_found']} goal_unreachable={m['goal_unreachable']}"
    console.print(line, highlight=False)
    if json_out is not None:
        write_record(rec, json_out)
    if render is not None:
        from swarmex.viz.roadmap_plot import render as draw

        draw(run, render)


@reproduce_app.command("roadmap")
def reproduce_roadmap(
    out: Path = typer.Option(Path("reproduction/roadmap"), "--out", help="Output directory."),
    quick: bool = typer.Option(False, "--quick", help="A few runs per row (under a minute)."),
) -> None:
    """Tables 1–2, Fig. 6 and Figs. 14–17 of seed 004, beside the paper's numbers."""
    from swarmex.studies.roadmap import reproduce

    reproduce(out, quick=quick, console=console)
