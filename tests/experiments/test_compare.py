"""``swarmex.compare`` and ``swarmex sweep --baseline``: paired differences of a sweep.

Checked by an independent route: the pairs are rebuilt from ``swarmex.run`` (one run per
algorithm, grid and seed) and their interval is SciPy's paired t-test interval
(``ttest_rel(...).confidence_interval()``), not swarmex's statistics code."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

import swarmex
from swarmex.cli import main
from swarmex.errors import InputError

GRIDS, SEEDS = ["6x6", "7x5"], [0, 1, 2, 3]


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    out = tmp_path_factory.mktemp("cmp") / "s"
    return swarmex.sweep("traversal", out=out, algorithm=["madgta", "nearest", "madgta+"],
                         grid=GRIDS, agents=2, seeds=SEEDS, backend="serial", progress=False)


def makespans(algorithm: str, grid: str) -> np.ndarray:
    return np.array([swarmex.run("traversal", seed=s, algorithm=algorithm, grid=grid,
                                 agents=2).makespan for s in SEEDS])


def test_pairs_match_runs_and_scipys_paired_interval(table) -> None:
    rows = swarmex.compare(table, {"algorithm": "madgta"}, ["makespan"]).to_pylist()
    assert [(r["algorithm"], r["grid"]) for r in rows] == [
        ("nearest", "6x6"), ("nearest", "7x5"), ("nearest", None),
        ("madgta+", "6x6"), ("madgta+", "7x5"), ("madgta+", None),
    ]
    checked = 0
    for r in rows:
        grids = GRIDS if r["grid"] is None else [r["grid"]]
        a = np.concatenate([makespans("madgta", g) for g in grids])
        b = np.concatenate([makespans(r["algorithm"], g) for g in grids])
        assert r["pairs"] == len(a) and r["metric"] == "makespan"
        assert r["baseline_mean"] == pytest.approx(a.mean())
        assert r["mean"] == pytest.approx(b.mean())
        assert r["diff"] == pytest.approx((b - a).mean())
        assert (r["lower_in"], r["higher_in"]) == (int((b < a).sum()), int((b > a).sum()))
        ratios = b / a - 1
        assert r["relative"] == pytest.approx(ratios.mean())
        if np.ptp(b - a) > 0:
            low, high = stats.ttest_rel(b, a).confidence_interval()
            assert (r["diff_low"], r["diff_high"]) == pytest.approx((low, high))
            low, high = stats.ttest_1samp(ratios, 0).confidence_interval()
            assert (r["relative_low"], r["relative_high"]) == pytest.approx((low, high))
            checked += 1
    assert checked >= 3  # the intervals, not only the means, were checked


def test_failed_runs_leave_their_pairs_out(tmp_path: Path) -> None:
    table = swarmex.sweep("traversal", out=tmp_path / "s", algorithm=["madgta", "nearest"],
                          grid="5x5", agents=[2, 30], seeds=2, backend="serial", progress=False)
    rows = swarmex.compare(table, {"algorithm": "madgta"}, ["makespan"]).to_pylist()
    assert [(r["agents"], r["pairs"]) for r in rows] == [(2, 2)]  # 30 agents > 25 cells


def test_python_bad_input_is_one_clear_error(table) -> None:
    for baseline, said in (({"algorithm": "nope"}, "has no value 'nope'"),
                           ({"agents": 2}, "'agents' is not a parameter the sweep varies"),
                           ({"algorithm": "madgta", "grid": "6x6"}, "must name one parameter")):
        with pytest.raises(InputError, match=said):
            swarmex.compare(table, baseline)
    with pytest.raises(InputError, match="metric 'speed': no such column"):
        swarmex.compare(table, {"algorithm": "madgta"}, ["speed"])
    with pytest.raises(InputError, match="expected a sweep folder"):
        swarmex.compare(42, {"algorithm": "madgta"})


def test_the_command_line_prints_the_table_and_checks_before_running(tmp_path: Path,
                                                                      capsys) -> None:
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "6x6"\nagents = 2\n'
                    'algorithm = ["madgta", "nearest"]\nseeds = [0, 1, 2]\n', encoding="utf-8")
    out = tmp_path / "out"
    for bad, said in (("algorithm=nope", "has no value 'nope' in this sweep (its values:"
                                         " madgta, nearest)"),
                      ("grid=6x6", "'grid' is not a parameter the sweep varies"),
                      ("algorithm", "expected PARAM=VALUE")):
        assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                     "--baseline", bad]) == 2
        assert said in capsys.readouterr().err
        assert not out.exists()  # nothing ran
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                 "--baseline", "algorithm=madgta", "--metric", "total_time_all"]) == 0
    text = capsys.readouterr().out
    assert "paired against algorithm = madgta" in text
    row = next(r for r in swarmex.compare(out, {"algorithm": "madgta"}).to_pylist())
    line = next(ln for ln in text.splitlines() if "nearest" in ln and "makespan" in ln)
    assert f"{100 * row['relative']:.3g}"[:4] in line and not math.isnan(row["diff"])


def test_a_dashed_axis_and_values_of_another_type_are_found(tmp_path: Path, capsys) -> None:
    """A spec key keeps its dashes (``travel-time``) while ``--baseline`` wrote
    ``travel_time`` and refused every dashed axis; a float axis written ``2`` and a TOML
    boolean written ``true`` were "no value" because values compared as text only."""
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "5x5"\nagents = 2\n'
                    'travel-time = [2, 2.5]\nseeds = [0, 1]\n', encoding="utf-8")
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                 "--baseline", "travel-time=2"]) == 0
    assert "paired against travel-time = 2 " in capsys.readouterr().out
    for name, value in (("travel_time", 2), ("travel-time", 2.0), ("travel_time", "2")):
        rows = swarmex.compare(out, {name: value}).to_pylist()
        assert [(r["travel-time"], r["pairs"]) for r in rows] == [(2.5, 2)]
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                 "--baseline", "travel-time=3"]) == 2
    assert "has no value '3'" in capsys.readouterr().err

    flags = tmp_path / "b.toml"
    flags.write_text('mission = "exploration"\nempty = "4x4"\nrobots = 2\n'
                     'aodv = [true, false]\nseeds = [0]\n', encoding="utf-8")
    assert main(["sweep", str(flags), "--backend", "serial", "--out", str(tmp_path / "b"),
                 "--baseline", "aodv=true"]) == 0
    assert "paired against aodv = True" in capsys.readouterr().out


def test_metrics_spelt_as_the_command_line_does_and_non_numbers(table) -> None:
    """``metrics.NAME`` is what ``--metric`` accepts: compare took it for a missing column.
    A text column (``grid``) gave an empty table rather than an error."""
    plain = swarmex.compare(table, {"algorithm": "madgta"}, ["total_time_all"])
    spelt = swarmex.compare(table, {"algorithm": "madgta"}, ["metrics.total_time_all"])
    assert spelt.equals(plain) and plain.num_rows > 0
    with pytest.raises(InputError, match="'grid' is a parameter of the runs, not a result"):
        swarmex.compare(table, {"algorithm": "madgta"}, ["grid"])
    with pytest.raises(InputError, match="metric 'time_unit': not a number"):
        swarmex.compare(table, {"algorithm": "madgta"}, ["time_unit"])


def test_a_table_without_swarmex_metadata_still_names_its_axes(table) -> None:
    """A table written back through another tool keeps the columns but loses the schema
    metadata that named the axes: compare said "'algorithm' is not a parameter the sweep
    varies (it varies: none)". The layout (parameters between ``run`` and ``seed``) says."""
    bare = table.replace_schema_metadata(None)
    got = swarmex.compare(bare, {"algorithm": "madgta"})
    assert got.equals(swarmex.compare(table, {"algorithm": "madgta"}))


def test_no_pairs_at_all_is_said_in_one_line(tmp_path: Path, capsys) -> None:
    """Every baseline run failed (30 agents on 25 cells): the command printed an empty
    table, headers only."""
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "5x5"\nagents = [2, 30]\nseeds = [0]\n',
                    encoding="utf-8")
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(tmp_path / "o"),
                 "--baseline", "agents=30"]) == 0
    out = capsys.readouterr().out
    assert "paired against agents = 30: no pairs" in out and "┏" not in out.split("no pairs")[1]
    with pytest.warns(UserWarning, match="no pairs against agents = 30"):  # it was silent
        assert swarmex.compare(tmp_path / "o", {"agents": 30}).num_rows == 0


def test_a_parameter_is_no_metric_and_a_metric_counts_once(table) -> None:
    # metrics=["seed"] or a parameter gave rows of zeros; a repeated metric, twice the rows
    for metric in ("seed", "grid", "agents"):
        with pytest.raises(InputError, match=f"{metric!r} is a parameter of the runs"):
            swarmex.compare(table, {"algorithm": "madgta"}, [metric])
    once = swarmex.compare(table, {"algorithm": "madgta"}, ["makespan"])
    assert swarmex.compare(table, {"algorithm": "madgta"}, ["makespan", "makespan"]).equals(once)


def test_two_sweeps_put_together_are_refused_not_paired_across(table, tmp_path: Path) -> None:
    # a grid the axes do not name (two one-grid sweeps concatenated): runs of 6x6 were paired
    # with runs of 9x9, a difference of -122 where the true one is +15.7
    import pyarrow as pa

    small = swarmex.sweep("traversal", out=tmp_path / "a", algorithm=["madgta", "nearest"],
                          grid="5x5", agents=2, seeds=[0, 1], backend="serial", progress=False)
    big = swarmex.sweep("traversal", out=tmp_path / "b", algorithm=["madgta", "nearest"],
                        grid="6x5", agents=2, seeds=[0, 1], backend="serial", progress=False)
    both = pa.concat_tables([small, big])
    with pytest.raises(InputError, match="the table varies grid, which its axes do not name"):
        swarmex.compare(both, {"algorithm": "madgta"}, ["makespan"])
    # without the metadata's parameter list, the pairing itself finds the clash
    with pytest.raises(InputError, match="two runs of algorithm=madgta share seed=0"):
        swarmex.compare(both.replace_schema_metadata(None).drop(["grid"]),
                        {"algorithm": "madgta"}, ["makespan"])


def test_a_pair_swept_as_a_tuple_is_found_by_its_usual_spelling(tmp_path: Path) -> None:
    # grid=(5, 5), as docs/api.md writes a shared grid, is "5,5" in the table: where=
    # {"grid": "5x5"} (docs/api.md's plot example), a tuple, and a baseline of "5x5" all
    # found no run
    out = tmp_path / "tg"
    table = swarmex.sweep("traversal", out=out, grid=[(5, 5), (6, 5)], agents=[1, 2],
                          seeds=2, backend="serial", progress=False)
    assert set(table.column("grid").to_pylist()) == {"5,5", "6,5"}
    for where in ({"grid": "5x5"}, {"grid": (5, 5)}, {"grid": "5,5"}):
        fig = swarmex.plot(out, "agents", "makespan", where=where)
        assert len(fig.axes[0].get_lines()) == 1
    with pytest.raises(InputError, match="no run matches"):
        swarmex.plot(out, "agents", "makespan", where={"grid": "7x7"})
    rows = swarmex.compare(out, {"grid": "5x5"}).to_pylist()
    assert {r["grid"] for r in rows} == {"6,5"} and all(r["pairs"] == 2 for r in rows if
                                                        r["agents"] is not None)
