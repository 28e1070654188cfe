"""Communication models: perfect broadcast, loss, delay, limited range."""

from swarmex.comm.channel import Channel

__all__ = ["Channel"]
