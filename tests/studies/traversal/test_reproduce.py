"""``swarmex reproduce traversal --quick`` end to end, plus the pieces the report relies on."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from swarmex.cli import main
from swarmex.experiments.runstore import RunStore
from swarmex.studies.runner import run_jobs
from swarmex.studies.traversal.analysis import best_fleet, optimum_6x6
from swarmex.studies.traversal.design import (
    Config,
    RunSpec,
    build_plan,
    diagonal_node,
    reference_rows,
    thesis_node,
)
from swarmex.studies.traversal.runs import execute


@pytest.fixture(scope="module")
def quick_out(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("traversal")
    assert main(["reproduce", "traversal", "--quick", "--out", str(out)]) == 0
    return out


def test_quick_run_writes_report_figures_and_raw_runs(quick_out):
    report = (quick_out / "traversal.md").read_text()
    for name in (f"fig_5_{k}.png" for k in range(1, 15)):
        png = quick_out / name
        assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        assert f"({name})" in report
    data = json.loads((quick_out / "traversal.json").read_text())
    plan = build_plan(quick=True)
    assert set(data["runs"]) == {s.id for s in plan.run_specs()}
    rec = next(iter(data["runs"].values()))
    assert rec["complete"] and rec["totals"]["nodes_missed"] == 0
    assert data["sessions"][-1]["mode"] == "quick"
    assert not (quick_out / "traversal.journal.jsonl").exists()


def test_report_has_every_thesis_number_beside_ours(quick_out):
    report = (quick_out / "traversal.md").read_text()
    assert "Headline: corner nests" in report and "[450.45, 453.07]" in report
    for row in reference_rows():
        assert f"[{row.ci_low:.2f}, {row.ci_high:.2f}]" in report, row
        assert f"{row.min:.2f}–{row.max:.2f}" in report, row
        assert f"{row.mean:.2f} ({row.std:.2f})" in report, row
    for stated in ("4750", "4580", "4760", "2300", "1500", "450"):
        assert f"| {stated} |" in report
    assert "| CIs overlap |" in report
    # the quick plan's 6 runs per group were reported as "We use 108 runs per group"
    assert "We use 6 runs per group and the honest n" in report


def test_thesis_numbering():
    # node 1 bottom-left, row-major upwards; GridWorld row 0 is the top row
    assert thesis_node(1, 6) == 30 and thesis_node(6, 6) == 35
    assert thesis_node(31, 6) == 0 and thesis_node(36, 6) == 5
    assert [diagonal_node(d, 6) for d in (1, 2, 3)] == [8, 15, 22]


def test_table_groups_are_the_six_symmetry_classes():
    groups = build_plan(quick=False).groups
    assert [len(g.config.nests) for g in groups] == [4, 8, 8, 4, 8, 4]
    assert sorted(k for g in groups for k in g.config.nests) == list(range(1, 37))
    assert all(g.reps == 108 for g in groups)


def test_optimum_by_hand():
    best, corner_floor = optimum_6x6(nest_degree=2)
    assert best == pytest.approx(360 + 35 * 40 / 6 / 3)  # 437.78 s
    assert corner_floor == pytest.approx(360 + 36 * 40 / 6 / 3)  # 440.00 s
    assert optimum_6x6(nest_degree=3)[1] == pytest.approx(best)


def test_best_fleet_thresholds():
    # the thesis's own numbers: T(2) - T(3) = 2300 - 1536 = 764 s is the 2↔3 switch
    bands = best_fleet({2: 2300.0, 3: 1536.0})
    assert bands[0] == (3, 0.0, pytest.approx(764.0))
    assert bands[-1][0] == 2 and math.isinf(bands[-1][2])
    three = best_fleet({2: 2300.0, 3: 1500.0, 10: 450.0})
    assert [n for n, _, _ in three] == [10, 3, 2]
    assert three[0][2] == pytest.approx(150.0)  # (1500 - 450) / 7


def test_results_do_not_depend_on_workers_and_sweeps_resume(tmp_path):
    specs = [RunSpec(Config(6, 40.0, 3, (1, 8)), r) for r in range(3)]
    specs.append(RunSpec(Config(6, 40.0, 3, (3,), obstacles=4), 0))

    def sweep(path: Path, workers: int, subset) -> tuple[dict, int]:
        store = RunStore(path, {})
        n = run_jobs(subset, execute, lambda s: s.id, store=store, workers=workers, show=False).ran
        store.close()
        return json.loads(path.read_text())["runs"], n

    serial, n1 = sweep(tmp_path / "a.json", 1, specs)
    parallel, n2 = sweep(tmp_path / "b.json", 2, specs)
    assert n1 == n2 == 4

    def strip(runs: dict) -> dict:
        return {k: {f: v for f, v in r.items() if f != "wall_seconds"} for k, r in runs.items()}

    assert strip(serial) == strip(parallel)
    assert len(parallel[specs[-1].id]["obstacles"]) == 4
    # resume: only the missing run is executed
    _, n3 = sweep(tmp_path / "c.json", 1, specs[:2])
    _, n4 = sweep(tmp_path / "c.json", 1, specs)
    assert (n3, n4) == (2, 2)


def test_rebuild_draws_the_plan_the_sweep_ran(quick_out, tmp_path):
    # rebuild(DIR) assumed the full plan: a quick sweep's report came back titled "full plan,
    # 9072 runs", with bars the quick plan does not draw
    import shutil

    from swarmex.studies.traversal.report import rebuild

    shutil.copy(quick_out / "traversal.json", tmp_path / "traversal.json")
    rebuild(tmp_path)
    assert (tmp_path / "traversal.md").read_text() == (quick_out / "traversal.md").read_text()
    # another plan than the JSON holds: its header claimed "full plan ..., 4200 runs" over
    # tables of 6 runs; now refused, naming what is missing, and the report is left alone
    from swarmex.errors import InputError

    full = {s.id for s in build_plan(False, 50).run_specs()}
    have = len(full & {s.id for s in build_plan(quick=True).run_specs()})
    with pytest.raises(InputError, match=f"holds {have} of the {len(full)} runs of the full "
                       rf"plan \(--runs 50\): {len(full) - have} are missing"):
        rebuild(tmp_path, quick=False, reps=50)
    assert (tmp_path / "traversal.md").read_text() == (quick_out / "traversal.md").read_text()


def test_a_rerun_that_runs_nothing_is_no_session(quick_out, tmp_path):
    # the report counted it ("2 session(s)") while the JSON, not rewritten, kept one
    import shutil

    from swarmex.studies.traversal import reproduce

    shutil.copy(quick_out / "traversal.json", tmp_path / "traversal.json")
    assert reproduce(tmp_path, quick=True)["executed"] == 0
    assert len(json.loads((tmp_path / "traversal.json").read_text())["sessions"]) == 1
    assert "executed in 1 session(s)" in (tmp_path / "traversal.md").read_text()


def test_a_gzipped_json_is_resumed_and_kept_gzipped(quick_out, tmp_path):
    # only rebuild() read traversal.json.gz: a rerun in docs/reproduction/traversal redid
    # every run into a new traversal.json beside it
    import gzip

    from swarmex.studies.traversal import reproduce

    data = json.loads((quick_out / "traversal.json").read_text())
    del data["plan"]  # as the committed .gz, written before the header named its plan
    with gzip.open(tmp_path / "traversal.json.gz", "wt", encoding="utf-8") as fh:
        json.dump(data, fh)
    summary = reproduce(tmp_path, quick=True)
    assert summary["executed"] == 0 and summary["json"] == tmp_path / "traversal.json.gz"
    assert not (tmp_path / "traversal.json").exists()
    with gzip.open(tmp_path / "traversal.json.gz", "rt", encoding="utf-8") as fh:
        again = json.load(fh)
    assert again["runs"] == data["runs"] and again["plan"] == {"quick": True, "reps": None}
    assert (tmp_path / "traversal.md").read_text() == (quick_out / "traversal.md").read_text()


def test_runs_option_is_named_and_redrawn(tmp_path):
    # a --runs sweep was reported as the "full" plan, and rebuild() drew the full plan
    from swarmex.studies.traversal import reproduce
    from swarmex.studies.traversal.report import rebuild

    reproduce(tmp_path, reps=1)
    report = (tmp_path / "traversal.md").read_text()
    assert "`swarmex reproduce traversal --runs 1`" in report
    assert "**full** plan with 1 run per table group and figure bar, 84 runs." in report
    # one run has no STD nor interval: it read "451.11 (0.00)", "[451.11, 451.11] (1) | yes"
    # and "+inf of our standard errors" for a mean below the thesis's
    assert "95 % CI **n/a** (n = 1)" in report and "overlap is not judged" in report
    assert "standard errors" not in report.split("## Tables")[0].split("n = 1)")[1]
    row = next(line for line in report.splitlines() if line.startswith("| totalTimeAll |"))
    assert row.endswith("(n/a) | [450.45, 453.07] | n/a (1) | – | 108 |")
    assert not re.search(r"\b(nan|inf)\b", report)
    rebuild(tmp_path)
    assert (tmp_path / "traversal.md").read_text() == report
    # the JSON names the plan of the last report drawn, so rebuild() draws that one
    reproduce(tmp_path, quick=True)
    assert json.loads((tmp_path / "traversal.json").read_text())["plan"]["quick"] is True
    quick_report = (tmp_path / "traversal.md").read_text()
    rebuild(tmp_path)
    assert (tmp_path / "traversal.md").read_text() == quick_report


WARM_CHECK = """
import json
from swarmex import _kernels
from swarmex.studies.traversal.design import build_plan
from swarmex.studies.traversal.pipeline import warm_kernels
from swarmex.studies.traversal.runs import execute

def signatures():
    return {f"{k.__module__}.{k.__qualname__}": len(k._dispatcher.signatures)
            for k in _kernels._all if k._dispatcher is not None}

warm_kernels()
warmed = signatures()
for spec in build_plan(quick=True).run_specs():  # every grid size, obstacles, uneven starts
    execute(spec)
print(json.dumps({"warmed": warmed, "after": signatures()}))
"""


def test_the_driver_readies_every_kernel_before_the_workers_fork():
    # on a cold cache each worker compiled the same kernels itself (2 workers: 36.6 s wall,
    # 28.8 s CPU for the first `--runs 1` sweep, and no notice); warm_kernels() compiles them
    # once in the driver, so it must reach every kernel any run of the plan calls
    import os
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parents[3] / "src")}
    out = subprocess.run(
        [sys.executable, "-c", WARM_CHECK], capture_output=True, text=True, env=env, check=True
    ).stdout
    got = json.loads(out.splitlines()[-1])
    assert got["warmed"] and got["warmed"] == got["after"]


def test_bad_counts_and_a_missing_json_are_clear(tmp_path):
    # reps=-1 planned no run and wrote an empty report without a word; rebuild() of a folder
    # without runs named only the .gz it had looked for last
    from swarmex.errors import InputError
    from swarmex.studies.traversal import reproduce
    from swarmex.studies.traversal.report import rebuild

    with pytest.raises(InputError, match="reps must be >= 1"):
        reproduce(tmp_path / "a", reps=-1)
    with pytest.raises(InputError, match="workers must be between 1 and 1024"):
        reproduce(tmp_path / "a", workers=0)
    assert not (tmp_path / "a").exists()
    with pytest.raises(FileNotFoundError, match=r"no traversal\.json \(or traversal\.json\.gz\)"):
        rebuild(tmp_path)


def test_a_killed_session_is_counted_with_its_runs(tmp_path):
    # SIGKILL skipped the session's final bookkeeping: the report said "1 session(s)" and
    # gave the killed session's runs to the next one (or to none)
    import multiprocessing
    import os

    from swarmex.studies.traversal import reproduce

    def killed_at_50() -> None:
        def progress(done: int, _total: int) -> None:
            if done == 50:
                os._exit(9)  # no finally, no flush: as a SIGKILL leaves it

        reproduce(tmp_path, quick=True, progress=progress)

    child = multiprocessing.get_context("fork").Process(target=killed_at_50)
    child.start()
    child.join(120)
    assert child.exitcode == 9
    summary = reproduce(tmp_path, quick=True)
    sessions = json.loads((tmp_path / "traversal.json").read_text())["sessions"]
    assert [s["finished"] for s in sessions] == [False, True]
    assert [s["runs_executed"] for s in sessions] == [50, summary["runs"] - 50]
    assert summary["executed"] == summary["runs"] - 50
    assert "executed in 2 session(s)" in (tmp_path / "traversal.md").read_text()


def test_fleet_chart_titles_name_the_fleets_drawn():
    # the quick plan's Fig. 5.13 was titled "2–6 agents" over the 2- and 3-agent lines only
    from swarmex.studies.traversal.figures import agent_counts

    assert agent_counts([2, 3, 4, 5, 6]) == "2–6"
    assert agent_counts([2, 3]) == "2, 3" and agent_counts([10]) == "10"


def test_a_delayed_channel_does_not_livelock_the_6x6_runs():
    # the report said a 1 s delay "can make two agents swap forever" on the 6x6 grid, and
    # left the latency experiment out for it; the report's sentence now rests on this
    import swarmex

    for nest in ("0,5", "1,5", "2,5", "1,4", "2,4", "2,3"):  # one of each symmetry group
        for seed in range(3):
            r = swarmex.run("traversal", grid="6x6", agents=3, nests=nest, travel_time=2.222,
                            job_time=10, delay=1.0, altitude=5, up_speed=1.5, down_speed=0.3,
                            seed=seed)
            assert r.complete, (nest, seed)
