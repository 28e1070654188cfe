"""``swarmex forage`` and ``swarmex reproduce foraging`` (seed 002's foraging mission).

Food placement: ``--food x,y`` puts it at a cell; ``--food-distance LO-HI`` draws a cell whose
distance from the nest lies in that band (percent of the corner–nest distance, ch. 6); with
neither, a uniformly random non-nest cell is drawn. Draws use ``numpy.random.default_rng(seed)``,
so a seed fixes the whole run. ``--food-units`` defaults to 100, the released simulator's
value (the thesis does not state its k). All input errors are raised before the run.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer
from rich.table import Table

from swarmex.cli.app import app, console, reproduce_app
from swarmex.cli.outputs import RENDER_SUFFIXES, check_output
from swarmex.errors import InputError


@app.command()
def forage(
    grid: int = typer.Option(..., "--grid", help="Grid side g (the grid is g×g)."),
    agents: int = typer.Option(..., "--agents", help="Number of robots n."),
    algorithm: str = typer.Option(
        ...,
        "--algorithm",
        help="strips|zigzag|hilbert|sectors|spiral|modified-zigzag, or rings (ours).",
    ),
    transport: str = typer.Option(
        "relay-food", "--transport", help="end-to-end|relay-food|relay-path."
    ),
    food: str | None = typer.Option(None, "--food", help="Food cell x,y."),
    food_distance: str | None = typer.Option(
        None, "--food-distance", help="Band LO-HI (percent of the corner–nest distance)."
    ),
    food_units: int = typer.Option(100, "--food-units", help="Units k at the food cell."),
    seed: int = typer.Option(0, "--seed", help="Seed of every random choice."),
    json_out: Path | None = typer.Option(None, "--json", help="Write the result record here."),
    render: Path | None = typer.Option(
        None, "--render", help="Draw the run (.png) or animate it (.gif, .mp4)."
    ),
) -> None:
    """Find food on a g×g grid, spread the word, carry k units home (seed 002)."""
    from swarmex.engine.record import write_record
    from swarmex.missions.foraging import run_forage, to_record
    from swarmex.missions.foraging.food import parse_cell, sample_food
    from swarmex.missions.foraging.run import check_inputs

    algorithm = algorithm.strip().lower()
    transport = transport.strip().lower()
    check_inputs(algorithm, grid, agents, food_units, transport)
    if food is not None and food_distance is not None:
        raise InputError("give at most one of --food and --food-distance")
    check_output(json_out, "--json")
    check_output(render, "--render", RENDER_SUFFIXES)
    rng = np.random.default_rng(seed)
    if food is not None:
        cell = parse_cell(food, grid)
    else:
        cell = sample_food(grid, food_distance or "random", rng)[0]
    run = run_forage(algorithm, grid, agents, cell, food_units, transport)
    params = {"food_distance": food_distance, "seed": seed}
    record = to_record(run, seed, params)
    m = run.metrics
    table = Table(title=f"foraging · {algorithm} · n={agents} · g={grid} · food {cell}")
    for key in ("exploration_time", "communication_time", "comm_transport_overlap"):
        table.add_column(key.replace("_", " "))
    table.add_column("transport time")
    table.add_column("total")
    table.add_column("delivered")
    table.add_row(
        str(m["exploration_time"]),
        str(m["communication_time"]),
        str(m["comm_transport_overlap"]),
        str(m["transport_time"]),
        str(m["total_time"]),
        f"{m['food_delivered']}/{food_units}",
    )
    console.print(table)
    if json_out is not None:
        write_record(record, json_out)
        console.print(f"record → {json_out}")
    if render is not None:
        from swarmex.viz.foraging import render_run

        render_run(record.to_dict(), render)
        console.print(f"drawing → {render}")


@reproduce_app.command("foraging")
def reproduce_foraging(
    out: Path = typer.Option(Path("reproduction-foraging"), "--out", help="Output directory."),
    quick: bool = typer.Option(
        False, "--quick", help="One food cell per band: a smoke test, well under a minute."
    ),
    workers: int = typer.Option(2, "--workers", help="Worker processes."),
    seed: int = typer.Option(2015, "--seed", help="Seed of the food positions."),
) -> None:
    """Regenerate Figs. 56–79 of seed 002 (128×128 grid) beside the thesis's numbers."""
    from swarmex.studies.foraging import reproduce

    if workers < 1:
        raise InputError(f"--workers must be at least 1 (got {workers})")
    report = reproduce(out, quick=quick, workers=workers, seed=seed)
    console.print(f"report → {report}")
