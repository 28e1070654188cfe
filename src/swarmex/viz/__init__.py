"""Static figures and animations of result records (matplotlib Agg, imageio)."""

# exports load on first use (swarmex._lazy: the Params import without the simulator)
from typing import Any as _Any

from swarmex._lazy import lazy_attribute as _lazy_attribute

_EXPORTS = {
    "as_record": "traversal",
    "frame_times": "traversal",
    "traversal_gif": "traversal",
    "traversal_png": "traversal",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> _Any:
    return _lazy_attribute(__name__, _EXPORTS, name)
