"""``swarmex traverse`` and ``swarmex demo`` (seed 000's traversal mission)."""

from __future__ import annotations

from swarmex.cli.app import app, console


@app.command()
def demo() -> None:
    """Run MADGTA on an embedded generated map and print a summary."""
    from swarmex.missions.traversal import run_metrics, run_traversal, uniform_agents
    from swarmex.worlds import random_obstacles

    world = random_obstacles(12, 12, 0.15, seed=7)
    nest = int(next(iter((~world.blocked).nonzero()[0])))
    run = run_traversal(world, uniform_agents([nest] * 3, 2.0, 9.0), seed=0)
    totals, _ = run_metrics(run, 1.0)
    console.print(totals)
