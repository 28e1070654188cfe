"""The seeds' studies, reproduced: one package per seed (``swarmex reproduce STUDY``).

Each study is split by job, lowest first:

* ``design``   which runs: the seed's fixed parameters, the plan, its reference numbers;
* ``runs``     one run: the study's job function (a picklable module-level function of a
  job), which :func:`swarmex.studies.runner.run_jobs` — the one runner of every study —
  runs in worker processes, keeping the results in a resumable journal or run store;
* ``analysis`` tables, means and confidence intervals (:mod:`swarmex.engine.stats`) from the
  stored runs;
* ``figures``  the seed's figures redrawn from the analysis;
* ``report``   the Markdown report beside the seed's own numbers;
* ``pipeline`` :func:`reproduce`, plan → run → analyse → draw → write, re-exported by the
  study's package.

Reports and figures are rebuilt from the stored runs, so an interrupted reproduction resumes
and a report can be rewritten without rerunning. The seeds' reference numbers ship in
``studies/reference/`` (copied from ``../shared/reference/``) and are read with
:func:`reference_file`, so reports work from an installed package. Studies sit above the
missions and ``viz`` (they draw with it) and beside ``experiments`` (whose process pool,
progress bar, journal and run store the runner uses); only the CLI imports them.
"""

from __future__ import annotations

from importlib import resources
from importlib.resources.abc import Traversable

STUDIES = ("traversal", "foraging", "exploration", "roadmap")


def reference_file(name: str) -> Traversable:
    """A seed's reference table shipped in the package: ``studies/reference/<name>``."""
    return resources.files(__name__) / "reference" / name
