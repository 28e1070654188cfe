"""swarmex: teams of agents that explore, cover and search unknown environments.

The package is organised as a simulation core (``worlds``, ``sensing``, ``planning``,
``comm``, ``engine``), the four missions of the source studies (``missions``) and the
surfaces users touch (``net``, ``experiments``, ``viz``, ``cli``).
"""

__version__ = "0.1.0"
