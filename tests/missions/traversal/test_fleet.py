"""Heterogeneous fleets (issue 15, item 1): per-agent values by id from a TOML or CSV file,
``[[agents]]`` tables in a scenario, or Python; all give the same record, which shows each
agent's parameters; a bad row is one line naming the row's id and the field, exit 2."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError
from swarmex.missions.traversal.agents import AgentSpec
from swarmex.missions.traversal.optimal import optimal_record
from swarmex.worlds import GridWorld

# seed 000 §4.3's example, in m/s: D01 nest 2 (here a cell), 5 m, 300 cm/s, 10 s, 150 / 30
# cm/s; D02 higher and slower, 12 s a job, faster up and down; D03 takes the defaults but
# its job time
FLEET = [
    {"id": 1, "nest": [0, 0], "altitude": 5.0, "travel_speed": 3.0, "job_time": 10.0,
     "up_speed": 1.5, "down_speed": 0.3},
    {"id": 2, "nest": [4, 3], "altitude": 15.0, "travel_speed": 2.0, "job_time": 12.0,
     "up_speed": 2.5, "down_speed": 0.5},
    {"id": 3, "job_time": 6.0},
]
BASE: dict[str, Any] = {"grid": (5, 4), "obstacles": [(2, 1), (2, 2)], "edge_length": 6.67}
BASE_ARGV = ["--grid", "5x4", "--obstacles", "2,1;2,2", "--edge-length", "6.67"]


def _csv(rows: list[dict[str, Any]], path: Path) -> Path:
    cols = ["id", "nest", "altitude", "travel_speed", "job_time", "up_speed", "down_speed"]
    lines = [",".join(cols)]
    for r in reversed(rows):  # any order: rows are by id
        cells = []
        for c in cols:
            v = r.get(c)
            cells.append("" if v is None else f'"{v[0]},{v[1]}"' if c == "nest" else str(v))
        lines.append(",".join(cells))
    path.write_text("\n".join(lines) + "\n")
    return path


def _toml_tables(rows: list[dict[str, Any]]) -> str:
    out = []
    for r in rows:
        out.append("[[agents]]")
        out += [f"{k} = {json.dumps(v)}" for k, v in r.items()]
    return "\n".join(out) + "\n"


def _strip(rec: dict) -> dict:
    return {k: v for k, v in rec.items() if k != "wall_seconds"}


def _cli_record(argv: list[Any], tmp_path: Path, capsys: Any, name: str) -> dict:
    out = tmp_path / f"{name}.json"
    assert main([str(a) for a in argv] + ["--json", str(out)]) in (0, 1)
    capsys.readouterr()
    return json.loads(out.read_text())


@pytest.mark.parametrize("algorithm", ["madgta", "optimal"])
def test_a_mixed_fleet_is_the_same_from_a_file_a_scenario_and_python(
    algorithm: str, tmp_path: Path, capsys: Any
) -> None:
    py = swarmex.run("traversal", seed=4, algorithm=algorithm, fleet=FLEET, **BASE).to_dict()
    also = swarmex.run("traversal", seed=4, algorithm=algorithm, agents=FLEET, **BASE)
    assert _strip(also.to_dict()) == _strip(py)

    csv_file = _csv(FLEET, tmp_path / "fleet.csv")
    toml_file = tmp_path / "fleet.toml"
    toml_file.write_text(_toml_tables(FLEET))
    for fleet_file in (csv_file, toml_file):
        assert _strip(swarmex.run("traversal", seed=4, algorithm=algorithm, fleet=fleet_file,
                                  **BASE).to_dict()) == _strip(py)
        rec = _cli_record(["traverse", *BASE_ARGV, "--fleet", fleet_file, "--seed", 4,
                           "--algorithm", algorithm], tmp_path, capsys, "cli")
        assert _strip(rec) == _strip(py)

    scenario = tmp_path / "s.toml"
    scenario.write_text(
        f'mission = "traversal"\ngrid = "5x4"\nobstacles = "2,1;2,2"\nedge_length = 6.67\n'
        f'seed = 4\nalgorithm = "{algorithm}"\n' + _toml_tables(FLEET)
    )
    assert _strip(_cli_record(["run", scenario], tmp_path, capsys, "toml")) == _strip(py)

    # the record shows every agent's parameters, the options filling the gaps
    fleet = py["params"]["fleet"]
    assert [r["id"] for r in fleet] == [1, 2, 3]
    assert fleet[0] == {"id": 1, "nest": [0, 0], "altitude": 5.0,
                        "travel_time": pytest.approx(6.67 / 3.0), "travel_speed": 3.0,
                        "job_time": 10.0, "up_speed": 1.5, "down_speed": 0.3}
    assert fleet[1]["nest"] == [4, 3] and fleet[1]["travel_speed"] == 2.0
    assert fleet[2] == {"id": 3, "nest": [0, 0], "altitude": 0.0, "travel_time": 2.22,
                        "travel_speed": pytest.approx(6.67 / 2.22), "job_time": 6.0,
                        "up_speed": 1.5, "down_speed": 0.3}
    assert py["complete"]


def test_the_optimum_uses_each_agents_own_values() -> None:
    """The mission hands the MILP the fleet's specs: the same optimum as the solver called
    directly on those AgentSpecs (metres: edges of 6.67 m)."""
    rec = swarmex.run("traversal", seed=4, algorithm="optimal", fleet=FLEET, **BASE).to_dict()
    free = np.ones((4, 5), dtype=bool)
    free[1:3, 2] = False  # the obstacles (2,1) and (2,2)
    world = GridWorld(free)
    specs = [
        AgentSpec(0, 3.0, 10.0, 5.0, 1.5, 0.3),
        AgentSpec(world.node(4, 3), 2.0, 12.0, 15.0, 2.5, 0.5),
        AgentSpec(0, 6.67 / 2.22, 6.0, 0.0, 1.5, 0.3),
    ]
    direct = optimal_record(world, specs, "sum", 4, {}, 6.67).to_dict()
    assert rec["metrics"]["total_time_all"] == pytest.approx(direct["metrics"]["total_time_all"])
    assert [a["metrics"] for a in rec["agents"]] == [a["metrics"] for a in direct["agents"]]
    # a slower agent with longer jobs is worth less: the optimum gives it fewer jobs
    jobs = [a["metrics"]["nodes_done"] for a in rec["agents"]]
    assert jobs[1] <= jobs[0]


def test_identical_rows_are_the_uniform_team() -> None:
    uniform = swarmex.run("traversal", grid=(6, 6), agents=3, seed=1).to_dict()
    fleet = swarmex.run("traversal", grid=(6, 6), fleet=[{"id": i} for i in (1, 2, 3)],
                        seed=1).to_dict()
    assert fleet["params"].pop("fleet")[1]["travel_time"] == 2.22
    assert _strip(fleet) == _strip(uniform)


def test_missing_nests_follow_the_nests_option_round_robin() -> None:
    rec = swarmex.run("traversal", grid=(6, 6), nests=[(0, 0), (5, 5)], seed=1,
                      fleet=[{"id": 1}, {"id": 2}, {"id": 3, "nest": "3,3"}]).to_dict()
    assert rec["params"]["nests"] == [[0, 0], [5, 5], [3, 3]]
    assert [r["nest"] for r in rec["params"]["fleet"]] == [[0, 0], [5, 5], [3, 3]]


BAD_ROWS = [
    ("id,job_time\n1,10\n2,abc\n", "agent 2: job_time: expected a number, got 'abc'"),
    ("id,job_time\n1,10\n2,-1\n", "agent 2: job_time must be at least 0"),
    ("id,travel_time\n1,2\n2,0\n", "agent 2: travel_time must be greater than 0"),
    ("id,job_time\n1,10\n2,1e308\n", "agent 2: job_time must be at most 1e+09"),
    ("id,id\n1,2\n", "column 'id' is given twice"),
    ("id,job-time,job_time\n1,2,3\n", "column 'job_time' is given twice"),
    ("id,up_speed\n1,1e-300\n", "agent 1: up_speed must be at least 0.001"),
    ("id,nest\n1,\"0,0\"\n2,\"2,1\"\n", "agent 2: nest (2,1) is an obstacle"),
    ("id,nest\n1,\"0,0\"\n2,\"9,1\"\n", "agent 2: nest: cell (9,1) is outside the 5x4 map"),
    ("id,nest\n1,\"0,0\"\n2,x\n", "agent 2: nest: malformed cell 'x'"),
    ("id,altitude\n1,5\n1,6\n", "agent 1: id: listed twice"),
    ("id,altitude\n1,5\nD03,6\n", "agent 3: id: the ids of 2 agents are 1..2"),
    ("id,altitude\n1,5\nfoo,6\n", "row 2: id: expected an agent number"),
    ("id,altitude\n1,5\n,6\n", "row 2: id: missing"),
    ("id,speed\n1,5\n", "unknown column 'speed'"),
    ("id,travel_speed,travel_time\n1,3,2\n", "agent 1: travel_speed: give travel_speed or"),
]


@pytest.mark.parametrize(("text", "message"), BAD_ROWS)
def test_a_bad_row_exits_2_with_one_line_naming_the_row_and_the_field(
    text: str, message: str, tmp_path: Path, capsys: Any
) -> None:
    path = tmp_path / "fleet.csv"
    path.write_text(text)
    code = main(["traverse", *BASE_ARGV, "--fleet", str(path)])
    out, err = capsys.readouterr()
    assert code == 2, out
    assert err.count("\n") == 1 and err.startswith("swarmex: error: --fleet"), err
    assert message in err, err


def test_bad_toml_rows_and_fleet_conflicts() -> None:
    with pytest.raises(InputError, match=r"agent 2: unknown field 'jobtime'; did you mean"):
        swarmex.run("traversal", grid=(4, 4), fleet=[{"id": 1}, {"id": 2, "jobtime": 3}])
    with pytest.raises(InputError, match="agents 3 but the fleet lists 2 agents"):
        swarmex.run("traversal", grid=(4, 4), agents=3, fleet=[{"id": 1}, {"id": 2}])
    with pytest.raises(InputError, match="travel_speed \\(m/s\\) needs a length scale"):
        swarmex.run("traversal", grid=(4, 4), fleet=[{"id": 1, "travel_speed": 3}])
    with pytest.raises(InputError, match=r"agents \(or fleet\) is required"):
        swarmex.run("traversal", grid=(4, 4))
    with pytest.raises(InputError, match="not both"):
        swarmex.run("traversal", grid=(4, 4), agents=[{"id": 1}], fleet=[{"id": 1}])
