"""``swarmex.run(progress=True)``: a long run's bar from Python, as the command line shows it."""

from __future__ import annotations

import io

import pytest
from rich.console import Console

import swarmex


def test_a_run_from_python_shows_the_bar_when_asked(monkeypatch, capfd) -> None:
    """``swarmex.run(progress=True)``: the command line's bar of a long run (jobs started of
    the free cells, here forced onto a terminal and shown at once), and the same record as
    without it."""
    from swarmex.experiments.progress import FrameProgress

    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    monkeypatch.setenv("FORCE_COLOR", "1")
    seen = []
    with_bar = swarmex.run("traversal", grid="9x8", agents=3, seed=4, progress=True,
                           on_frame=seen.append)
    err = capfd.readouterr().err
    assert "jobs" in err and "/72" in err  # 9x8 free cells
    plain = swarmex.run("traversal", grid="9x8", agents=3, seed=4)
    a, b = with_bar.to_dict(), plain.to_dict()
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b and seen  # the caller's own on_frame still gets every frame
    assert capfd.readouterr().err == ""  # no bar unless asked


def test_the_bar_wants_a_frame_only_when_it_redraws_unless_it_wraps_a_recorder():
    """A mission that asks ``wants(t)`` (the roadmap's frames copy every edge's count) builds
    frames for the bar only when it redraws, and every frame a wrapped recorder keeps."""
    import io

    from rich.console import Console

    from swarmex.experiments.progress import FrameProgress
    from swarmex.missions.base import FrameList, ProgressSpec

    spec = ProgressSpec(10, "steps", lambda f: f)
    alone = FrameProgress(spec, Console(file=io.StringIO()))
    assert not alone.wants(1)  # within the delay before the bar shows
    alone.t0 = alone.last = alone.last - 10.0
    assert alone.wants(2)
    recorder = FrameProgress(spec, Console(file=io.StringIO()), FrameList())
    assert recorder.wants(1) and recorder.wants(2)


@pytest.mark.parametrize("width", [80, 100])
def test_a_batch_bar_with_a_long_run_description_fits_one_line(width):
    """A reproduction's bar names the run in progress: unbounded, that name squeezed the
    counts and the ETA to "…" and wrapped the bar onto a second line at 80 or 100 columns."""
    from swarmex.experiments.progress import runs_progress

    console = Console(file=io.StringIO(), force_terminal=True, width=width, color_system=None)
    bar = runs_progress("exploration", console, detail=True)
    bar.add_task("sweep n=1 laser=2 comm=5 greedy-exclusion seed=0 " * 2, total=53,
                 completed=7)
    with console.capture() as shown:
        console.print(bar.get_renderable())
    lines = shown.get().splitlines()
    assert len(lines) == 1 and len(lines[0]) <= width
    assert "7/53" in lines[0] and "runs/s" in lines[0] and "-:--:--" in lines[0]
    assert "sweep n=1" in lines[0] and lines[0].rstrip().endswith("…")


def test_a_rerun_and_a_drawing_from_python_show_the_bar_when_asked(monkeypatch, capfd,
                                                                   tmp_path) -> None:
    """``swarmex.rerun`` and ``swarmex.render`` of a long run were silent from Python, as
    their commands were: ``progress=True`` shows the run's bar; the record is the same."""
    from swarmex.experiments.progress import FrameProgress

    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    monkeypatch.setenv("FORCE_COLOR", "1")
    rec = swarmex.run("traversal", grid="9x8", agents=3, seed=4)
    again = swarmex.rerun(rec, progress=True)
    assert "/72" in capfd.readouterr().err
    a, b = rec.to_dict(), again.to_dict()
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
    swarmex.render(rec, tmp_path / "r.png", progress=True)
    assert "/72" in capfd.readouterr().err and (tmp_path / "r.png").exists()
    swarmex.rerun(rec)
    assert capfd.readouterr().err == ""  # no bar unless asked
    with pytest.raises(swarmex.InputError, match="progress must be True or False"):
        swarmex.rerun(rec, progress="no")


def test_a_foraging_run_counts_robots_told_then_units_home(monkeypatch, capfd) -> None:
    """A foraging run had no bar (1024² with 1,024 robots and Sectors: about 10 s in
    silence). It counts the robots that know the food, then the units home: never down,
    and n + k when the run completes; the record is the same with the bar."""
    from swarmex.experiments.progress import FrameProgress
    from swarmex.missions.registry import get

    opts = dict(grid=32, agents=8, algorithm="sectors", food_units=5, seed=2)
    mission = get("foraging")
    params = mission.params(opts)
    spec = mission.progress(params, mission.prepare(params))
    frames = []
    plain = swarmex.run("foraging", **opts, on_frame=frames.append)
    counts = [spec.count(f) for f in frames]
    assert spec.total == 8 + 5 and plain.complete
    assert counts == sorted(counts) and counts[0] == 0 and counts[-1] == spec.total
    told = [int(f.informed.sum()) for f in frames]
    assert 0 < told.index(8) < len(frames) - 1  # the word is spread before the last unit
    monkeypatch.setattr(FrameProgress, "DELAY", 0.0)
    monkeypatch.setattr(FrameProgress, "EVERY", 0.0)
    monkeypatch.setenv("FORCE_COLOR", "1")
    with_bar = swarmex.run("foraging", **opts, progress=True)
    assert "robots told, units home" in capfd.readouterr().err
    a, b = with_bar.to_dict(), plain.to_dict()
    a.pop("wall_seconds"), b.pop("wall_seconds")
    assert a == b
