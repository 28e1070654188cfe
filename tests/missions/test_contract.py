"""The Mission contract, checked over every registered mission (in the spirit of
PettingZoo's api_test): parameters round-trip through Python, TOML and the command line to
the same record; bad parameters are refused before any work; the same seed gives the same
record; the record has DESIGN.md's schema; the CLI's options are the Params' own.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import swarmex
from swarmex.cli import main
from swarmex.missions.registry import get

REPO = Path(__file__).resolve().parents[2]

# one small run per mission: Python values, and the same run as the CLI's strings
SAMPLES: dict[str, tuple[dict[str, Any], list[str]]] = {
    "traversal": (
        {"grid": (6, 5), "agents": 2, "nests": [(0, 0), (5, 4)], "obstacles": [(2, 2)]},
        ["--grid", "6x5", "--agents", "2", "--nests", "0,0;5,4", "--obstacles", "2,2"],
    ),
    "foraging": (
        {"grid": 16, "agents": 4, "algorithm": "sectors", "food": (12, 3), "food_units": 5},
        ["--grid", "16", "--agents", "4", "--algorithm", "sectors", "--food", "12,3",
         "--food-units", "5"],
    ),
    "exploration": (
        {"empty": (3, 3), "cell": 0.1, "robots": 2, "laser_range": 1.0, "comm_range": 2.0},
        ["--empty", "3x3", "--cell", "0.1", "--robots", "2", "--laser-range", "1.0",
         "--comm-range", "2.0"],
    ),
    "roadmap": (
        {"env": REPO / "examples" / "roadmap_fig8.json", "agents": 2, "nodes": 60, "step": 40.0,
         "sensor_range": "inf"},
        ["--env", str(REPO / "examples" / "roadmap_fig8.json"), "--agents", "2", "--nodes", "60",
         "--step", "40", "--sensor-range", "inf"],
    ),
}
SCHEMA = {"swarmex_version", "mission", "algorithm", "params", "seed", "world", "complete",
          "makespan", "time_unit", "metrics", "agents", "wall_seconds"}


def _strip(record: dict) -> dict:
    return {k: v for k, v in record.items() if k != "wall_seconds"}


def test_the_four_missions_are_registered():
    assert swarmex.missions() == ["exploration", "foraging", "roadmap", "traversal"]
    assert sorted(SAMPLES) == swarmex.missions()


@pytest.fixture(params=sorted(SAMPLES))
def mission(request):
    return request.param


def test_python_cli_and_toml_give_the_same_record(mission, tmp_path, capsys):
    values, argv = SAMPLES[mission]
    rec = swarmex.run(mission, seed=2, **values).to_dict()
    assert set(rec) >= SCHEMA and rec["mission"] == mission
    assert isinstance(rec["agents"], list) and rec["agents"]
    assert {"id", "metrics", "trajectory", "jobs"} <= set(rec["agents"][0])
    assert rec["time_unit"] in ("s", "step") and rec["seed"] == 2

    cli = tmp_path / "cli.json"
    assert main([get(mission).command, *argv, "--seed", "2", "--json", str(cli)]) in (0, 1)
    assert _strip(json.loads(cli.read_text())) == _strip(rec)

    toml = tmp_path / "s.toml"
    lines = [f'mission = "{mission}"', "seed = 2"]
    for key, value in values.items():
        lines.append(f"{key} = {_toml(value)}")
    toml.write_text("\n".join(lines) + "\n")
    out = tmp_path / "toml.json"
    assert main(["run", str(toml), "--json", str(out)]) in (0, 1)
    capsys.readouterr()
    assert _strip(json.loads(out.read_text())) == _strip(rec)


def _toml(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return repr(value)
    if isinstance(value, Path):
        return json.dumps(str(value))
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, tuple) and all(isinstance(v, int) for v in value):
        return "[" + ", ".join(str(v) for v in value) + "]"  # a point
    return "[" + ", ".join(json.dumps(",".join(map(str, c))) for c in value) + "]"


def test_same_seed_same_record(mission):
    values, _ = SAMPLES[mission]
    a = swarmex.run(mission, seed=5, **values).to_dict()
    b = swarmex.run(mission, seed=5, **values).to_dict()
    assert _strip(a) == _strip(b)


# per-agent metrics that only the per-step trace gives (None without it)
TRACE_DERIVED = {"foraging": {"moves"}}


def test_record_without_trace_keeps_every_metric(mission):
    """``trace=False`` (studies of many runs): same run and metrics, no per-step trace."""
    values, _ = SAMPLES[mission]
    full = swarmex.run(mission, seed=2, **values).to_dict()
    lean = swarmex.run(mission, seed=2, trace=False, **values).to_dict()
    assert any(a["trajectory"] for a in full["agents"])  # the sample has a trace to drop
    assert all(a["trajectory"] == [] and a["jobs"] == [] for a in lean["agents"])
    derived = TRACE_DERIVED.get(mission, set())
    for a_full, a_lean in zip(full["agents"], lean["agents"], strict=True):
        assert all(a_lean["metrics"][k] is None for k in derived)
        kept = {k: v for k, v in a_full["metrics"].items() if k not in derived}
        assert {k: a_lean["metrics"][k] for k in kept} == kept
    strip = lambda r: {k: v for k, v in _strip(r).items() if k != "agents"}  # noqa: E731
    assert strip(lean) == strip(full)


def test_unknown_keyword_names_the_nearest(mission):
    values, _ = SAMPLES[mission]
    first = next(iter(values))
    typo = first[:-1] if len(first) > 3 else first + "x"
    bad = {k: v for k, v in values.items() if k != first} | {typo: values[first]}
    with pytest.raises(swarmex.InputError, match=f"unknown parameter {typo!r}.*{first!r}"):
        swarmex.run(mission, **bad)


def test_bad_value_is_refused_before_work_naming_the_parameter(mission, monkeypatch):
    values, _ = SAMPLES[mission]
    m = get(mission)
    monkeypatch.setattr(type(m), "execute", lambda *a, **k: pytest.fail("ran"))
    team = "robots" if mission == "exploration" else "agents"
    # named as the Python keyword the caller wrote, not as the command line's flag
    with pytest.raises(swarmex.InputError, match=f"^{team}\\b"):
        swarmex.run(mission, **(values | {team: "many"}))
    with pytest.raises(swarmex.InputError, match=f"^{team}\\b"):
        swarmex.run(mission, **(values | {team: 0}))
    required = [o for o in m.params_type.options().values() if o.required]
    if required:
        with pytest.raises(swarmex.InputError, match=rf": {required[0].name}\b") as err:
            swarmex.run(mission, **{k: v for k, v in values.items() if k != required[0].name})
        assert "--" not in str(err.value)


def test_cli_options_are_the_params_options(mission):
    from swarmex.cli.app import load

    m = get(mission)
    command = load(m.command)
    flags = {o: p for p in command.params for o in getattr(p, "opts", ()) if o.startswith("--")}
    for info in m.params_type.options().values():
        assert info.flag in flags, f"{m.command} lacks {info.flag}"
        click_default = flags[info.flag].default
        if isinstance(info.default, int | float | str | bool) and not info.required:
            assert click_default == info.default, info.flag  # the default is the Params'
    assert "--json" in flags and "--render" in flags


def test_stop_run_from_on_frame_ends_the_run(mission):
    values, _ = SAMPLES[mission]
    frames: list[Any] = []

    def stop(frame: Any) -> None:
        frames.append(frame)
        if len(frames) == 3:
            raise swarmex.StopRun

    rec = swarmex.run(mission, on_frame=stop, **values)
    assert len(frames) == 3
    assert rec.complete is False
