"""``swarmex.sweep``: the sweep from Python, a thin layer on the same spec and runner as
``swarmex sweep SPEC.toml``. Each row is checked against ``swarmex.run`` with the row's
parameters and seed (an independent route to the same record)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import swarmex
from swarmex.errors import InputError


def test_rows_are_the_runs_of_the_product(tmp_path: Path) -> None:
    out = tmp_path / "s"
    table = swarmex.sweep("traversal", out=out, algorithm=["madgta", "nearest"],
                          grid=(6, 6), agents=range(2, 4), seeds=2, backend="serial")
    rows = table.to_pylist()
    assert len(rows) == 2 * 2 * 2
    assert {(r["algorithm"], r["agents"], r["seed"]) for r in rows} == {
        (a, n, s) for a in ("madgta", "nearest") for n in (2, 3) for s in (0, 1)
    }
    for row in rows:
        assert row["error"] is None
        rec = swarmex.run("traversal", seed=row["seed"], algorithm=row["algorithm"],
                          grid=(6, 6), agents=row["agents"])
        assert row["makespan"] == rec.makespan
        assert row["total_time_all"] == rec.metrics["total_time_all"]
    stamps = {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*.json")}
    again = swarmex.sweep("traversal", out=out, algorithm=["madgta", "nearest"],
                          grid=(6, 6), agents=range(2, 4), seeds=2, backend="serial")
    assert again.to_pylist() == rows  # resumed: nothing ran again
    assert {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*.json")} == stamps


def test_fixed_values_and_a_list_of_tuples(tmp_path: Path) -> None:
    table = swarmex.sweep("traversal", out=tmp_path / "s", grid=[(5, 5), (6, 4)], agents=2,
                          seeds=[7], fixed={"nests": [[0, 0], [3, 3]]}, backend="serial")
    rows = table.to_pylist()
    assert len(rows) == 2 and all(r["seed"] == 7 for r in rows)
    record = json.loads(next((tmp_path / "s" / "runs").glob("*.json")).read_text())
    assert record["params"]["nests"] == [[0, 0], [3, 3]]


def test_bad_input_fails_before_any_run(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="agnts"):
        swarmex.sweep("traversal", out=tmp_path / "a", grid="6x6", agnts=[2, 3])
    with pytest.raises(InputError, match="cannot be swept"):
        swarmex.sweep("traversal", out=tmp_path / "b", map=object(), agents=2)
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


@pytest.mark.parametrize("kw, said", [
    (dict(seed=3), r"swarmex.sweep: seed=3: .*give seeds=\[3\]"),
    (dict(job_tim=[1, 2]), r"unknown parameter 'job_tim'; did you mean 'job_time'\?$"),
    (dict(backend="serial", workers=1), r"^workers is for backend='local' or 'ray'"),
    (dict(backend="fast"), r"^backend must be one of local, ray, serial"),
    (dict(workers=0), r"^workers must be between 1 and"),
])
def test_errors_name_the_python_keywords(tmp_path: Path, kw, said) -> None:
    """The Python surface said "give seeds or seed, not both" when only seed was given,
    "has no option --job-tim" with no nearest name, and "--workers is for ...": its errors
    now name its own keywords, as swarmex.run's do."""
    with pytest.raises(InputError, match=said) as err:
        swarmex.sweep("traversal", out=tmp_path / "s", grid="6x6", agents=[1, 2], **kw)
    assert "--" not in str(err.value) and "not both" not in str(err.value)
    assert not (tmp_path / "s").exists()


def test_bad_values_stop_before_any_run_and_none_is_the_default(tmp_path: Path) -> None:
    """A value its option refuses fails every run it is in the same way: InputError before
    any run (docs promise it), not a folder of error rows. ``None`` is the default, as in
    ``swarmex.run``; a dict (a fleet's rows) is named as what it is, not "cannot be swept"."""
    out = tmp_path / "s"
    for kw, said in ((dict(agents=[2, "three"]), " agents: expected an integer"),
                     (dict(agents=2, loss=[0.1, 1.5]), " loss must be less than 1"),
                     (dict(agents=2, comm_range=[None, 2]), "None cannot be one of"),
                     (dict(agents=2, fleet=[{"id": 1}, {"id": 2}]), "a dict cannot be")):
        with pytest.raises(InputError, match=said):
            swarmex.sweep("traversal", out=out, grid="4x4", backend="serial", **kw)
        assert not out.exists()
    table = swarmex.sweep("traversal", out=out, grid="4x4", agents=2, comm_range=None,
                          backend="serial")
    assert table.num_rows == 1 and table.column("error").to_pylist() == [None]
    assert "comm_range" not in table.column_names


@pytest.mark.parametrize("progress", [True, False])
def test_the_bar_of_the_command_line_unless_turned_off(progress: bool, tmp_path: Path,
                                                       monkeypatch, capfd) -> None:
    """A sweep from Python used to show nothing however long it ran. On a terminal (forced
    here: Rich reads FORCE_COLOR) it shows the command line's bar, counting every run and
    the failed ones; ``progress=False`` keeps standard error silent."""
    monkeypatch.setenv("FORCE_COLOR", "1")
    monkeypatch.setenv("COLUMNS", "200")
    swarmex.sweep("traversal", out=tmp_path / "s", grid="5x5", agents=[1, 2, 30], seeds=1,
                  backend="serial", progress=progress)
    err = capfd.readouterr().err
    if progress:
        assert "sweep" in err and "3/3" in err and "(1 failed)" in err  # 30 agents > 25 cells
    else:
        assert err == ""

