"""Params as a library user handles them: copied with changes, built by their constructor.

``dataclasses.replace(params, grid="12x12")`` and ``TraversalParams(grid="8x8", ...)`` skip
the parsers; the run used to get a string where it expects a tuple and fail deep inside with
"too many values to unpack". ``Params.replace`` parses and checks, and ``Mission.run`` reruns
the parsers on Params that did not go through them.
"""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

import swarmex
from swarmex.errors import InputError
from swarmex.missions.registry import get
from swarmex.missions.traversal.params import TraversalParams


def _key(record: swarmex.ResultRecord) -> dict:
    data = record.to_dict()
    data.pop("wall_seconds")
    return data


def test_dataclasses_replace_with_a_cli_string_runs_like_the_parsed_value() -> None:
    m = get("traversal")
    base = m.params(grid="8x8", agents=3)
    via_replace = m.run(dataclasses.replace(base, grid="6x5")).record
    parsed = m.run(m.params(grid="6x5", agents=3)).record
    assert _key(via_replace) == _key(parsed)


def test_constructor_params_are_parsed_and_checked_before_the_run() -> None:
    m = get("traversal")
    record = m.run(TraversalParams(grid="5x5", agents=2)).record  # type: ignore[arg-type]
    assert record.params["grid"] == "5x5" and record.complete
    with pytest.raises(swarmex.InputError, match="--algorithm must be one of"):
        m.run(TraversalParams(grid=(5, 5), agents=2, algorithm="nearst"))
    with pytest.raises(swarmex.InputError, match="exactly one of --map"):
        m.run(TraversalParams(agents=2))
    foraging = get("foraging")
    good = foraging.params(grid=16, agents=4, algorithm="sectors")
    with pytest.raises(swarmex.InputError, match="outside the 16×16 grid"):
        foraging.run(dataclasses.replace(good, food=(99, 99)))


def test_params_replace_parses_checks_and_keeps_the_rest() -> None:
    m = get("traversal")
    base = m.params(grid="8x8", agents=3, nests="0,0;1,1", travel_time=3)
    copy = base.replace(grid="12x12", agents="4")
    assert copy == m.params(grid=(12, 12), agents=4, nests=[(0, 0), (1, 1)], travel_time=3.0)
    assert base.grid == (8, 8)  # frozen: the original is untouched
    with pytest.raises(swarmex.InputError, match="^agents must be at least 1"):
        base.replace(agents=0)
    with pytest.raises(swarmex.InputError, match="did you mean 'agents'"):
        base.replace(agnts=2)
    exploration = get("exploration").params(empty="4x4", cell=0.1, robots=2)
    changed = exploration.replace(robots=3, plan_period=10)  # plan_period: not an option
    assert (changed.robots, changed.plan_period, changed.empty) == (3, 10, (4.0, 4.0))


def test_validated_params_pickle_and_compare_as_before() -> None:
    p = get("foraging").params(grid=16, agents=4, algorithm="sectors")
    assert p.validated() is p  # from_values' Params are not parsed again
    q = pickle.loads(pickle.dumps(p))
    assert q == p and repr(q) == repr(p)
    assert "_swarmex" not in repr(p) and "_swarmex" not in str(dataclasses.asdict(p))


@pytest.mark.parametrize(("kw", "message"), [
    ({"on_frame": 5}, "on_frame must be a function of one frame"),
    ({"trace": "false"}, "trace must be True or False"),
    ({"trace": None}, "trace must be True or False"),
])
def test_run_refuses_a_bad_on_frame_or_trace_before_any_work(kw: dict, message: str) -> None:
    # on_frame=5 was a TypeError from the first frame; trace="false" silently kept the trace
    with pytest.raises(swarmex.InputError, match=message):
        swarmex.run("traversal", grid="4x4", agents=1, **kw)


def test_run_refuses_seed_none() -> None:
    # seed=None (numpy's "fresh entropy") silently ran seed 0
    with pytest.raises(swarmex.InputError, match="seed=None"):
        swarmex.run("traversal", grid="4x4", agents=1, seed=None)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("key", "hint"),
    [("json", r"record\.write\(path\)"), ("render", r"swarmex\.render\(record, path\)"),
     ("max_cycles", r"no cycle cap; .*foraging's max_rounds")],  # was "did you mean 'obstacles'?"
)
def test_a_key_that_is_no_run_parameter_says_what_to_do_instead(key: str, hint: str) -> None:
    # render= was "unknown parameter 'render'; did you mean 'center'?"
    with pytest.raises(swarmex.InputError, match=f"'{key}' is not a parameter of the run.*{hint}"):
        swarmex.run("traversal", grid="4x4", agents=1, **{key: "out"})


def test_every_missing_required_parameter_is_named_at_once() -> None:
    # roadmap needs five; a Python user used to learn them one error at a time
    with pytest.raises(swarmex.InputError, match=r"^roadmap: env, agents, nodes, step"
                                                 r" and sensor_range are required$"):
        swarmex.run("roadmap")
    with pytest.raises(swarmex.InputError, match=r"^roadmap: agents and sensor_range are"
                                                 r" required$"):
        swarmex.run("roadmap", env="e.json", nodes=5, step=1)
    with pytest.raises(swarmex.InputError, match=r"^foraging: algorithm is required$"):
        swarmex.run("foraging", grid=16, agents=4)
    # a world is one of several options: it was asked for only after the rest was fixed
    # (exploration: "robots is required", then "give exactly one of map and empty")
    with pytest.raises(swarmex.InputError, match=r"^exploration: robots and map \(or"
                                                 r" empty\) are required$"):
        swarmex.run("exploration")
    with pytest.raises(swarmex.InputError, match=r"^traversal: map \(or grid, center\)"
                                                 r" and agents \(or fleet\) are required$"):
        swarmex.run("traversal")
    # the Mission object's own parser is the command line's too: it names the flags
    with pytest.raises(swarmex.InputError, match=r"^traversal: --map \(or --grid, --center\)"
                                                 r" and --agents \(or --fleet\) are required$"):
        get("traversal").params_type.from_values({})
    with pytest.raises(swarmex.InputError, match="give exactly one of map and empty$"):
        swarmex.run("exploration", robots=2, map="x.map", empty="4x4")  # two: still refused


def test_the_command_line_names_every_missing_option_at_once(capsys) -> None:
    """Typer's own required check named one missing option per try; the Params name all,
    and --help still marks them required."""
    from swarmex.cli import main

    assert main(["forage"]) == 2
    err = capsys.readouterr().err
    assert err == "swarmex: error: foraging: --grid, --agents and --algorithm are required\n"
    assert main(["roadmap", "--agents", "2"]) == 2
    assert "--env, --nodes, --step and --sensor-range are required" in capsys.readouterr().err
    assert main(["forage", "--help"]) == 0
    assert "Number of robots n. (required)" in capsys.readouterr().out


@pytest.mark.parametrize("value", [(5, 5), [5, 5], np.array([5, 5]), "5,5", [(5, 5)], ["5,5"]])
def test_one_cell_alone_is_a_list_of_one_cell(value) -> None:
    # a sweep axis of cells (nests = [[0, 0], [5, 5]]) gives each run one (x, y) pair, which
    # failed with "malformed cell 0"
    from swarmex.missions.base import cells

    assert cells()(value, "--nests") == ((5, 5),)


@pytest.mark.parametrize("value", [(5, 5, 5), (5.5, 2), (True, 1), [5]])
def test_a_malformed_cell_list_is_still_refused(value) -> None:
    from swarmex.missions.base import cells

    with pytest.raises(InputError, match="--nests: malformed cell"):
        cells()(value, "--nests")


def test_a_sweep_axis_of_cell_pairs_runs_one_nest_per_run(tmp_path) -> None:
    with pytest.warns(UserWarning, match="nests is an axis of 2 values, one per run"):
        table = swarmex.sweep("traversal", out=tmp_path / "s", grid="8x8", agents=2,
                              nests=[(0, 0), (5, 5)], backend="serial", progress=False)
    assert table.column("error").to_pylist() == [None, None]
    assert table.column("nests").to_pylist() == ["0,0", "5,5"]


@pytest.mark.parametrize("params", [{"grid": "8x8", "agents": 3}, None, "grid=8x8"])
def test_mission_run_names_the_params_it_takes(params) -> None:
    # a dict or None met an AttributeError ('dict' object has no attribute 'validated')
    with pytest.raises(InputError, match=r"traversal: run\(\) takes TraversalParams \(from "
                                         r"get\('traversal'\)\.params\(\.\.\.\)\), got "):
        get("traversal").run(params)
    foraging = get("foraging").params(grid=8, agents=2, algorithm="strips")
    with pytest.raises(InputError, match="got ForagingParams"):
        get("traversal").run(foraging)


def test_python_surfaces_name_keywords_and_the_command_line_names_flags(tmp_path, capsys) -> None:
    """The parsers are the command line's, so their messages name flags; a Python caller
    got "--job-time must be at least 0", a name it cannot write. Every Python surface now
    names the keyword, and the command line keeps its flags."""
    from swarmex.cli import main
    from swarmex.envs import traversal_v0

    said = "^job_time must be at least 0, got -2$"
    with pytest.raises(InputError, match=said):
        swarmex.run("traversal", grid="4x4", agents=1, job_time=-2)
    rec = swarmex.run("traversal", grid="4x4", agents=1)
    with pytest.raises(InputError, match=said):
        swarmex.rerun(rec, job_time=-2)
    with pytest.raises(InputError, match=said):
        get("traversal").params(grid="4x4", agents=1).replace(job_time=-2)
    with pytest.raises(InputError, match="^swarmex.sweep: " + said[1:]):
        swarmex.sweep("traversal", out=tmp_path / "s", grid="4x4", agents=1, job_time=[1, -2],
                      backend="serial", progress=False)
    with pytest.raises(InputError, match=said):
        traversal_v0.env(grid="4x4", agents=1, job_time=-2)
    # a metavar goes with its flag; a world check (after parsing) is renamed too
    with pytest.raises(InputError, match="^give exactly one of map, grid or center$"):
        swarmex.run("traversal", grid="4x4", map="x.map", agents=1)
    with pytest.raises(InputError, match=r"^nests: cell \(0,9\) is outside the 4x4 map$"):
        swarmex.run("traversal", grid="4x4", agents=1, nests="0,9")
    assert main(["traverse", "--grid", "4x4", "--agents", "1", "--job-time", "-2"]) == 2
    assert capsys.readouterr().err == "swarmex: error: --job-time must be at least 0, got -2\n"
