"""Map axes carry the map's own coordinates, so a reader can find a cell the record names."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from swarmex.viz.axes import MAX_TICKS, coordinate_ticks


@pytest.mark.parametrize("g", [5, 16, 32, 128, 1000])
def test_grid_ticks_are_whole_cells_inside_the_map(g):
    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_xlim(-0.5, g - 0.5)
    ax.set_ylim(g - 0.5, -0.5)  # row 0 at the top
    coordinate_ticks(ax, unit="cells")
    fig.canvas.draw()
    for ticks in (ax.get_xticks(), ax.get_yticks()):
        inside = ticks[(ticks >= -0.5) & (ticks <= g - 0.5)]
        assert 2 <= len(inside) <= MAX_TICKS + 1
        assert np.all(inside == np.round(inside)) and 0 in inside
    assert ax.get_xlabel() == "x (cells)" and ax.get_ylabel() == "y (cells)"
    assert ax.yaxis_inverted()


def test_continuous_maps_get_plain_coordinates():
    fig = Figure()
    ax = fig.add_subplot()
    ax.set_xlim(0, 0.6)
    coordinate_ticks(ax, integer=False)
    ticks = ax.get_xticks()
    assert np.any(ticks != np.round(ticks)) and ax.get_xlabel() == "x"


@pytest.mark.parametrize("dpi", [64, 80, 110])
def test_map_text_is_legible_at_an_animations_dpi(dpi):
    # an animation's frames (64-80 dpi) had 6 pt ticks: 4-5 pixels, unreadable
    ax = Figure(dpi=dpi).add_subplot(111)
    coordinate_ticks(ax, unit="cells")
    tick_px = ax.xaxis.get_major_ticks()[0].label1.get_fontsize() * dpi / 72
    label_px = ax.xaxis.label.get_fontsize() * dpi / 72
    assert tick_px >= 8 - 1e-9 and label_px >= 9 - 1e-9
    if dpi >= 110:  # the pictures keep their sizes
        assert ax.xaxis.label.get_fontsize() == 7
