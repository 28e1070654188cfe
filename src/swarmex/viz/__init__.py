"""Static figures and animations of result records (matplotlib Agg, imageio)."""

# Exports load on first use (PEP 562), so that importing one module of this package (its
# Params, for the command line's options) does not import the simulator and its kernels.
from importlib import import_module as _import_module
from typing import Any as _Any

_EXPORTS = {
    "as_record": "traversal",
    "frame_times": "traversal",
    "traversal_gif": "traversal",
    "traversal_png": "traversal",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> _Any:
    if name in _EXPORTS:
        return getattr(_import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
