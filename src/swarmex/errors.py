"""One exception type for bad user input.

Every surface (CLI, scenario files, sweeps) turns :class:`InputError` into exit status 2
and a single line on stderr; anything else is a bug and keeps its traceback.
"""

import math


class InputError(ValueError):
    """A parameter, file or scenario that cannot be run; the message names the problem."""


class MissingExtra(InputError, ImportError):
    """An optional library is not installed: the message names the extra that brings it.

    Why both bases: the CLI turns any :class:`InputError` into one line and exit status 2,
    and Python code expects a missing library to be an :class:`ImportError` (``try: import
    swarmex.envs except ImportError: ...``); as an InputError alone, that ``except`` missed
    it and the import ended in a traceback instead of the fallback."""


def check_number(value: float, option: str, *, above: float | None = None,
                 at_least: float | None = None) -> None:
    """``value`` must be a finite number, above or at least a bound: one line naming the
    option otherwise. Why "finite" is said: ``inf`` and ``nan`` pass or fail a bare
    comparison by accident, and "must be > 0, got inf" reads as a contradiction."""
    bound = (f" > {above:g}" if above is not None
             else f" >= {at_least:g}" if at_least is not None else "")
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise InputError(f"{option} must be a finite number{bound}, got {value}")
    if (above is not None and not value > above) or (at_least is not None and value < at_least):
        raise InputError(f"{option} must be{bound}, got {value}")


def require(module: str, extra: str, what: str) -> None:
    """Import ``module`` or fail in one line naming the extra to install.

    Heavy optional pieces (the web monitor, the MP4 writer, Ray) live in extras so that
    ``pip install swarmex`` stays small; a user who reaches for one without it gets
    ``MissingExtra("<what> needs <module>: pip install 'swarmex[<extra>]'")``, which the CLI
    prints as one line with exit status 2 and Python code can catch as an ImportError.
    """
    import importlib

    try:
        importlib.import_module(module)
    except ImportError:
        err = MissingExtra(f"{what} needs {module}: pip install 'swarmex[{extra}]'")
        err.name = module  # ImportError's: which module is missing
        raise err from None
