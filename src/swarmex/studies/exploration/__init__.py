"""Seed 003, chapter 4: decentralized exploration with laser robots (Figs. 4.1–4.4).

:mod:`.design` (the thesis's sweep, the team-size study, the strategy scenarios) → :mod:`.runs`
(one run; the study runner keeps them in ``runs.jsonl``) → :mod:`.analysis` (the thesis's
trends, checked) → :mod:`.figures` (Figs. 4.1–4.4, strategies) → :mod:`.report`
(``exploration.md``). :func:`reproduce` (:mod:`.pipeline`) does all of it.
"""

from swarmex.studies.exploration.pipeline import reproduce

__all__ = ["reproduce"]
