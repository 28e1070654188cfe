"""Seed 002, chapter 6: foraging patterns and transport on a 128×128 grid (Figs. 56–79).

:mod:`.design` (food cells per separation band, the configurations, the thesis's Figs. 78–79)
→ :mod:`.runs` (journaled runs) → :mod:`.analysis` (mean phase times, timetable-exact
exploration) → :mod:`.figures` (Figs. 56–77) → :mod:`.report` (``foraging.md``).
:func:`reproduce` (:mod:`.pipeline`) does all of it.
"""

from swarmex.studies.foraging.pipeline import reproduce

__all__ = ["reproduce"]
