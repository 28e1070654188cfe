"""Seed 004: WMA-RRT roadmap coverage and goal search against PRM (Tables 1–2, Figs. 6–17).

:mod:`.design` (environments, the plan of jobs, the paper's tables) → :mod:`.runs` (the
journaled runs) and :mod:`.readings` (the study of ε, N and r readings) → :mod:`.analysis`
(the tables beside the paper's) → :mod:`.figures` → :mod:`.report` (``roadmap.md``).
:func:`reproduce` (:mod:`.pipeline`) does all of it.
"""

from swarmex.studies.roadmap.pipeline import reproduce

__all__ = ["reproduce"]
