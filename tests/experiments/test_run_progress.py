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
