"""A record read back from its JSON (what --json writes) is the same record again."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import pytest

import swarmex
from swarmex.cli import main
from swarmex.engine import ResultRecord, read_record, write_record
from swarmex.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
RUNS = {
    "traversal": {"grid": "6x5", "agents": 2},
    "foraging": {"grid": 16, "agents": 4, "algorithm": "sectors", "food_units": 5},
    "exploration": {"empty": "3x3", "cell": 0.1, "robots": 2, "laser_range": 1.0},
    "roadmap": {"env": EXAMPLES / "roadmap_fig8.json", "agents": 2, "nodes": 60, "step": 40.0,
                "sensor_range": "inf"},
}


@pytest.mark.parametrize("mission", sorted(RUNS))
def test_from_dict_gives_back_the_same_record(mission: str, tmp_path: Path) -> None:
    record = swarmex.run(mission, seed=2, **RUNS[mission])
    path = write_record(record, tmp_path / "r.json")
    back = ResultRecord.from_dict(read_record(path))
    assert back.to_dict() == record.to_dict()
    assert write_record(back, tmp_path / "again.json").read_text() == path.read_text()
    assert back.agents[0].id == record.agents[0].id and back.metrics == record.to_dict()["metrics"]
    assert pickle.loads(pickle.dumps(back)).to_dict() == record.to_dict()


def test_from_dict_reads_the_command_lines_json(tmp_path: Path) -> None:
    out = tmp_path / "run.json"
    assert main(["traverse", "--grid", "5x4", "--agents", "2", "--seed", "4",
                 "--json", str(out)]) == 0
    back = ResultRecord.from_dict(json.loads(out.read_text()))
    assert back.mission == "traversal" and back.complete and back.seed == 4
    assert back.agents[1].trajectory == json.loads(out.read_text())["agents"][1]["trajectory"]


@pytest.mark.parametrize(("data", "message"), [
    ([], "a record is a JSON object"),
    ({"mission": "traversal"}, "not a swarmex record: no 'algorithm'"),
])
def test_from_dict_refuses_what_is_not_a_record(data: object, message: str) -> None:
    with pytest.raises(InputError, match=message):
        ResultRecord.from_dict(data)  # type: ignore[arg-type]


@pytest.mark.parametrize("mission", sorted(RUNS))
def test_records_in_memory_hold_plain_python_values(mission: str) -> None:
    """What a user prints is what the JSON holds: no numpy scalars (traversal's per-agent
    travel_time and total_time were np.float64)."""
    record = swarmex.run(mission, seed=2, **RUNS[mission])
    for metrics in [record.metrics, *(a.metrics for a in record.agents)]:
        for key, value in metrics.items():
            assert value is None or type(value) in (int, float, bool, str, list, dict), key


def test_repr_is_one_line_that_does_not_grow_with_the_trace() -> None:
    """A REPL or notebook shows a record by its repr: the dataclass's printed every
    trajectory row (hundreds of MB for a 1024² run). It must stay one short line naming the
    run, however long the trace, and the notebook view a table of the team metrics."""
    small = swarmex.run("traversal", grid="4x4", agents=2, seed=1)
    large = swarmex.run("traversal", grid="24x24", agents=2, seed=1)
    assert sum(len(a.trajectory) for a in large.agents) > 500
    for rec in (small, large):
        text = repr(rec)
        assert "\n" not in text and len(text) < 400
        assert text.startswith("<ResultRecord traversal madgta, seed 1: complete, makespan ")
        assert f"makespan {rec.makespan:.4g} s, 2 agents" in text
        assert f"total_time_all={rec.metrics['total_time_all']:.4g}" in text
        rows = len(rec.agents[0].trajectory)
        assert f"trajectory=<{rows} rows>" in repr(rec.agents[0])
        html = rec._repr_html_()
        assert html.count("<tr>") == len(rec.metrics)
    assert "steps" in repr(swarmex.run("foraging", grid=16, agents=4, algorithm="strips", seed=1))


def test_notebook_view_shows_every_metric_and_escapes_it() -> None:
    """The notebook table left out a table metric (exploration's ``unicasts``) without a
    word, said "makespan 69 step" where the repr says "steps", and "1 agents"; a record with
    no metrics printed "metrics >"."""
    rec = swarmex.run("exploration", empty="3x3", robots=1, seed=1)
    html = rec._repr_html_()
    assert html.count("<tr>") == len(rec.metrics)
    assert "<code>unicasts</code></td><td>sent=" in html
    assert " steps, 1 agent<table>" in html and " steps, 1 agent;" in repr(rec)
    data = rec.to_dict()
    data["algorithm"] = "<b>&"
    data["metrics"] = {"<k>": {"a<": "<v>"}, "series": [1, 2, 3]}
    odd = swarmex.ResultRecord.from_dict(data)
    html = odd._repr_html_()
    assert "&lt;b&gt;&amp;" in html and "a&lt;=&lt;v&gt;" in html and "[3 values]" in html
    assert "<k>" not in html and repr(odd).endswith("metrics 2 not numbers>")
    data["metrics"] = {}
    assert repr(swarmex.ResultRecord.from_dict(data)).endswith("; metrics none>")
    data["metrics"] = {"a": 1, "b": 2.5}  # every one shown: it printed "b=2.5none"
    assert repr(swarmex.ResultRecord.from_dict(data)).endswith("; metrics a=1, b=2.5>")


def test_read_and_write_are_the_command_lines_json(tmp_path: Path) -> None:
    rec = swarmex.run("traversal", grid="5x4", agents=2, seed=3)
    assert rec.write(tmp_path / "py.json") == tmp_path / "py.json"
    assert main(["traverse", "--grid", "5x4", "--agents", "2", "--seed", "3",
                 "--json", str(tmp_path / "cli.json")]) == 0
    a, b = (json.loads((tmp_path / n).read_text()) for n in ("py.json", "cli.json"))
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
    assert ResultRecord.read(tmp_path / "py.json").to_dict() == rec.to_dict()
    with pytest.raises(InputError, match="record not found"):
        ResultRecord.read(tmp_path / "none.json")
