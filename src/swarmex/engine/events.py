"""A discrete-event clock.

Events are ``(time, seq, payload)``; ``seq`` is a global insertion counter, so two events at
the same instant run in the order they were scheduled. That tie rule is what makes a run a
pure function of its inputs and seed. Synchronous Look-Compute-Move rounds are the special
case where every event falls on an integer time.
"""

from __future__ import annotations

import heapq
import itertools
from dataclasses import dataclass, field
from typing import Any


@dataclass(order=True)
class Event:
    time: float
    seq: int
    kind: str = field(compare=False)
    agent: int = field(compare=False, default=-1)
    data: Any = field(compare=False, default=None)


class EventQueue:
    def __init__(self) -> None:
        self._heap: list[Event] = []
        self._counter = itertools.count()
        self.now = 0.0

    def schedule(self, time: float, kind: str, agent: int = -1, data: Any = None) -> Event:
        if time < self.now - 1e-12:
            raise ValueError(f"cannot schedule into the past ({time} < {self.now})")
        ev = Event(float(time), next(self._counter), kind, agent, data)
        heapq.heappush(self._heap, ev)
        return ev

    def pop(self) -> Event:
        ev = heapq.heappop(self._heap)
        self.now = ev.time
        return ev

    def __len__(self) -> int:
        return len(self._heap)

    def __bool__(self) -> bool:
        return bool(self._heap)
