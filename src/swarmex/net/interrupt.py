"""A stop request for the networked processes: the first Ctrl-C (or SIGTERM) asks, the second
insists.

Why a flag and not ``KeyboardInterrupt``: the exception could land halfway through a frame's
handling, leaving the log a server writes its record from (or an agent's hand-back)
inconsistent. The loops check :attr:`StopRequest.seen` at a safe point and end as they
would on a fault: a server writes the record of what was done and sends ``END``; an agent
hands its id back (``RET``) and brings its vehicle down. A second signal raises
``KeyboardInterrupt`` as usual (leave now). SIGTERM reaches the handler through
:func:`swarmex.cli.main`, which forwards it to the SIGINT handler with its own number.
"""

from __future__ import annotations

import signal
import threading
from types import TracebackType
from typing import Any

#: the exit status of a process a stop request ended, as the shell reports one SIGINT ended
EXIT_INTERRUPTED = 130


class StopRequest:
    """Within ``with StopRequest() as stop:``, SIGINT sets :attr:`seen` and :attr:`how`
    ("Ctrl-C" or the signal's name). The handler is installed only in the main thread (a
    signal handler can live nowhere else); elsewhere (a test's thread) nothing changes.
    ``also_sigterm``: SIGTERM asks too and never escalates (a child whose launcher forwards
    its own stop, while a terminal's Ctrl-C or a group SIGTERM may reach it directly)."""

    def __init__(self, also_sigterm: bool = False) -> None:
        self.seen = False
        self.how = "Ctrl-C"
        self.also_sigterm = also_sigterm
        self._previous: Any = None
        self._previous_term: Any = None

    def __enter__(self) -> StopRequest:
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._on_signal)
            if self.also_sigterm:
                self._previous_term = signal.signal(
                    signal.SIGTERM, lambda signum, _frame: self.request(signum))
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
            self._previous = None
        if self._previous_term is not None:
            signal.signal(signal.SIGTERM, self._previous_term)
            self._previous_term = None

    def request(self, signum: int) -> None:
        """Ask to stop (once; a repeated request changes nothing): for a signal that must
        never escalate, such as the SIGTERM a launcher sends its own child."""
        if not self.seen:
            self.seen = True
            self.how = "Ctrl-C" if signum == signal.SIGINT else signal.Signals(signum).name

    def _on_signal(self, signum: int, _frame: Any) -> None:
        if self.seen:
            raise KeyboardInterrupt
        self.request(signum)
