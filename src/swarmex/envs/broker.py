"""Hand a simulator's decisions to a caller outside it, one at a time (the envs' engine).

Why: every mission's simulator is a loop that *calls* its agents' policies deep inside its
own code (an arrival, a planning tick). A reinforcement-learning environment needs the
opposite: the *caller* supplies each decision. Rewriting four simulators as re-entrant state
machines would create a second simulator per mission, which the project forbids (the envs
must drive the same agent cores as ``swarmex.run``). Instead the simulator runs unchanged in a
worker thread, and the policy object it calls is a stub that hands the question to the
environment and waits for the answer. Exactly one of the two threads runs at any time (a
strict hand-over through one condition variable), so the run is as deterministic as the
plain simulator, and the numbers are identical when the answers are the built-in policy's.

Usage, from an environment::

    broker = DecisionBroker(lambda ask: run_mission(..., policy=Stub(ask)))
    request = broker.start()          # runs until the first decision (or the end)
    while request is not None:
        request = broker.answer(action_for(request))
    result = broker.result            # what the run function returned

Inside the simulator the stub calls ``ask(payload)`` and gets the action back. ``close()``
abandons a run in the middle (the worker unwinds with :class:`Abandoned`, which the stub
must not catch).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

Ask = Callable[[Any], Any]


class Abandoned(BaseException):  # noqa: N818 - a control-flow signal; BaseException so that
    """Raised inside the worker when the environment drops the run (reset, close).

    A BaseException so that ``except Exception`` in simulator code does not swallow it.
    """


@dataclass
class _Slot:
    request: Any = None
    answer: Any = None
    turn: str = "caller"  # whose turn it is: "caller" or "worker"
    finished: bool = False
    abandoned: bool = False
    error: BaseException | None = None


class DecisionBroker:
    """Runs ``run(ask)`` in a worker thread; each ``ask(payload)`` becomes a request here."""

    def __init__(self, run: Callable[[Ask], Any], name: str = "swarmex-env-sim") -> None:
        self._run = run
        self._name = name
        self._cv = threading.Condition()
        self._slot = _Slot()
        self._thread: threading.Thread | None = None
        self.result: Any = None

    # ---------------------------------------------------------------- caller side
    def start(self) -> Any:
        """Start the run; return its first request, or None if it finished without one."""
        if self._thread is not None:
            raise RuntimeError("a broker runs once; make a new one")
        self._thread = threading.Thread(target=self._work, name=self._name, daemon=True)
        with self._cv:
            self._slot.turn = "worker"
            self._thread.start()
            return self._wait_for_caller()

    def answer(self, action: Any) -> Any:
        """Answer the pending request; return the next one, or None when the run ended."""
        with self._cv:
            if self._slot.finished:
                raise RuntimeError("the run has ended: no decision is pending")
            self._slot.answer = action
            self._slot.turn = "worker"
            self._cv.notify_all()
            return self._wait_for_caller()

    @property
    def pending(self) -> Any:
        """The request waiting for an answer (None when the run has ended)."""
        return None if self._slot.finished else self._slot.request

    @property
    def finished(self) -> bool:
        return self._slot.finished

    def close(self, timeout: float = 10.0) -> None:
        """Abandon the run if it is still going; the worker unwinds and ends."""
        thread = self._thread
        if thread is None or not thread.is_alive():
            return
        with self._cv:
            self._slot.abandoned = True
            self._slot.turn = "worker"
            self._cv.notify_all()
        thread.join(timeout)

    def _wait_for_caller(self) -> Any:
        while self._slot.turn != "caller":
            self._cv.wait()
        if self._slot.error is not None:
            error, self._slot.error = self._slot.error, None
            raise error
        return None if self._slot.finished else self._slot.request

    # ---------------------------------------------------------------- worker side
    def _ask(self, payload: Any) -> Any:
        with self._cv:
            if self._slot.abandoned:
                raise Abandoned
            self._slot.request = payload
            self._slot.turn = "caller"
            self._cv.notify_all()
            while self._slot.turn != "worker":
                self._cv.wait()
            if self._slot.abandoned:
                raise Abandoned
            answer, self._slot.answer = self._slot.answer, None
            return answer

    def _work(self) -> None:
        with self._cv:
            while self._slot.turn != "worker":
                self._cv.wait()
        try:
            result = self._run(self._ask)
        except Abandoned:
            result, error = None, None
        except BaseException as exc:  # handed to the caller, raised there
            result, error = None, exc
        else:
            error = None
        with self._cv:
            self.result = result
            self._slot.error = error
            self._slot.finished = True
            self._slot.request = None
            self._slot.turn = "caller"
            self._cv.notify_all()
