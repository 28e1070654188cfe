"""Writing a figure file: atomically, in one line on failure, the same bytes for the same run.

Every drawing (a mission's PNG, a sweep's plot, a study's figure) goes through
:func:`save_figure`, so that a Ctrl-C or a full disk in the middle of a write leaves the
previous file as it was rather than a truncated image under its name (matplotlib and Pillow
write straight to the path they are given), and an SVG does not change on every run
(matplotlib stamps it with the date and salts its element ids at random).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmex.engine.atomic import atomic_path
from swarmex.errors import InputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def save_figure(fig: Figure, path: Path, **savefig: Any) -> Path:
    """Write ``fig`` to ``path`` in the format its suffix names, making its folder; the file
    appears whole or not at all. A path that cannot be written (no permission, a full disk)
    is one :class:`~swarmex.errors.InputError` line."""
    import matplotlib as mpl

    path = Path(path)
    fmt = path.suffix.lower()[1:] or "png"
    if fmt == "svg":
        savefig.setdefault("metadata", {"Date": None})
    try:
        with atomic_path(path) as tmp, mpl.rc_context({"svg.hashsalt": "swarmex"}):
            fig.savefig(tmp, format=fmt, **savefig)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror or exc}") from None
    return path

