"""``swarmex watch``'s terminal view says what each agent flies (a hybrid mission)."""

from __future__ import annotations

import io

from rich.console import Console

from swarmex.net import events as ev
from swarmex.net.watch import TerminalView


def test_terminal_view_shows_vehicle_kinds_and_a_spares():
    out = io.StringIO()
    view = TerminalView(Console(file=out, width=120), live=False)
    view.update([
        ev.hello("traversal", "madgta", [1, 2], "traversal · hybrid", None,
                 vehicles=[{"id": 1, "kind": "mavlink", "link": "udp:127.0.0.1:1"},
                           {"id": 2, "kind": "simulated"}]),
        ev.message(3.0, 1, "left", extra={"reason": "low battery"}),
        ev.message(4.0, 1, "join", 0.0, 0.0, extra={"vehicle": "simulated"}),
    ])
    assert view.agents[2]["vehicle"] == "simulated"
    assert view.agents[1]["vehicle"] == "simulated" and view.agents[1]["state"] == "spare"
    table = io.StringIO()
    Console(file=table, width=120).print(view._table())
    assert "vehicle" in table.getvalue() and "simulated" in table.getvalue()
    view.close()


def test_ctrl_c_keeps_the_events_seen_so_far(tmp_path, monkeypatch, capsys):
    """``watch --events FILE`` wrote the file only after a mission's end: Ctrl-C lost it."""
    import json

    from swarmex.cli import main

    hello = ev.hello("traversal", "madgta", [1, 2], "traversal", None)

    def batches(address, timeout, stop=None):
        yield [hello, ev.message(1.0, 1, "pos", 0.0, 0.0)]
        raise KeyboardInterrupt

    monkeypatch.setattr(ev, "viewer_batches", batches)
    path = tmp_path / "events.json"
    assert main(["watch", "--connect", "tcp://127.0.0.1:9", "--events", str(path)]) == 130
    assert capsys.readouterr().err.strip() == "swarmex: interrupted"
    saved = json.loads(path.read_text())
    assert [e["type"] for e in saved] == ["hello", "message"]


def test_an_exploration_stream_is_shown_in_steps_without_jobs():
    """``watch`` on the mesh's display said "t=70.0 s · jobs 0 · messages 0": an exploration
    counts steps, has no jobs, and gives its messages only as the end's total."""
    import io

    from rich.console import Console

    from swarmex.net import events as ev
    from swarmex.net.watch import TerminalView

    out = io.StringIO()
    view = TerminalView(Console(file=out, width=200), live=False)
    view.update([ev.hello("exploration", "greedy-exclusion", [0, 1], "exploration · test",
                          None, "step", messages="totals"),
                 ev.move(70.0, 0, 3.0, 4.0)])
    view._last_line = 0.0
    view.update([{"type": "end", "t": 110.0, "complete": True, "makespan": 110.0,
                  "time_unit": "step", "metrics": {}, "messages": 2436, "agents": []}])
    lines = out.getvalue().splitlines()
    assert lines[0] == "t=70.0 steps · messages counted at the end"
    assert lines[-1] == "t=110.0 steps · messages 2436 · mission over"
    assert "jobs" not in out.getvalue() and "t=70.0 s ·" not in out.getvalue()
