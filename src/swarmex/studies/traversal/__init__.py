"""Seed 000, chapter 5: the MADGTA simulation series (Tables 5.1–5.2, Figs. 5.1–5.14).

:mod:`.design` (the plan and the thesis's parameters) → :mod:`.runs` (one run; the study runner
keeps them in ``traversal.json``, resumable) → :mod:`.analysis` (summaries and CIs beside the
thesis's rows, verdicts, best fleet size) → :mod:`.figures` (candlesticks, fleet cost) →
:mod:`.report` (``traversal.md``; :func:`~.report.rebuild` rewrites it from the JSON alone).
:func:`reproduce` (:mod:`.pipeline`) does all of it.
"""

from swarmex.studies.traversal.pipeline import reproduce

__all__ = ["reproduce"]
