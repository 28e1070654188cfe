"""``swarmex reproduce traversal``: plan, run (or resume), then write figures and report."""

from __future__ import annotations

import random
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from swarmex import __version__
from swarmex.errors import InputError
from swarmex.experiments.pool import check_workers, local_processes
from swarmex.experiments.runstore import RunStore
from swarmex.studies.runner import run_jobs
from swarmex.studies.traversal.design import AGENT_PARAMS, Config, RunSpec, build_plan
from swarmex.studies.traversal.runs import execute


def reproduce(
    out: Path,
    quick: bool = False,
    workers: int | None = None,
    reps: int | None = None,
    progress: Callable[[int, int], Any] | None = None,
    console=None,
) -> dict[str, Any]:
    """Run (or resume) the sweep into ``out``/traversal.json, then write figures and report.

    Returns a small summary (paths, runs executed, elapsed seconds) for the CLI to print.
    """
    from swarmex.studies.traversal.report import write_outputs

    # a negative count planned no run at all and wrote an empty report without a word
    check_workers(workers, "workers")
    if reps is not None and reps < 1:
        raise InputError(f"reps must be >= 1, got {reps}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # the processes the pool will fork (at most a few per core), as recorded and reported
    workers = local_processes(workers if workers is not None else (1 if quick else 2))
    plan = build_plan(quick, reps)
    specs = plan.run_specs()
    drawn = plan_header(quick, reps)
    header = {
        "study": "traversal",
        "seed_file": "000_a5793bd95eb4b07a.txt",
        "format": 1,
        "swarmex_version": __version__,
        "agent_params": AGENT_PARAMS,
        "plan": drawn,  # the plan the report is drawn for: rebuild() draws it again
    }
    # a folder holding only traversal.json.gz (docs/reproduction/traversal) resumes from it
    store = RunStore(out / "traversal.json", header)
    sessions = list(store.previous.get("sessions", []))
    for key, cfg in plan.configs().items():
        store.add_config(key, cfg.params())
    already = sum(1 for s in specs if s.id in store)
    _credit_killed_session(sessions, already)
    # costly and cheap configurations mixed evenly (deterministically), so the progress rate
    # is steady and the ETA honest; the order cannot change results (each run has its seed)
    order = list(specs)
    random.Random(0).shuffle(order)
    t0 = time.perf_counter()

    stored = already
    # this session, on disk from its first run on (a killed session must still count; see
    # _credit_killed_session) and kept current at every periodic rewrite of the JSON
    session: dict[str, Any] = {
        "mode": "quick" if quick else "full",
        "workers": workers,
        "runs_planned": len(specs),
        "runs_executed": 0,
        "elapsed_s": 0.0,
        "finished": False,
    }

    def tick(_spec: RunSpec, _rec: dict[str, Any]) -> None:
        nonlocal stored
        stored += 1
        session["runs_executed"] = stored - already
        session["elapsed_s"] = round(time.perf_counter() - t0, 2)
        if stored == already + 1:  # a rerun that runs nothing is no session of the sweep
            store.header["sessions"] = [*sessions, session]
            store.flush()
        if progress:
            progress(stored, len(specs))

    try:
        run_jobs(
            order, execute, lambda s: s.id, store=store, workers=workers, label="traversal",
            console=console, show=console is not None, on_result=tick, warm=warm_kernels,
        )
    finally:
        elapsed = time.perf_counter() - t0
        # runs stored now and not before: also those that finished while an interrupted
        # session was stopping, and those a killed one left in the runner's spool
        executed = sum(1 for s in specs if s.id in store) - already
        if executed:
            session.update(
                runs_executed=executed,
                elapsed_s=round(elapsed, 2),
                finished=all(s.id in store for s in specs),
            )
            sessions.append(session)
        store.header["sessions"] = sessions
        if store.previous.get("plan") != drawn:
            # the JSON must name the plan of the report beside it, even when no run was added
            # (the store rewrites its JSON only when a run or configuration was)
            store.flush()
        store.close()
    paths = write_outputs(plan, store.runs, out, store.header)
    return {
        "json": store.path,
        "report": paths["report"],
        "figures": paths["figures"],
        "runs": len(specs),
        "executed": executed,
        "elapsed_s": elapsed,
        "workers": workers,
    }


def _credit_killed_session(sessions: list[dict[str, Any]], stored: int) -> None:
    """Give a killed session the runs it stored after the JSON's last rewrite.

    A session is written to the JSON at its first run and kept current at each periodic
    rewrite; a SIGKILL skips the final update, so the runs it journalled since then (the store
    recovers them) are counted by no session. They are the last session's: every earlier one
    ended with a final count.
    """
    missing = stored - sum(int(x.get("runs_executed", 0)) for x in sessions)
    if sessions and missing > 0:
        sessions[-1]["runs_executed"] = int(sessions[-1].get("runs_executed", 0)) + missing


def warm_kernels() -> None:
    """Compile (or load from numba's cache) every kernel a run uses, once, in the driver
    before the workers are forked from it.

    Why: on a cold cache each worker compiled the same ~115 kernels itself (about 14 s of
    CPU each), silently, so the first sweep showed nothing for ~30 s and paid the compile
    once per worker; compiled here, the compile notice is shown and the forked workers start
    with the machine code. A 6x6 run with obstacles reaches every kernel any run of the plan
    calls (its result is thrown away; runs do not depend on one another).
    """
    execute(RunSpec(Config(6, 40.0, 3, (1,), obstacles=4), 0))


def plan_header(quick: bool, reps: int | None) -> dict[str, Any]:
    """How ``traversal.json`` names the plan its report was drawn for (see
    :func:`.report.rebuild`)."""
    return {"quick": bool(quick), "reps": reps}


