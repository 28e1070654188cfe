"""A terminal view of a live mission, built only from monitor events (``swarmex watch``).

The web page of ``swarmex monitor`` is the full view; this one needs nothing but a terminal,
which is what one has on a field laptop over SSH. It keeps, per agent, where it is, how many
jobs it has started and its last message, plus the mission's progress, and redraws a Rich
table at most a few times a second (or prints one status line a second when stdout is not a
terminal, so logs stay readable).
"""

from __future__ import annotations

import time
from typing import Any

from rich.console import Console
from rich.live import Live
from rich.table import Table


class TerminalView:
    def __init__(self, console: Console, live: bool = True, quiet: bool = False) -> None:
        self.console = console
        self.quiet = quiet
        self.title = "waiting for the mission"
        self.t = 0.0
        self.agents: dict[int, dict[str, Any]] = {}
        self.cells = 0
        self.jobs = 0
        self.messages = 0
        self.ended = False
        self.end: dict[str, Any] | None = None
        self._live = Live(self._table(), console=console, auto_refresh=False) \
            if live and not quiet else None
        if self._live is not None:
            self._live.start()
        self._last_line = 0.0

    def _agent(self, aid: int) -> dict[str, Any]:
        return self.agents.setdefault(aid, {"pos": "", "jobs": 0, "last": "", "state": "",
                                            "vehicle": ""})

    def update(self, batch: list[dict]) -> None:
        for e in batch:
            if not isinstance(e, dict):
                continue
            kind = e.get("type")
            if isinstance(e.get("t"), int | float):
                self.t = max(self.t, float(e["t"]))
            if kind == "hello":
                self.title = str(e.get("title", ""))
                self.agents.clear()
                for aid in e.get("agents") or []:
                    self._agent(int(aid))
                for v in e.get("vehicles") or []:  # a hybrid mission: who flies what
                    if isinstance(v, dict) and isinstance(v.get("id"), int):
                        self._agent(v["id"])["vehicle"] = str(v.get("kind", ""))
            elif kind == "world":
                cells = e.get("cells")
                if isinstance(cells, list):
                    self.cells = sum(str(row).count(".") for row in cells)
            elif kind == "move" and isinstance(e.get("agent"), int):
                self._agent(e["agent"])["pos"] = f"({e.get('x'):g},{e.get('y'):g})"
            elif kind == "job" and isinstance(e.get("agent"), int):
                self._agent(e["agent"])["jobs"] += 1
                self.jobs += 1
            elif kind == "message" and isinstance(e.get("agent"), int):
                self.messages += 1
                a = self._agent(e["agent"])
                a["last"] = str(e.get("kind"))
                if e.get("kind") in ("left", "finish", "join"):
                    a["state"] = {"left": "gone", "finish": "home", "join": "spare"}[e["kind"]]
                if e.get("kind") == "join" and isinstance(e.get("vehicle"), str):
                    a["vehicle"] = e["vehicle"]
            elif kind == "end":
                self.ended = True
                self.end = e
        self._draw()

    def _table(self) -> Table:
        share = f"{self.jobs}/{self.cells}" if self.cells else str(self.jobs)
        table = Table(title=f"{self.title} · t = {self.t:.1f} s · jobs {share}"
                      f" · {self.messages} messages", title_justify="left")
        for col in ("agent", "vehicle", "at", "jobs", "last message", "state"):
            table.add_column(col)
        for aid in sorted(self.agents)[:40]:
            a = self.agents[aid]
            table.add_row(str(aid), a["vehicle"], a["pos"], str(a["jobs"]), a["last"],
                          a["state"])
        return table

    def _draw(self) -> None:
        if self.quiet:
            return
        now = time.monotonic()
        if self._live is not None:
            if self.ended or now - self._last_line > 0.2:
                self._live.update(self._table(), refresh=True)
                self._last_line = now
        elif self.ended or now - self._last_line > 1.0:
            self._last_line = now
            self.console.print(
                f"t={self.t:.1f} s · jobs {self.jobs} · messages {self.messages}"
                + (" · mission over" if self.ended else ""),
                highlight=False,
            )

    def close(self) -> None:
        if self._live is not None:
            self._live.stop()
        if self.end is not None and not self.quiet:
            e = self.end
            self.console.print(
                f"{'complete' if e.get('complete') else 'incomplete'} · makespan "
                f"{e.get('makespan')} {e.get('time_unit', '')}",
                highlight=False,
            )
