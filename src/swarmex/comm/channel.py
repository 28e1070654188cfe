"""Who hears whom, and when.

:class:`Channel` decides, for one broadcast, which agents receive it and after what delay.
The default is the studies' assumption: a perfect, instantaneous, global broadcast (seed 000
§1.3). The options model what the thesis leaves as future work:

* ``loss``: each receiver independently misses the message with this probability;
* ``delay``: seconds (or steps) between sending and receiving;
* ``range``: only agents within this Euclidean distance of the sender hear it (walls ignored,
  as in seed 003's disc model).

Randomness comes from the run's generator, so lossy runs are reproducible.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from swarmex.errors import InputError


@dataclass(frozen=True)
class Channel:
    loss: float = 0.0
    delay: float = 0.0
    range: float = math.inf

    def __post_init__(self) -> None:
        if not 0.0 <= self.loss < 1.0:
            raise InputError(f"message loss must be in [0, 1), got {self.loss}")
        if self.delay < 0:
            raise InputError(f"message delay must be >= 0, got {self.delay}")
        if not self.range > 0:
            raise InputError(f"communication range must be > 0, got {self.range}")

    @property
    def perfect(self) -> bool:
        return self.loss == 0.0 and self.delay == 0.0 and math.isinf(self.range)

    def receivers(
        self,
        sender: int,
        positions: np.ndarray,
        rng: np.random.Generator,
        alive: np.ndarray | None = None,
    ) -> np.ndarray:
        """Indices of the agents (other than ``sender``) that receive one broadcast."""
        n = positions.shape[0]
        mask = np.ones(n, dtype=bool)
        mask[sender] = False
        if alive is not None:
            mask &= alive
        if not math.isinf(self.range):
            d = np.hypot(*(positions - positions[sender]).T)
            mask &= d <= self.range
        if self.loss > 0.0:
            mask &= rng.random(n) >= self.loss
        return np.nonzero(mask)[0]

    def describe(self) -> dict[str, Any]:
        return {
            "loss": self.loss,
            "delay": self.delay,
            "range": None if math.isinf(self.range) else self.range,
        }
