"""Static figures and animations of result records (matplotlib Agg, imageio)."""

from swarmex.viz.traversal import as_record, frame_times, traversal_gif, traversal_png

__all__ = ["as_record", "frame_times", "traversal_gif", "traversal_png"]
