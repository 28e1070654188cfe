"""PettingZoo environments over the four missions (issue 13).

Each environment drives the same worlds, sensing, channel and agent cores as
``swarmex.run``: the mission's simulator runs unchanged and the decisions its agents take are
handed to the environment's caller (:mod:`swarmex.envs.broker`; foraging instead steps the
mission's hooked run, a generator, in the caller's thread). Modules follow PettingZoo's
convention: ``swarmex.envs.traversal_v0.env()`` / ``parallel_env()`` / ``raw_env``.
PettingZoo itself is an optional extra: ``pip install 'swarmex[envs]'``.
"""

from swarmex.errors import require

require("pettingzoo", "envs", "swarmex.envs")  # one line naming the extra, not a traceback
