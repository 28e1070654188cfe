"""The array types and hop sentinels that the planning kernels and their callers share.

The numba kernels of :mod:`swarmex.planning.distance`, :mod:`swarmex.planning.hop_shift`,
:mod:`swarmex.planning.hop_repair` and :mod:`swarmex.planning.fieldcache` take the same
CSR arrays, masks, scratch and hop rows; naming them once keeps their signatures readable
and in agreement, and lets those modules share them without importing each other.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

#: hop count of a vertex no source reaches (any negative value means unreached)
UNREACHED = np.int32(-1)
#: hop-kernel template value of a blocked vertex: negative (unreached) but not UNREACHED,
#: so the search needs one comparison per neighbour instead of a second array
BLOCKED = np.int32(-2)

# array types of the kernels' arguments (the CSR arrays are NodeGraph's)
Indptr = NDArray[np.int64]
Indices = NDArray[np.int32]
Weights = NDArray[np.float64]
Mask = NDArray[np.bool_]
Vertices = NDArray[np.int64]
#: 4-connected lattice neighbour bits (see :func:`~swarmex.planning.distance.lattice_structure`)
NbMask = NDArray[np.uint8]
#: int32 scratch: search queues and lists of vertices
Scratch = NDArray[np.int32]
#: hop counts: int32 fields; a KnownGraph's table holds int16 until it needs int32
Hops = NDArray[np.signedinteger[Any]]
#: a distance field (inf: unreachable)
Field = NDArray[np.float64]
