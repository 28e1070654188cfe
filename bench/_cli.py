"""What every bench script shares on its command line: one-line errors and checked numbers.

The scripts are run by hand (``python bench/NAME.py``), so a wrong argument must say what is
wrong in one line and exit 2, as ``swarmex`` does, not print a traceback from deep inside a
run (or, worse, run with a meaningless value: ``--runs 0`` used to time nothing and divide by
zero, ``--seeds 0`` silently meant the default). Three pieces:

* :class:`Parser`: ``argparse`` whose errors are one line (``prog: error: ...``), no usage
  block (``--help`` still prints it);
* argument types that refuse out-of-range numbers at parse time (:func:`positive_int`, ...);
* :func:`run`: calls a script's ``main`` and turns the library's input errors
  (:class:`swarmex.errors.InputError`), a missing input file and Ctrl-C into one line and
  exit status 2 (130 for Ctrl-C);
* :func:`process_pool`: a process pool that Ctrl-C ends at once.

Imported as ``_cli`` (the script's folder is first on ``sys.path`` when it runs).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import signal
import sys
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import NoReturn


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> NoReturn:
        """Print ``prog: error: message`` alone: the usage block is what ``--help`` is for."""
        self.exit(2, f"{self.prog}: error: {message}\n")


def _number(text: str, kind: Callable[[str], float]) -> float:
    try:
        value = kind(text)
    except ValueError:
        name = "an integer" if kind is int else "a number"
        raise argparse.ArgumentTypeError(f"must be {name}, got {text!r}") from None
    if isinstance(value, float) and math.isnan(value):
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}")
    return value


def _int_at_least(text: str, lo: int, why: str = "") -> int:
    value = int(_number(text, int))
    if value < lo:
        raise argparse.ArgumentTypeError(f"must be at least {lo}{why}, got {value}")
    return value


def sizes(count: int, form: str) -> Callable[[str], tuple[int, ...]]:
    """``count`` integers >= 1 joined by ``x`` (``form`` names them in the error, e.g.
    ``WxHxROBOTS``): a grid's or a scenario's size, checked before any run."""

    def parse(text: str) -> tuple[int, ...]:
        parts = text.lower().split("x")
        if len(parts) != count:
            raise argparse.ArgumentTypeError(f"expected {form}, got {text!r}")
        return tuple(_int_at_least(p.strip(), 1) for p in parts)

    return parse


def maps_dir() -> Path:
    """The real benchmark maps: ``$SWARMEX_MAPS``, default ``../shared/maps`` beside the
    repository (every script that reads a map asks here). Not
    :func:`swarmex.worlds.mapfiles.maps_dir`: a script may run with another tree's ``src``
    on ``PYTHONPATH`` (``profile_traversal``, the reference child of
    ``compare_traversal_fingerprints``), and an older tree has no such function."""
    return Path(os.environ.get("SWARMEX_MAPS",
                               Path(__file__).resolve().parents[2] / "shared" / "maps"))


def map_file(text: str) -> Path:
    """A map file: the path as given, else a bare name in ``$SWARMEX_MAPS`` (default
    ``../shared/maps``), as the other scripts' ``--maps`` names are read."""
    path = Path(text)
    if path.is_file():
        return path
    folder = maps_dir()
    if path.parent == Path(".") and (folder / text).is_file():
        return folder / text
    raise argparse.ArgumentTypeError(f"no map file {text} (nor {folder / path.name})")


def positive_int(text: str) -> int:
    """An integer >= 1 (counts of runs, seeds, agents, workers)."""
    return _int_at_least(text, 1)


def paired_count(text: str) -> int:
    """An integer >= 2: seeds or cells of a paired comparison (one gives no interval, only nan)."""
    return _int_at_least(text, 2, " (a 95 % interval needs two pairs)")


def nonneg_int(text: str) -> int:
    """An integer >= 0 (a first seed)."""
    return _int_at_least(text, 0)


def positive_float(text: str) -> float:
    """A finite number > 0 (seconds, time limits, scales)."""
    value = _number(text, float)
    if not (0 < value < math.inf):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def cap(text: str) -> float:
    """A makespan cap as a multiple of the optimum: a finite number >= 1 (below, no plan)."""
    value = _number(text, float)
    if not (1 <= value < math.inf):
        raise argparse.ArgumentTypeError(f"must be a number >= 1 (x optimal), got {text!r}")
    return value


def nonneg_float(text: str) -> float:
    """A finite number >= 0 (a warm-up that may be skipped)."""
    value = _number(text, float)
    if not (0 <= value < math.inf):
        raise argparse.ArgumentTypeError(f"must be a number >= 0, got {text!r}")
    return value


def probability(text: str) -> float:
    """A loss probability in [0, 1) (at 1 nothing would ever arrive)."""
    value = _number(text, float)
    if not (0 <= value < 1):
        raise argparse.ArgumentTypeError(f"must be in [0, 1), got {text!r}")
    return value


def int_list(text: str) -> list[int]:
    """Comma-separated integers >= 1, e.g. ``10,50``."""
    try:
        return [positive_int(part.strip()) for part in text.split(",")]
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"a comma-separated list of counts: {exc}") from None


def out_file(text: str) -> Path:
    """A file to write at the end: its folder must exist now, not after the runs are done."""
    path = Path(text)
    folder = path.resolve().parent
    if not folder.is_dir():
        raise argparse.ArgumentTypeError(f"cannot write {text}: folder {folder} does not exist")
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"cannot write {text}: it is a folder")
    return path


def indices(text: str, count: int, what: str = "scenario") -> list[int]:
    """Comma-separated 0-based indices below ``count`` (``--only 0,2``); ``SystemExit(2)``."""
    out = []
    for part in text.split(","):
        try:
            i = int(part)
        except ValueError:
            fail(f"--only: {what} indices are integers 0..{count - 1}, got {part!r}")
        if not 0 <= i < count:
            fail(f"--only: {what} index {i} out of range 0..{count - 1}")
        out.append(i)
    return out


def fail(message: str) -> NoReturn:
    """Refuse the command line in one line, exit status 2."""
    print(f"{_prog()}: error: {message}", file=sys.stderr)
    raise SystemExit(2)


def _ignore_sigint() -> None:
    """In a worker: Ctrl-C is the driver's to handle (one line, and it ends the workers);
    each worker used to print its own KeyboardInterrupt traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextlib.contextmanager
def process_pool(workers: int) -> Iterator[ProcessPoolExecutor]:
    """A pool of ``workers`` processes that a Ctrl-C (or any error) in the block ends at
    once: ``with ProcessPoolExecutor()`` waits on leaving for every job still queued, so a
    Ctrl-C went on running them (31 s for a quick traversal comparison), or hung when a
    worker had died of the signal."""
    from swarmex.experiments.pool import kill_workers

    pool = ProcessPoolExecutor(max(1, workers), initializer=_ignore_sigint)
    try:
        yield pool
    except BaseException:
        # killed first: the executor then sees its workers gone, and its shutdown (waited
        # for, or its thread hangs the interpreter's exit) returns at once
        kill_workers(pool)
        with contextlib.suppress(Exception):
            pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown()


def _prog() -> str:
    return sys.argv[0].rsplit("/", 1)[-1] if sys.argv and sys.argv[0] else "bench"


def run(main: Callable[[], object]) -> NoReturn:
    """Run a script's ``main`` and exit with its status; input errors are one line, exit 2.

    ``InputError`` is the library's "your input is wrong" (an unknown algorithm, an agent
    count the map cannot hold); a missing or unreadable file named on the command line is the
    same kind of mistake. Anything else is a bug and keeps its traceback.
    """
    from swarmex.errors import InputError

    try:
        status = main()
    except InputError as exc:
        fail(str(exc))
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        fail(f"cannot read {exc.filename}: {exc.strerror}")
    except KeyboardInterrupt:
        print(f"{_prog()}: interrupted (Ctrl-C)", file=sys.stderr)
        raise SystemExit(130) from None
    raise SystemExit(status if isinstance(status, int) else 0)
