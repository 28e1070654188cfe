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
