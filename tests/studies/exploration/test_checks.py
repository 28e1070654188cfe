"""The reproduction's trend checks on made-up results (the runs themselves are too slow here)."""

from __future__ import annotations

from swarmex.studies.exploration.analysis import checks, phase_intervals
from swarmex.studies.exploration.design import Design

D = Design(world_m=10.0, sizes=(1, 2, 10), comms=(5.0, 20.0), lasers=(2.0, 1.5), runs=1)


def fake(laser, comm, n, steps, plan_ticks=None, makespan=None):
    return {
        "job": {"kind": "sweep", "laser": laser, "comm": comm, "robots": n, "seed": 0},
        "mean_steps": steps, "makespan": makespan or steps, "complete": True,
        "explored_fraction": 1.0, "plan_ticks": plan_ticks or [[0]],
    }


def results(u_shape: bool):
    out = {}
    # ten robots: first third conflicts, middle third the 20-step timer, last third ping-pong
    ticks = [[0, 3, 6, 9, 20, 40, 60, 80, 100, 120, 121, 122, 123, 124, 125, 126]]
    for la, k in ((2.0, 1.0), (1.5, 1.2)):
        for c, extra in ((5.0, 50), (20.0, 0)):
            for n, s in ((1, 1000), (2, 600), (10, 400 if not u_shape else 700)):
                out[(la, c, n)] = fake(la, c, n, k * s + (extra if n > 1 else 0),
                                       ticks if n == 10 else None, 126 if n == 10 else None)
    return {str(key): v for key, v in out.items()}


def test_checks_pass_and_fail_as_the_numbers_say():
    rows = {r["trend"].split(":")[0]: r["holds"] for r in checks(results(False), D)}
    assert rows["teamwork cuts time"] is True
    assert rows["a shorter radio costs steps (5 m vs 20 m)"] is True
    assert rows["a shorter laser costs steps (1.5 m vs 2 m)"] is True
    assert rows["crowding at the end"] is True
    assert rows["an optimal team size"] is False
    assert any(k.startswith("10 robots, 20 m radio") and v for k, v in rows.items())
    rows = {r["trend"].split(":")[0]: r["holds"] for r in checks(results(True), D)}
    assert rows["an optimal team size"] is True


def test_phase_intervals_split_by_the_tick_of_the_later_plan():
    # thirds of 90 ticks: [0, 30), [30, 60), [60, 90]
    assert phase_intervals([[0, 10, 50, 60, 89]], 90) == [[10], [40], [10, 29]]


def test_report_cells_use_the_sample_sd():
    # the committed Fig. 4.1(a) cell, 10 robots, radio 20 m: runs 552.8, 514.6 and 528.4 were
    # printed "532 ± 16" (population SD) while the docs read them as the sample SD (19.3)
    from swarmex.studies.exploration.report import _fmt

    assert _fmt([552.8, 514.6, 528.4]) == "532 ± 19"
    assert _fmt([700.0]) == "700" and _fmt([]) == "–"


def test_report_counts_the_runs_it_reused_apart_from_the_picture_runs():
    # "53 runs (runs already in runs.jsonl are reused, not rerun)": 46 were journalled, and
    # the 7 picture runs are simulated again on every invocation
    from swarmex.studies.exploration.report import _runs_text

    text = _runs_text(46, 0, 7)
    assert "46 runs are journalled in `runs.jsonl`: 0 of them ran in this invocation" in text
    assert "The 7 runs drawn in Figs. 4.2–4.3" in text and "simulates them again" in text
    assert "53" not in text
