"""``swarmex reproduce exploration``: run (or resume) the jobs, draw, check and report."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from swarmex.experiments.progress import Journal
from swarmex.studies.exploration.analysis import checks, fastest_size, steps_table, team_table
from swarmex.studies.exploration.design import (
    FULL,
    QUICK,
    QUICK_SCENARIOS,
    SCENARIOS,
    STRATEGY_ORDER,
    TEAM_VARIANTS,
    THESIS_SNAPSHOT_STEPS,
    job_key,
    missing_maps,
    picture_jobs,
    skipped_note,
    strategy_jobs,
    sweep_jobs,
    team_jobs,
)
from swarmex.studies.exploration.report import write_report
from swarmex.studies.exploration.runs import describe, run_job
from swarmex.studies.runner import run_jobs


def reproduce(
    out: Path, quick: bool = False, workers: int = 2, progress: Callable[[str], None] = print
) -> Path:
    from swarmex.studies.exploration import figures as figs

    t0 = time.perf_counter()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    d = QUICK if quick else FULL
    scenarios = QUICK_SCENARIOS if quick else SCENARIOS
    runs_file = out / "runs.jsonl"
    sweep = sweep_jobs(d)
    strat = strategy_jobs(scenarios, 1 if quick else 3)
    skipped = missing_maps(scenarios)
    if skipped:
        progress(skipped_note(skipped))
    teams = [j for j in team_jobs(d, quick) if j["kind"] == "teamsize"]
    jobs = sweep + teams + strat
    with Journal(runs_file) as journal:
        done = run_jobs(jobs, run_job, job_key, store=journal, workers=workers,
                        label="exploration", describe=describe)
    results = {job_key(j): r for j, r in zip(jobs, done.results, strict=True)}
    shots = picture_jobs(d)
    drawn = run_jobs(shots, run_job, job_key, workers=workers, label="pictures",
                     describe=describe)
    pics = {job_key(j): r for j, r in zip(shots, drawn.results, strict=True)}
    sweep_res = {job_key(j): results[job_key(j)] for j in sweep}
    strat_rows = [results[job_key(j)] for j in strat]
    figures = []
    tab = steps_table(sweep_res, d)
    figures.append(
        (
            "Fig. 4.1 — steps against team size",
            figs.fig4_1(tab, d.lasers, d.comms, d.sizes, out / "fig4_1.png"),
        )
    )
    panels = []
    for laser in (2.0, 1.5):
        for n in (1, 2, 5):
            r = next(
                v
                for v in pics.values()
                if v["job"]["kind"] == "fig4_2"
                and v["job"]["laser"] == laser
                and v["job"]["robots"] == n
            )
            p = r["pictures"]
            panels.append(
                {
                    "snap": p["final"],
                    "trajectories": p["trajectories"],
                    "truth": p["truth"],
                    "title": f"{n} robot{'s' if n > 1 else ''}, {r['makespan']} steps",
                }
            )
    figures.append(("Fig. 4.2 — paths after exploration", figs.fig4_2(panels, out / "fig4_2.png")))
    r43 = next(v for v in pics.values() if v["job"]["kind"] == "fig4_3")
    p = r43["pictures"]
    end = r43["makespan"]
    wanted = sorted({min(THESIS_SNAPSHOT_STEPS[0], round(0.15 * end)), round(0.45 * end),
                     round(0.85 * end), end})
    snaps = [
        min(p["snaps"] + [p["final"]], key=lambda s: (abs(s.t - w), -s.t)) for w in wanted
    ]
    caps = [f"step {s.t}" for s in snaps[:-1]] + [f"finished, step {end}"]
    figures.append(
        (
            "Fig. 4.3 — 10 robots at about 15 %, 45 % and 85 % of the run and at its end"
            " (thesis: steps 80, 580, 800; our robots are faster, docs/exploration.md)",
            figs.fig4_3(
                snaps, p["trajectories"], p["truth"], p["laser_cells"], caps, out / "fig4_3.png"
            ),
        )
    )
    series = {}
    for n in (1, 2, 5, 10):
        key = next(
            (
                k
                for k, v in sweep_res.items()
                if v["job"]["robots"] == n
                and v["job"]["comm"] == max(d.comms)
                and v["job"]["laser"] == 2.0
                and v["job"]["seed"] == 0
            ),
            None,
        )
        if key:
            series[n] = sweep_res[key]["plan_ticks"]
    figures.append(
        ("Fig. 4.4 — plan-generation intervals", figs.fig4_4(series, 20, out / "fig4_4.png"))
    )
    if strat_rows:
        scs = list(dict.fromkeys(r["job"]["scenario"] for r in strat_rows))
        figures.append(
            (
                "Strategies compared",
                figs.fig_strategies(
                    [
                        {
                            "scenario": r["job"]["scenario"],
                            "strategy": r["job"]["strategy"],
                            "makespan": r["makespan"],
                        }
                        for r in strat_rows
                    ],
                    scs,
                    list(STRATEGY_ORDER),
                    out / "fig_strategies.png",
                ),
            )
        )
    rows = checks(sweep_res, d)
    team_res = team_table(results, d)
    for row in rows:
        if row["trend"].startswith("an optimal team size") and team_res:
            sizes = sorted({n for v in team_res.values() for n in v})
            row["evidence"] += (
                f"; team-size study (below, {sizes[0]}–{sizes[-1]} robots), fastest: "
                + ", ".join(
                    f"{name} → {fastest_size(team_res[name])}"
                    for name in TEAM_VARIANTS
                    if name in team_res
                )
            )
    report = write_report(
        out, d, sweep_res, strat_rows, figures, rows, quick, time.perf_counter() - t0,
        (len(results), done.ran, len(pics)), team_res, skipped_maps=skipped,
    )
    for c in rows:
        progress(f"{'PASS' if c['holds'] else 'FAIL'}: {c['trend']} — {c['evidence']}")
    return report
