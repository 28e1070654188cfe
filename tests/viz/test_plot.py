"""``swarmex plot``: lines with CI bands, grouped bars, filters and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from swarmex.cli import main
from swarmex.engine.stats import summarize
from swarmex.errors import InputError
from swarmex.viz.plot import plot_sweep, series, sweep_figure

META = {"mission": "traversal", "axes": ["algorithm", "agents", "grid"]}
FAILED_NOTE = "note: 1 failed run(s) left out (the table's error column)"  # rows()'s "boom"


def rows() -> list[dict]:
    """A synthetic sweep table: makespan = 100 / agents (+ seed noise, nearest +10)."""
    out = []
    for algorithm in ("madgta", "nearest"):
        for agents in (1, 2, 4):
            for seed in range(3):
                out.append(
                    {
                        "algorithm": algorithm,
                        "agents": agents,
                        "grid": "8x8",
                        "seed": seed,
                        "makespan": 100 / agents + seed + (10 if algorithm == "nearest" else 0),
                        "complete": seed != 2,
                        "error": None,
                    }
                )
    out.append({**out[0], "seed": 9, "makespan": None, "complete": None, "error": "boom"})
    return out


def test_series_are_means_and_cis_per_level():
    s = series([r for r in rows() if not r["error"]], "agents", "makespan", "algorithm")
    assert list(s) == ["madgta", "nearest"]
    assert [st.mean for st in s["madgta"]] == [101.0, 51.0, 26.0]
    assert [st.mean for st in s["nearest"]] == [111.0, 61.0, 36.0]
    assert s["madgta"][0].half_width == pytest.approx(summarize([100, 101, 102]).half_width)
    assert s["madgta"][0].half_width == pytest.approx(4.302652729911275 * 1 / math.sqrt(3))


def test_line_plot_png_and_svg(tmp_path):
    finished = [r for r in rows() if r["complete"] is not False]
    png, note = plot_sweep(finished, META, "agents", "makespan", "algorithm",
                           path=tmp_path / "a.png")
    assert note == FAILED_NOTE
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size[0] > 400
        pixels = np.asarray(im.convert("RGB"))
    assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 20  # lines and bands, not blank
    svg, _ = plot_sweep(rows(), META, "agents", "complete", None, path=tmp_path / "a.svg")
    text = svg.read_text()
    assert text.lstrip().startswith("<?xml") and "<svg" in text
    # the same figure, the same bytes: matplotlib stamped the date and salted its ids at
    # random, so a figure kept under version control changed on every run
    again, _ = plot_sweep(rows(), META, "agents", "complete", None, path=tmp_path / "b.svg")
    assert again.read_text() == text and "<dc:date>" not in text


def test_bar_plot_for_a_categorical_x_and_where(tmp_path):
    path, note = plot_sweep(
        rows(), META, "algorithm", "makespan", None, ["agents=2", "complete=true"], "auto",
        tmp_path / "b.png",
    )
    assert path.exists() and note is None
    from swarmex.viz.plot import sweep_figure

    fig, _ = sweep_figure(rows(), META, "algorithm", "makespan", None, ["agents=2"], "auto")
    assert fig.axes[0].get_title().endswith("\nagents=2")  # the filter is on the figure
    _, pooled = plot_sweep(rows(), META, "algorithm", "makespan", path=tmp_path / "c.png")
    assert pooled and "pooled over agents" in pooled


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"x": "speed"}, "no column 'speed'"),
        ({"path": "p.pdf"}, "must end in .png or .svg"),
        ({"x": "algorithm", "kind": "line"}, "needs a numeric --x"),
        ({"where": ["agents=7"]}, "no run matches"),
        ({"where": ["agents"]}, "expected PARAM=VALUE"),
        ({"y": "error"}, "numeric 'error'"),
        ({"hue": "agents"}, "--hue agents is also --x"),  # was one lone point per series
    ],
)
def test_bad_requests_name_the_problem(tmp_path, kwargs, message):
    args = {"x": "agents", "y": "makespan", "hue": None, "where": None, "kind": "auto"}
    args.update(kwargs)
    args["path"] = tmp_path / args.get("path", "p.png")
    with pytest.raises(InputError, match=message):
        plot_sweep(rows(), META, **args)


def test_an_output_under_a_file_names_that_file(tmp_path):
    (tmp_path / "afile").write_text("x")
    with pytest.raises(InputError, match="afile is a file, not a folder"):
        plot_sweep(rows(), META, "agents", "makespan", None, path=tmp_path / "afile" / "p.png")


def test_cli_plot_of_a_real_sweep(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = [1, 2]\nseeds = [0, 1]\n')
    out = tmp_path / "sw"
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out)]) == 0
    assert main(["plot", str(out), "--x", "agents", "--y", "makespan"]) == 0
    assert (out / "makespan-vs-agents.png").exists()
    capsys.readouterr()
    assert main(["plot", str(out), "--x", "agents", "--y", "nope"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("swarmex: error: --y: no column 'nope'") and err.count("\n") == 1
    assert main(["plot", str(tmp_path / "missing"), "--x", "a", "--y", "b"]) == 2
    capsys.readouterr()
    # the note and the "wrote" line were folded at 80 columns
    deep = tmp_path / ("a-long-folder-name-" * 4) / "p.png"
    assert main(["plot", str(out), "--x", "seed", "--y", "makespan", "--out", str(deep)]) == 0
    said = capsys.readouterr()  # the note on stderr, as every command's notes
    assert said.out.splitlines() == [f"wrote {deep}"]
    assert said.err.splitlines() == ["note: pooled over agents (use --hue or --where to"
                                     " separate)"]


def test_python_plot_is_the_command_lines_figure(tmp_path, capsys):
    """``swarmex.plot`` returns the figure ``swarmex plot`` writes (the same PNG bytes), on
    the table ``swarmex.sweep`` returned; ``where`` filters, a pooled axis warns."""
    import swarmex

    out = tmp_path / "sw"
    table = swarmex.sweep("traversal", out=out, grid=["4x4", "5x4"], agents=[1, 2], seeds=2,
                          backend="serial", progress=False)
    assert main(["plot", str(out), "--x", "agents", "--y", "makespan", "--hue", "grid",
                 "--out", str(tmp_path / "cli.png")]) == 0
    fig = swarmex.plot(table, "agents", "makespan", hue="grid", out=tmp_path / "lib.png")
    assert (tmp_path / "lib.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    assert [line.get_label() for line in fig.axes[0].get_lines()] == ["4x4", "5x4"]
    fig = swarmex.plot(out, "agents", "makespan", where={"grid": "5x4"})  # no pooling: no warning
    assert len(fig.axes[0].get_lines()) == 1
    with pytest.warns(UserWarning, match="pooled over grid .use hue= or where="):
        swarmex.plot(table, "agents", "makespan")
    with pytest.raises(InputError, match="must end in .png or .svg"):
        swarmex.plot(table, "agents", "makespan", hue="grid", out=tmp_path / "x.jpg")


def test_traversal_mp4_render(tmp_path, capsys):
    """`--render .mp4` support of the traversal drawing: H.264 frames of the same animation."""
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg is not installed")
    import imageio.v2 as iio

    from swarmex.engine.record import read_record
    from swarmex.missions.traversal.mission import build_world
    from swarmex.missions.traversal.params import TraversalParams
    from swarmex.viz.traversal import render_traversal

    rec = tmp_path / "r.json"
    assert main(["traverse", "--grid", "5x3", "--agents", "2", "--json", str(rec)]) == 0
    capsys.readouterr()
    record = read_record(rec)
    world = build_world(TraversalParams.from_values(grid="5x3", agents=2))
    path = render_traversal(record, world, tmp_path / "run.mp4")
    reader = iio.get_reader(path)
    meta = reader.get_meta_data()
    frames = [f for f in reader]
    reader.close()
    assert meta["codec"] == "h264"
    assert len(frames) > 10 and frames[0].shape[0] % 2 == 0 and frames[0].shape[1] % 2 == 0
    assert not np.array_equal(frames[0], frames[-1])  # agents moved and jobs appeared
    with pytest.raises(InputError, match="must end in"):
        render_traversal(record, world, tmp_path / "run.avi")


def test_time_metrics_carry_the_runs_time_unit():
    # only makespan had its unit: total_time_all (s) or exploration_time (steps) had none
    from swarmex.viz.plot import y_label

    secs = [{"time_unit": "s"}]
    assert y_label("makespan", secs) == "makespan (s)"
    assert y_label("total_time_all", secs) == "total_time_all (s)"
    assert y_label("max_total_time", secs) == "max_total_time (s)"
    assert y_label("mission_end", secs) == "mission_end (s)"
    assert y_label("exploration_time", [{"time_unit": "step"}]) == "exploration_time (step)"
    assert y_label("nodes_done_all", secs) == "nodes_done_all"
    assert y_label("timed_out", secs) == "timed_out"
    assert y_label("makespan", [{"time_unit": "s"}, {"time_unit": "step"}]) == "makespan"
    assert y_label("complete", secs) == "fraction complete"


def test_python_plot_names_and_bad_input(tmp_path):
    """From Python: a dashed spec key is named with underscores (``travel_time`` for the
    ``travel-time`` column), ``metrics.NAME`` is the ``NAME`` column, a ``where`` that is
    not a dict and an ``out`` below a file are one InputError each (they were an
    AttributeError and an OSError traceback)."""
    import swarmex

    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = 2\n'
                    'travel-time = [2, 2.5]\nseeds = [0, 1]\n', encoding="utf-8")
    out = tmp_path / "sw"
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out)]) == 0
    fig = swarmex.plot(out, "travel_time", "metrics.total_time_all",
                       where={"travel_time": 2.5})
    assert fig.axes[0].get_xlabel().startswith("travel-time")
    with pytest.raises(InputError, match="where must be a dict"):
        swarmex.plot(out, "travel_time", "makespan", where="travel_time=2")  # type: ignore[arg-type]
    blocker = tmp_path / "file"
    blocker.write_text("x", encoding="utf-8")
    with pytest.raises(InputError, match="file is a file, not a folder"):
        swarmex.plot(out, "travel_time", "makespan", out=blocker / "p.png")


def test_a_time_of_unfinished_runs_is_marked_and_noted(tmp_path, capsys):
    # a run that did not finish has its budget as its makespan: a roadmap sweep drew PRM's
    # 400 "steps" (its budget, 0 % complete) as if it had finished slowly, without a word
    fig_rows = rows()
    fig, note = sweep_figure(fig_rows, META, "agents", "makespan", "algorithm")
    assert note == ("note: 6 of the 18 runs plotted did not finish; their makespan is where"
                    " they stopped, not a finish time (--where complete=true keeps the"
                    " finished ones)\n" + FAILED_NOTE)
    ax = fig.axes[0]
    hollow = [ln for ln in ax.lines if ln.get_markerfacecolor() == "white"]
    assert [len(ln.get_xdata()) for ln in hollow] == [3, 3]  # every point has a seed 2
    assert "some runs did not finish" in fig.texts[0].get_text()
    fig, note = sweep_figure(fig_rows, META, "agents", "makespan", "algorithm",
                             ["complete=true"])
    assert note is None and not [ln for ln in fig.axes[0].lines
                                 if ln.get_markerfacecolor() == "white"]
    fig, note = sweep_figure(fig_rows, META, "algorithm", "makespan", kind="bar")
    assert "did not finish" in note
    assert {p.get_hatch() for p in fig.axes[0].patches} == {"//"}
    # completeness itself is no time: nothing to mark
    assert sweep_figure(fig_rows, META, "agents", "complete", "algorithm")[1] == FAILED_NOTE



def test_python_plot_warns_of_each_note_in_its_own_words(monkeypatch):
    import swarmex
    import swarmex.experiments.compare as compare

    class Table:
        def to_pylist(self):
            return rows()

    monkeypatch.setattr(compare, "load", lambda results: (Table(), META))
    with pytest.warns(UserWarning) as caught:
        swarmex.plot("sweep", x="agents", y="makespan")
    said = [str(w.message) for w in caught]
    assert said[0] == "pooled over algorithm (use hue= or where= to separate)"
    assert said[1].startswith("6 of the 18 runs plotted did not finish")
    assert said[1].endswith("(where={'complete': True} keeps the finished ones)")
    assert said[2] == "1 failed run(s) left out (the table's error column)"


def test_a_configuration_without_a_finished_run_has_no_point(tmp_path):
    # every zigzag run at 2 agents failed: the line went straight through agents=2, a bar
    # plot drew a zero-height bar with a whisker at 0, nothing was said, and the title's
    # runs per point counted the empty configuration
    table = [r for r in rows() if not r["error"] and r["complete"]]
    for r in table:
        if r["algorithm"] == "nearest" and r["agents"] == 2:
            r.update(makespan=None, error="crashed", complete=None)
    fig, note = sweep_figure(table, META, "agents", "makespan", "algorithm")
    assert note == ("note: 2 failed run(s) left out (the table's error column); no finished"
                    " run, so no point, at agents=2 algorithm=nearest")
    ax = fig.axes[0]
    nearest = ax.lines[1].get_ydata()
    assert np.isnan(nearest[1]) and np.isfinite(nearest[[0, 2]]).all()  # a gap, no segment
    assert "≈2 runs/point" in ax.get_title()  # 10 finished runs over 5 points
    fig, _ = sweep_figure(table, META, "algorithm", "makespan", "agents", kind="bar")
    heights = sorted(round(p.get_height(), 6) for p in fig.axes[0].patches)
    assert len(heights) == 5 and min(heights) > 0  # no bar for the empty configuration


def test_a_point_alone_keeps_its_interval():
    # a band needs two points: a series with one point lost its CI without a word
    table = [r for r in rows() if not r["error"] and r["complete"]
             and (r["algorithm"] == "madgta" or r["agents"] == 4)]
    fig, _ = sweep_figure(table, META, "agents", "makespan", "algorithm")
    from matplotlib.collections import LineCollection

    whiskers = [c for c in fig.axes[0].collections if isinstance(c, LineCollection)]
    (seg,) = whiskers[0].get_segments()
    assert seg[0][0] == seg[1][0] == 4.0 and seg[1][1] - seg[0][1] > 0  # vertical, at x=4


def test_seconds_and_steps_are_times():
    from swarmex.viz.plot import is_time, y_label

    assert is_time("makespan_seconds") and y_label("makespan_seconds", [{"time_unit": "step"}]) \
        == "makespan_seconds (s)"
    table = [dict(r, mean_steps=r["makespan"]) for r in rows()]
    _, note = sweep_figure(table, META, "agents", "mean_steps", "algorithm")
    assert "6 of the 18 runs plotted did not finish" in note


@pytest.mark.parametrize("kind", ["bar", "line"])
def test_a_point_of_one_run_has_no_whisker_and_the_title_says_so(kind):
    """A bar or lone point of one run drew a flat cap, read as "± 0", under a title that
    promised a 95 % CI. Whiskers now go only where a point has two runs or more."""
    from matplotlib.collections import LineCollection

    def whiskers(fig) -> int:
        return sum(len(c.get_segments()) for c in fig.axes[0].collections
                   if isinstance(c, LineCollection))

    one = [r for r in rows() if r["seed"] == 0]  # one run a point
    x = "algorithm" if kind == "bar" else "agents"
    where = ["agents=2"] if kind == "bar" else ["algorithm=madgta", "agents=2"]
    fig, _ = sweep_figure(one, META, x, "makespan", None, where, kind)
    assert whiskers(fig) == 0 and "one run a point: no interval" in fig.axes[0].get_title()
    fig, _ = sweep_figure(rows(), META, x, "makespan", None, where, kind)
    assert whiskers(fig) > 0 and "mean ± 95 % CI (" in fig.axes[0].get_title()
    mixed = one + [r for r in rows() if r["seed"] == 1 and r["algorithm"] == "nearest"]
    fig, _ = sweep_figure(mixed, META, "algorithm", "makespan", None, ["agents=2"], "bar")
    assert whiskers(fig) == 1 and "where a point has two runs" in fig.axes[0].get_title()


def test_a_share_of_runs_gets_wilsons_interval_within_0_and_1():
    """``--y complete`` drew the t interval of 0/1 values: a share of the runs from about
    0.1 to 1.2. It is now Wilson's score interval (scipy's, by an independent route), and the
    axis stays within 0 and 1."""
    import scipy.stats as st

    from swarmex.viz.plot import interval_ends

    fig, _ = sweep_figure(rows(), META, "agents", "complete", None, None, "line")
    ax = fig.axes[0]
    band = ax.collections[0].get_paths()[0].vertices[:, 1]
    ends = st.binomtest(4, 6).proportion_ci(method="wilson")  # 2 of 3 per algorithm, pooled
    # swarmex's z is 1.96, scipy's the exact quantile: equal to 1e-4
    assert band.min() == pytest.approx(ends.low, rel=1e-4)
    assert band.max() == pytest.approx(ends.high, rel=1e-4)
    assert ax.get_ylim() == (-0.03, 1.03) and "Wilson" in ax.get_title()
    lo, hi = interval_ends([summarize([0.0, 1.0]), summarize([1.0, 1.0, 1.0])], True)
    assert lo == pytest.approx([st.binomtest(1, 2).proportion_ci(method="wilson").low,
                                st.binomtest(3, 3).proportion_ci(method="wilson").low], rel=1e-4)
    assert hi[1] == pytest.approx(1.0)
