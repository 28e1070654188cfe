"""A terminal view of a live mission, built only from monitor events (``swarmex watch``).

The web page of ``swarmex monitor`` is the full view; this one needs nothing but a terminal,
which is what one has on a field laptop over SSH. It keeps, per agent, where it is, how many
jobs it has started and its last message, plus the mission's progress, and redraws a Rich
table at most a few times a second (or prints one status line a second when stdout is not a
terminal, so logs stay readable).
"""

from __future__ import annotations

import time
from collections import Counter
from typing import Any

from rich.console import Console
from rich.live import Live
from rich.table import Table

#: a networked mission's status events: shown, but not counted as the mission's messages (the
#: record counts the agents' broadcasts only, as the simulator does)
STATUS_KINDS = ("finish", "left", "join")


class TerminalView:
    def __init__(self, console: Console, live: bool = True, quiet: bool = False) -> None:
        self.console = console
        self.quiet = quiet
        self.title = "waiting for the mission"
        self.t = 0.0
        self.unit = "s"  # the hello's time unit (an exploration counts steps)
        self.has_jobs = True  # an exploration has none: its column would read 0 for ever
        self.message_mode = "events"  # "totals": only the end's count (the hello says)
        self.agents: dict[int, dict[str, Any]] = {}
        self.cells = 0
        self.jobs = 0
        self.job_cells: Counter[tuple[Any, Any]] = Counter()
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
                self.unit = {"step": "steps"}.get(str(e.get("time_unit", "s")), "s")
                self.has_jobs = e.get("mission") in ("traversal", None)
                self.message_mode = str(e.get("messages") or "events")
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
                self.job_cells[(e.get("x"), e.get("y"))] += 1
            elif kind == "message" and isinstance(e.get("agent"), int):
                if e.get("kind") not in STATUS_KINDS:
                    self.messages += 1
                cell = (e.get("x"), e.get("y"))
                if e.get("kind") in ("undone", "left") and self.job_cells[cell] > 0:
                    self.job_cells[cell] -= 1  # the job is not done any more (as the page)
                    self.jobs -= 1
                a = self._agent(e["agent"])
                a["last"] = str(e.get("kind"))
                if e.get("kind") in ("left", "finish", "join"):
                    a["state"] = {"left": "gone", "finish": "home", "join": "spare"}[e["kind"]]
                if e.get("kind") == "join" and isinstance(e.get("vehicle"), str):
                    a["vehicle"] = e["vehicle"]
            elif kind == "end":
                self.ended = True
                self.end = e
                if self.message_mode != "events" and isinstance(e.get("messages"), int):
                    self.messages = int(e["messages"])
        self._draw()

    def _counts(self) -> str:
        """The progress line's counts: jobs where the mission has them, messages as the
        stream gives them (each one, or only the end's total)."""
        share = f"{self.jobs}/{self.cells}" if self.cells else str(self.jobs)
        jobs = f" · jobs {share}" if self.has_jobs else ""
        if self.message_mode == "events" or self.ended:
            return f"{jobs} · messages {self.messages}"
        return f"{jobs} · messages counted at the end"

    def _table(self) -> Table:
        table = Table(title=f"{self.title} · t = {self.t:.1f} {self.unit}{self._counts()}",
                      title_justify="left")
        cols = ("agent", "vehicle", "at", "jobs", "last message", "state")
        for col in cols if self.has_jobs else [c for c in cols if c != "jobs"]:
            table.add_column(col)
        for aid in sorted(self.agents)[:40]:
            a = self.agents[aid]
            row = [str(aid), a["vehicle"], a["pos"], str(a["jobs"]), a["last"], a["state"]]
            table.add_row(*(row if self.has_jobs else row[:3] + row[4:]))
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
                f"t={self.t:.1f} {self.unit}{self._counts()}"
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
