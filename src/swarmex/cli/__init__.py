"""``swarmex`` command line: thin wrappers that parse, call the library and print.

:func:`main` is the console-script entry point. It turns bad input (our
:class:`~swarmex.errors.InputError` and Click's usage errors) into exit status 2 with one
line on stderr, and Ctrl-C into status 130, never a traceback. SIGTERM (``kill``,
``timeout``, a scheduler or a container stopping) ends a command exactly as Ctrl-C does, so
every command's "keep what is done" path (a sweep's table, a server's partial record, an
agent handing its ids back) serves both.
"""

from __future__ import annotations

import contextlib
import signal
import sys
from collections.abc import Iterator
from typing import Any, NoReturn

import typer

# the command modules register their commands on the shared app when the command is first
# looked up (swarmex.cli.app.LazyGroup), so `swarmex --help` imports none of them
from swarmex.cli.app import Interrupted, app
from swarmex.engine import interrupts
from swarmex.errors import InputError

try:  # recent Typer vendors Click as typer._click; older releases use Click itself
    from typer._click import exceptions as _cx
except ImportError:  # pragma: no cover - depends on the installed Typer
    from click import exceptions as _cx  # type: ignore[no-redef]

_NO_ARGS = getattr(_cx, "NoArgsIsHelpError", getattr(_cx, "NoArgsIsHelp", ()))


def main(argv: list[str] | None = None) -> int:
    # a stop request noted here (engine.interrupts) is cleared by the loops that read it
    # when they start: a sweep, a study's runs
    with _terminate_as_ctrl_c():
        return _main(argv)


@contextlib.contextmanager
def _terminate_as_ctrl_c() -> Iterator[None]:
    """Within the block, SIGTERM does what Ctrl-C does at that moment: it calls the SIGINT
    handler in place (a server's or an agent's own, or Python's KeyboardInterrupt), with
    SIGTERM's number, so a handler that says why it stops can name the signal.

    Why forward rather than raise: the commands that must finish cleanly already own a
    SIGINT handler (a server sets a flag and writes its record at a safe point), and one
    route for both signals cannot drift. Only the main thread may set handlers; elsewhere
    (an embedding program's thread) signals are left alone."""

    def on_sigterm(signum: int, frame: Any) -> None:
        handler = signal.getsignal(signal.SIGINT)
        if not callable(handler):  # SIGINT ignored or default-at-C-level: stop regardless
            interrupts.note()
            raise KeyboardInterrupt
        handler(signum, frame)

    try:
        previous = signal.signal(signal.SIGTERM, on_sigterm)
    except ValueError:  # not the main thread
        yield
        return
    # Python's Ctrl-C, noted before it raises (engine/interrupts: one raised inside a
    # finalizer is dropped, and a sweep's loop asks for it again)
    int_before = signal.getsignal(signal.SIGINT)
    if int_before is signal.default_int_handler:
        signal.signal(signal.SIGINT, interrupts.ctrl_c)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
        if signal.getsignal(signal.SIGINT) is interrupts.ctrl_c:
            signal.signal(signal.SIGINT, int_before)


def _main(argv: list[str] | None) -> int:
    try:
        result = app(args=argv, prog_name="swarmex", standalone_mode=False)
    except InputError as exc:
        print(f"swarmex: error: {exc}", file=sys.stderr)
        return 2
    except _NO_ARGS:
        return 0
    except _cx.UsageError as exc:
        msg = exc.format_message().replace("\n", " ")
        print(f"swarmex: error: {msg}", file=sys.stderr)
        return 2
    except typer.Exit as exc:
        return int(getattr(exc, "exit_code", getattr(exc, "code", 0)) or 0)
    except (KeyboardInterrupt, Interrupted):
        print("swarmex: interrupted", file=sys.stderr)
        return 130
    except MemoryError:  # a map or team too large for this machine: its line, not numpy's
        print("swarmex: error: out of memory: the run needs more memory than this machine"
              " gives it (a smaller map, fewer agents or fewer runs at once)", file=sys.stderr)
        return 2
    except SystemExit as exc:  # typer.Exit / broken pipes under standalone_mode=False
        return exc.code if isinstance(exc.code, int) else 0
    except SystemError as exc:
        # Ctrl-C while a compiled kernel is being called surfaces as numba's "returned a
        # result with an exception set", with the KeyboardInterrupt as its cause
        if not _interrupted(exc):
            raise
        print("swarmex: interrupted", file=sys.stderr)
        return 130
    return result if isinstance(result, int) else 0


def _interrupted(exc: BaseException) -> bool:
    """Whether ``exc`` was caused, directly or down its chain, by a KeyboardInterrupt."""
    seen: set[int] = set()
    cur: BaseException | None = exc
    while cur is not None and id(cur) not in seen:
        if isinstance(cur, KeyboardInterrupt):
            return True
        seen.add(id(cur))
        cur = cur.__cause__ or cur.__context__
    return False


def entry() -> None:
    """The console script (and ``python -m swarmex``): run, then leave quickly."""
    leave(main())


def leave(code: int) -> NoReturn:
    """End the process as the interpreter would, minus finalising it object by object.

    Why: after a run, finalisation frees every compiled-kernel object numba loaded (one
    LLVM call each) and the rest of the heap, 0.3-0.5 s of CPU after a ``swarmex demo`` that
    itself takes about 1.5 s, for memory the OS takes back at once anyway. What finalisation
    does that a command could rely on is kept, in the interpreter's order: wait for
    non-daemon threads, run the ``atexit`` callbacks (multiprocessing, tempfile and
    ``weakref.finalize`` clean-ups, logging), flush the standard streams. Files are closed by
    the commands themselves (every writer here uses ``with``); :func:`main` (the tests') does
    not go through this.
    """
    import atexit
    import contextlib
    import os
    import signal
    import threading

    for thread in threading.enumerate():
        if thread is not threading.main_thread() and not thread.daemon:
            thread.join()
    # a Ctrl-C (or SIGTERM) while the clean-ups run means "leave now": a terminal often
    # sends two, and the second one, raised inside a clean-up, printed "Exception ignored in
    # atexit callback" and its traceback after the command's own last line (a CI flake)
    with contextlib.suppress(ValueError):  # not the main thread: signals stay as they are
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, lambda *_: os._exit(code or 130))
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        # a closed pipe or stream: nothing more can be said
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    os._exit(code)


__all__ = ["app", "entry", "leave", "main"]
