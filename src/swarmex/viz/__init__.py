"""Figures and animations of runs (matplotlib Agg, imageio): one module per mission
(:mod:`.traversal`, :mod:`.foraging`, :mod:`.exploration`, :mod:`.roadmap_plot`), one entry
for all of them (:mod:`.render`: the frames a drawing needs, then the drawing), the animation
writer (:mod:`.animation`), figure files written whole (:mod:`.files`), sweep plots
(:mod:`.plot`, :mod:`.candles`) and the live monitor (:mod:`.monitor`)."""

# exports load on first use (swarmex._lazy): importing viz draws in no mission's modules
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
