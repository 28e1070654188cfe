"""``swarmex.run(progress=True)``: a long run's bar from Python, as the command line shows it."""

from __future__ import annotations

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
