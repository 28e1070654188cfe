"""One exception type for bad user input.

Every surface (CLI, scenario files, sweeps) turns :class:`InputError` into exit status 2
and a single line on stderr; anything else is a bug and keeps its traceback.
"""


class InputError(ValueError):
    """A parameter, file or scenario that cannot be run; the message names the problem."""


class MissingExtra(InputError, ImportError):
    """An optional library is not installed: the message names the extra that brings it.

    Why both bases: the CLI turns any :class:`InputError` into one line and exit status 2,
    and Python code expects a missing library to be an :class:`ImportError` (``try: import
    swarmex.envs except ImportError: ...``); as an InputError alone, that ``except`` missed
    it and the import ended in a traceback instead of the fallback."""


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
