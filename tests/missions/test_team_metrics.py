"""Every mission declares the team metrics its records hold (``Mission.team_metrics``).

The declaration feeds the sweep's ``--metric`` check, ``swarmex.describe`` and docs/api.md,
so it must be exactly what the runs write: no metric a run writes is missing from it, and
none it lists is never written (across configurations that reach every metric: optimal's
solver figures, WMA-RRT's branches, PRM's reachable edges). ``numeric`` must match the
values' types, since it decides what a summary may average.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError
from swarmex.experiments.sweep_worker import flat_scalars
from swarmex.missions.registry import get

ROADMAP_ENV = {
    "bounds": [0, 0, 200, 150],
    "obstacles": [[[40, 30], [70, 30], [70, 60], [40, 60]]],
    "goal": [175, 130],
}


def runs(mission: str, tmp_path: Path) -> list[dict[str, Any]]:
    """Small runs that between them write every metric the mission has."""
    if mission == "traversal":
        cases = [dict(grid="5x4", agents=2), dict(grid="3x2", agents=2, algorithm="optimal")]
    elif mission == "foraging":
        cases = [dict(grid=16, agents=4, algorithm="strips"),
                 dict(grid=16, agents=4, algorithm="sectors", transport="end-to-end")]
    elif mission == "exploration":
        cases = [dict(empty="6x6", robots=2), dict(empty="8x8", robots=3, comm_range=2.0)]
    else:
        env = tmp_path / "env.json"
        env.write_text(json.dumps(ROADMAP_ENV), encoding="utf-8")
        common = dict(env=env, agents=2, nodes=40, step=15, sensor_range="inf")
        cases = [common, {**common, "task": "search"}, {**common, "planner": "prm"}]
    return [swarmex.run(mission, seed=1, **kw).metrics for kw in cases]


@pytest.mark.parametrize("mission", ["traversal", "foraging", "exploration", "roadmap"])
def test_declared_metrics_are_exactly_the_written_ones(mission: str, tmp_path: Path) -> None:
    declared = get(mission).team_metrics()
    written = runs(mission, tmp_path)
    seen: set[str] = set()
    for metrics in written:
        assert set(metrics) <= set(declared), set(metrics) - set(declared)
        seen |= set(metrics)
    assert seen == set(declared), set(declared) - seen
    for name, info in declared.items():
        values = [m[name] for m in written if m.get(name) is not None]
        number = all(isinstance(v, int | float) for v in values)  # bools are ints
        assert number == info.numeric, (name, values[:2])
        assert info.meaning and "|" not in info.meaning
        tables = [v for v in values if isinstance(v, dict)]
        assert bool(tables) == bool(info.keys), name  # every table declares its entries
        for table in tables:
            written_keys = set(flat_scalars(table))
            assert written_keys <= set(info.keys), (name, written_keys - set(info.keys))


def test_check_metric_accepts_numbers_and_names_what_is_wrong() -> None:
    traversal = get("traversal")
    for name in ("total_time_all", "metrics.total_time_all", "makespan", "wall_seconds"):
        traversal.check_metric(name)
    with pytest.raises(InputError, match="did you mean 'total_time_all'"):
        traversal.check_metric("total_time_al")
    with pytest.raises(InputError, match="not a metric of traversal records"):
        traversal.check_metric("coverage")
    with pytest.raises(InputError, match="an exploration record holds it as a list") as lst:
        get("exploration").check_metric("steps")
    assert "sweep columns" not in str(lst.value)  # a list has no columns to point to
    with pytest.raises(InputError, match=r"its entries are sweep columns unicasts\.KEY"):
        get("exploration").check_metric("unicasts")
    # a table metric's entries are numeric sweep columns (unicasts.sent): accepted
    for name in ("unicasts.sent", "messages_by_kind.SCAN.bytes", "replan_reasons.blocked",
                 "messages_by_kind.RREQ.messages", "metrics.unicasts.gap_requests"):
        get("exploration").check_metric(name)
    # ... and a misspelt entry is caught before the runs, with the nearest one
    with pytest.raises(InputError, match="unicasts has no entry 'delivred'.*'unicasts.delivered'"):
        get("exploration").check_metric("unicasts.delivred")
    with pytest.raises(InputError, match="messages_by_kind has no entry 'SCAN.byte'"):
        get("exploration").check_metric("messages_by_kind.SCAN.byte")
    with pytest.raises(InputError, match="replan_reasons has no entry 'nope'"):
        get("exploration").check_metric("replan_reasons.nope")


def test_describe_lists_the_metrics_with_their_meaning() -> None:
    text = swarmex.describe("foraging")
    assert "team metrics of its records" in text
    assert "exploration_time" in text and "until a robot first stands on the food" in text


def test_a_misspelt_sweep_metric_stops_before_any_run(tmp_path: Path, capsys) -> None:
    spec = tmp_path / "s.toml"
    spec.write_text(
        'mission = "traversal"\ngrid = "4x4"\nagents = [1, 2]\nseeds = [0, 1]\n',
        encoding="utf-8",
    )
    out = tmp_path / "out"
    code = main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                 "--summary", "--metric", "total_time_al"])
    err = capsys.readouterr().err
    assert code == 2
    assert "did you mean 'total_time_all'" in err and "Traceback" not in err
    assert not out.exists()  # nothing ran, nothing written


def test_foraging_all_informed_means_finished_communicating() -> None:
    """``all_informed`` is false when a robot has not finished communicating when the last
    unit is home, even though every robot knows the food (each has an ``informed_at``):
    its stated meaning ("every robot learnt the food location") said the opposite here."""
    rec = swarmex.run("foraging", seed=25, grid=16, agents=4, algorithm="strips",
                      food_units=1, trace=False)
    assert all(a.metrics["informed_at"] is not None for a in rec.agents)
    assert rec.metrics["all_informed"] is False
    meaning = get("foraging").team_metrics()["all_informed"].meaning
    assert "finished communicating" in meaning and "learnt" not in meaning
