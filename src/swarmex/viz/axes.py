"""Decorating a map's axes: coordinate ticks and the legend beside it.

Why ticks on every map: a run's record, its summary and its options speak in coordinates
(a nest at ``(0,0)``, an obstacle at ``3,2``, the food cell, a robot's start), and a reader
checks them against the picture; without a scale a top-left ``(0,0)`` and a bottom-left one
look the same.
"""

from __future__ import annotations

from typing import Any

#: at most this many labelled ticks per axis: enough to read a cell off, few enough to stay legible
MAX_TICKS = 6


def coordinate_ticks(ax: Any, *, integer: bool = True, unit: str = "") -> None:
    """Small ticks labelled with the map's own coordinates (``x`` across, ``y`` as the map
    has it, downwards on grids); ``integer`` keeps them on whole cells, ``unit`` (if any)
    is named in the labels."""
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(MAX_TICKS, integer=integer, steps=[1, 2, 5, 10]))
    # at least 8 and 9 pixels tall: an animation's frames are drawn at 64-80 dpi, where 6 pt
    # is 4-5 pixels and could not be read (the pictures, at 110-120 dpi, keep 6 and 7 pt)
    dpi = float(ax.figure.dpi)
    ax.tick_params(labelsize=max(6.0, 8 * 72 / dpi), length=2, pad=1)
    suffix = f" ({unit})" if unit else ""
    size = max(7.0, 9 * 72 / dpi)
    ax.set_xlabel("x" + suffix, fontsize=size, labelpad=1)
    ax.set_ylabel("y" + suffix, fontsize=size, labelpad=1)


def side_legend(ax: Any, handles: list[Any]) -> None:
    """The legend beside the axes, top left, unframed: the map keeps its whole area, and
    :func:`~swarmex.viz.files.save_figure` with ``bbox_inches="tight"`` keeps the legend in the
    file."""
    size = max(7.0, 8 * 72 / float(ax.figure.dpi))  # as the ticks: legible in a low-dpi frame
    ax.legend(handles=handles, fontsize=size, loc="upper left", bbox_to_anchor=(1.01, 1),
              borderaxespad=0, frameon=False)
