"""Communication models: the broadcast channel (:mod:`.channel`: perfect, loss, delay, limited
range), the exploration mesh's flooding (:mod:`.mesh`) and AODV routes (:mod:`.aodv`), and
message sizes (:mod:`.message`)."""

from swarmex.comm.channel import Channel

__all__ = ["Channel"]
