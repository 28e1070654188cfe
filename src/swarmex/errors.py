"""One exception type for bad user input.

Every surface (CLI, scenario files, sweeps) turns :class:`InputError` into exit status 2
and a single line on stderr; anything else is a bug and keeps its traceback.
"""


class InputError(ValueError):
    """A parameter, file or scenario that cannot be run; the message names the problem."""
