"""One line on stderr while numba compiles kernels (a cold cache: the first run after an
install or after a kernel changed).

Why: every kernel is ``cache=True``, so only the first process compiles (8-20 s on a small
machine) and later ones load the machine code from disk in milliseconds. Without a word the
first big run looks hung. (``swarmex demo`` and other runs small enough to keep their
kernels interpreted, :mod:`swarmex._kernels`, compile nothing.) The detection is exact and
free: numba announces a ``numba:compile`` event only when it really compiles (a cache hit
loads without one), so a warm run prints nothing and costs one listener registration.

On a terminal the line is a transient Rich spinner, shown while a compile runs and cleared
after; elsewhere (a log, a pipe, the tests' capture) it is printed once per process. Only the
process that entered :func:`compile_notice` speaks: forked workers inherit the listener but
stay silent.
"""

from __future__ import annotations

import contextlib
import functools
import os
import threading
from collections.abc import Iterator
from typing import Any

from rich.console import Console

MESSAGE = "compiling kernels, first run only"

_said = False  # the plain (non-terminal) line is printed once per process


@functools.cache
def _listener_type() -> type:
    from numba.core import event

    class Notice(event.Listener):
        """Shows the notice from the first (outermost) compile start to its end."""

        def __init__(self, console: Console) -> None:
            self.console = console
            self.pid = os.getpid()
            self.depth = 0  # compiles nest (a kernel compiles the kernels it calls)
            self.live: Any = None
            self.lock = threading.Lock()

        def on_start(self, event: Any) -> None:
            global _said
            if os.getpid() != self.pid:
                return
            with self.lock:
                self.depth += 1
                if self.depth > 1:
                    return
                if self.console.is_terminal:
                    from rich.errors import LiveError
                    from rich.live import Live
                    from rich.spinner import Spinner

                    live = Live(
                        Spinner("dots", text=MESSAGE),
                        console=self.console,
                        transient=True,
                        refresh_per_second=8,
                    )
                    try:
                        live.start(refresh=True)
                    except LiveError:  # a run's progress bar is up: one line above it
                        if not _said:
                            _said = True
                            self.console.print(f"swarmex: {MESSAGE}", highlight=False)
                    else:
                        self.live = live
                elif not _said:
                    _said = True
                    self.console.print(f"swarmex: {MESSAGE}", highlight=False, soft_wrap=True)

        def on_end(self, event: Any) -> None:
            if os.getpid() != self.pid:
                return
            with self.lock:
                self.depth -= 1
                if self.depth == 0:
                    self.stop()

        def stop(self) -> None:
            if self.live is not None:
                self.live.stop()
                self.live = None

    return Notice


@contextlib.contextmanager
def compile_notice(console: Console) -> Iterator[None]:
    """Within the block, a numba compile shows :data:`MESSAGE` on ``console`` (stderr).

    Does not import numba: the listener is registered when a kernel loads it
    (:func:`swarmex._kernels.when_loaded`), so a block whose kernels run interpreted, or
    that runs none, never pays for numba. Nothing is shown when every kernel comes from the
    cache."""
    from swarmex._kernels import when_loaded

    attached: list[Any] = []

    def attach() -> None:
        from numba.core import event

        listener = _listener_type()(console)
        event.register("numba:compile", listener)
        attached.append(listener)

    withdraw = when_loaded(attach)
    try:
        yield
    finally:
        withdraw()
        for listener in attached:
            from numba.core import event

            event.unregister("numba:compile", listener)
            with listener.lock:
                listener.stop()
