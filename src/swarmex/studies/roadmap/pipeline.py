"""``swarmex reproduce roadmap``: run (or resume) the jobs, the readings study, the report."""

from __future__ import annotations

import os
import time
from pathlib import Path

from rich.console import Console

from swarmex import __version__
from swarmex.experiments.progress import Journal
from swarmex.studies.roadmap.buildtime import cached_build_times
from swarmex.studies.roadmap.design import plan
from swarmex.studies.roadmap.readings import cached_readings_study
from swarmex.studies.roadmap.runs import describe, job_key, run_job
from swarmex.studies.runner import run_jobs


def reproduce(
    out: str | Path, quick: bool = False, console: Console | None = None, workers: int = 2
) -> Path:
    from swarmex.studies.roadmap.report import write_report

    console = console or Console()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jobs = plan(quick)
    t0 = time.perf_counter()
    with Journal(out / "roadmap_runs.jsonl") as journal:
        done = run_jobs(jobs, run_job, job_key, store=journal,
                        workers=max(1, min(workers, os.cpu_count() or 1)), label="roadmap",
                        console=console, describe=describe)
    results, new_runs = done.results, done.ran
    console.print("readings study (trees swept edge by edge)…")
    study = cached_readings_study(out, quick)
    console.print("build times (CPU, in this process)…")
    builds = cached_build_times(out, quick)
    report = write_report(out, results, quick=quick, seconds=time.perf_counter() - t0,
                          version=__version__, new_runs=new_runs, study=study, builds=builds)
    console.print(f"report: {report}")
    return report
