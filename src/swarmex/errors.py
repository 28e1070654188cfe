"""One exception type for bad user input.

Every surface (CLI, scenario files, sweeps) turns :class:`InputError` into exit status 2
and a single line on stderr; anything else is a bug and keeps its traceback.
"""


class InputError(ValueError):
    """A parameter, file or scenario that cannot be run; the message names the problem."""


def require(module: str, extra: str, what: str) -> None:
    """Import ``module`` or fail in one line naming the extra to install.

    Heavy optional pieces (the web monitor, the MP4 writer, Ray) live in extras so that
    ``pip install swarmex`` stays small; a user who reaches for one without it gets
    ``InputError("<what> needs <module>: pip install 'swarmex[<extra>]'")``, which the CLI
    prints as one line with exit status 2.
    """
    import importlib

    try:
        importlib.import_module(module)
    except ImportError:
        raise InputError(f"{what} needs {module}: pip install 'swarmex[{extra}]'") from None
