"""A Ctrl-C (or SIGTERM) that Python would drop: remembered, so a loop of runs still stops.

Why: a signal handler's exception is raised wherever the main thread happens to be, and when
that is a finalizer or a weakref callback (a ``WeakKeyDictionary``'s clean-up, while a run
frees its objects) Python prints "Exception ignored in ..." and carries on. A sweep then ran
every one of its remaining runs after a SIGTERM and exited 0. The command line's handler
(:func:`ctrl_c`) notes the request before raising, and the loops between runs ask
:func:`raise_if_requested`, which raises the KeyboardInterrupt again if it was lost.
"""

from __future__ import annotations

import signal
import threading
from typing import Any

_REQUESTED = threading.Event()


def ctrl_c(signum: int, frame: Any) -> None:
    """Python's Ctrl-C (a KeyboardInterrupt where the main thread is), noted first."""
    note()
    signal.default_int_handler(signum, frame)


def is_ctrl_c(handler: Any) -> bool:
    """Whether ``handler`` is Python's own Ctrl-C, or :func:`ctrl_c`."""
    return handler is signal.default_int_handler or handler is ctrl_c


def note() -> None:
    """Note a stop request (a handler that raises its own way calls this first)."""
    _REQUESTED.set()


def clear() -> None:
    """Forget a request: a command starts, or its process goes on to another one."""
    _REQUESTED.clear()


def raise_if_requested() -> None:
    """Raise KeyboardInterrupt if a stop was requested: between runs, where a lost one
    would otherwise let every remaining run go ahead."""
    if _REQUESTED.is_set():
        raise KeyboardInterrupt
