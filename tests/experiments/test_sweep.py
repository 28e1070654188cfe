"""Sweeps: product expansion, Parquet columns, resume, failures, backends, summary CIs."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from swarmex.cli import main
from swarmex.cli.commands_sweep import _mean_ci, mission_shapes
from swarmex.engine.stats import summarize
from swarmex.errors import InputError
from swarmex.experiments.sweep import read_results, run_sweep
from swarmex.experiments.sweep_spec import load_sweep_spec, parse_sweep_spec

SPEC = """
mission = "traversal"
algorithm = ["madgta", "nearest"]
grid = "4x4"
agents = [1, 2]
seeds = [0, 1]
"""


def write_spec(tmp_path: Path, text: str = SPEC, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def sweep(path: Path, out: Path, backend: str = "serial", **kw):
    spec = load_sweep_spec(path)
    return run_sweep(spec, mission_shapes(spec.mission, path), out, backend=backend, **kw)


def records(out: Path) -> dict[str, dict]:
    """Every record of a sweep folder without wall_seconds (the one field allowed to vary)."""
    recs = {}
    for p in sorted((out / "runs").glob("*.json")):
        data = json.loads(p.read_text())
        data.pop("wall_seconds", None)
        recs[p.name] = data
    return recs


def table_rows(out: Path) -> list[dict]:
    rows = pq.read_table(out / "results.parquet").to_pylist()
    for r in rows:
        r.pop("wall_seconds")
    return rows


# ---------------------------------------------------------------------------- spec


def test_product_expansion_order_and_ids(tmp_path):
    spec = load_sweep_spec(write_spec(tmp_path))
    runs = spec.runs()
    assert len(runs) == 2 * 1 * 2 * 2
    assert [r.index for r in runs] == list(range(8))
    # axes in file order, seeds innermost
    assert [(r.params["algorithm"], r.params["agents"], r.seed) for r in runs[:4]] == [
        ("madgta", 1, 0),
        ("madgta", 1, 1),
        ("madgta", 2, 0),
        ("madgta", 2, 1),
    ]
    assert all(r.params["grid"] == "4x4" for r in runs)  # a scalar is a one-value column
    assert len({r.run_id for r in runs}) == 8
    assert [r.run_id for r in load_sweep_spec(spec.path).runs()] == [r.run_id for r in runs]
    shapes = mission_shapes("traversal", spec.path)
    assert spec.values(runs[3], shapes) == {
        "algorithm": "madgta",
        "grid": "4x4",
        "agents": 2,
        "seed": 1,
    }


def test_spec_fixed_table_seed_count_and_algorithm_option(tmp_path):
    spec = parse_sweep_spec(
        {
            "mission": "exploration",
            "algorithm": ["greedy", "greedy-exclusion"],
            "seeds": 3,
            "fixed": {"starts": ["1,1", "2,2"]},
        },
        tmp_path / "s.toml",
    )
    assert spec.seeds == [0, 1, 2]
    assert spec.param_names == ["algorithm", "starts"]
    run = spec.runs()[0]
    assert run.params["starts"] == ["1,1", "2,2"]  # [fixed] lists are one value, not an axis
    from swarmex.experiments.scenario import OptionShape

    shapes = {n: OptionShape(flag=f"--{n}") for n in ("strategy", "starts", "seed")}
    assert spec.values(run, shapes) == {
        "strategy": "greedy",
        "starts": ["1,1", "2,2"],
        "seed": 0,
    }


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"grid": "4x4"}, "no mission"),
        ({"mission": "flying"}, "unknown mission"),
        ({"mission": ["traversal"]}, "unknown mission"),  # unhashable: was a TypeError
        ({"mission": {"a": 1}}, "unknown mission"),
        ({"mission": "traversal", "json": "x.json"}, "cannot be set in a sweep"),
        ({"mission": "traversal", "agents": [2, 2]}, "lists a value twice"),
        # the same value as parsed: three runs of one, under three ids
        ({"mission": "traversal", "agents": [2, 2.0, "2"]},
         r"lists one value twice \(2 and 2\.0\)"),
        ({"mission": "traversal", "grid": ["5x5", [5, 5]]}, "lists one value twice"),
        ({"mission": "traversal", "map": ["m.map", "./m.map"]}, "lists one value twice"),
        ({"mission": "traversal", "seeds": [0, 0]}, "seed twice"),
        ({"mission": "traversal", "seeds": "many"}, "seeds must be"),
        # accepted before, and then every run with the seed failed inside numpy
        ({"mission": "traversal", "seeds": [-1, 2]}, "seeds must be >= 0, got -1"),
        ({"mission": "roadmap", "seed": -3}, "seeds must be >= 0, got -3"),
        ({"mission": "traversal", "agents": []}, "no values"),
        ({"mission": "traversal", "travel_time": 1, "travel-time": 2}, "given twice"),
    ],
)
def test_bad_specs_name_the_problem(tmp_path, data, message):
    with pytest.raises(InputError, match=message):
        parse_sweep_spec(data, tmp_path / "s.toml")


def test_unknown_option_fails_before_running(tmp_path, capsys):
    path = write_spec(tmp_path, 'mission = "traversal"\ngrid = "4x4"\nagents = 1\nspeed = [1, 2]\n')
    code = main(["sweep", str(path), "--backend", "serial", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2
    assert "has no option --speed" in err and len(err.strip().splitlines()) == 1
    assert not list((tmp_path / "o").glob("runs/*.json"))


def test_missing_required_option_fails_before_running(tmp_path, capsys):
    path = write_spec(tmp_path, 'mission = "foraging"\nagents = [2, 4]\nseeds = 2\n')
    code = main(["sweep", str(path), "--backend", "serial", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "swarmex forage needs --grid" in err and "add grid = " in err
    assert not list((tmp_path / "o").glob("runs/*"))


@pytest.mark.parametrize(("text", "says"), [
    # one of a group: every run used to fail the same way, and the sweep exited 0
    ('mission = "traversal"\nagents = [1, 2]\nseeds = 2\n',
     "swarmex traverse needs --map or --grid or --center"),
    ('mission = "traversal"\ngrid = "4x4"\nseeds = 2\n', "needs --agents or --fleet"),
    ('mission = "exploration"\nrobots = [1, 2]\nseeds = 2\n', "needs --map or --empty"),
])
def test_a_missing_one_of_a_group_fails_before_running(tmp_path, capsys, text, says):
    path = write_spec(tmp_path, text)
    code = main(["sweep", str(path), "--backend", "serial", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and says in err
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------------------- results


def test_parquet_columns_and_records_match_the_command(tmp_path, capsys):
    out = tmp_path / "out"
    result = sweep(write_spec(tmp_path), out)
    assert (result.total, result.ran, result.skipped, result.failed) == (8, 8, 0, 0)
    table, meta = read_results(out)
    names = table.column_names
    assert names[:8] == [
        "run",
        "algorithm",
        "grid",
        "agents",
        "seed",
        "complete",
        "makespan",
        "time_unit",
    ]
    assert names[-2:] == ["wall_seconds", "error"]
    assert {"total_time_all", "nodes_done_all", "messages"} <= set(names)
    assert str(table.schema.field("agents").type) == "int64"
    assert meta["params"] == ["algorithm", "grid", "agents"]
    assert meta["axes"] == ["algorithm", "agents"]
    rows = table.to_pylist()
    assert [(r["algorithm"], r["agents"], r["seed"]) for r in rows][:2] == [
        ("madgta", 1, 0),
        ("madgta", 1, 1),
    ]
    assert all(r["complete"] and r["error"] is None for r in rows)
    # the record of a run is the one `swarmex traverse` writes for the same options
    direct = tmp_path / "direct.json"
    argv = ["traverse", "--algorithm", "nearest", "--grid", "4x4", "--agents", "2"]
    assert main([*argv, "--seed", "1", "--json", str(direct)]) == 0
    capsys.readouterr()
    row = rows[-1]
    assert (row["algorithm"], row["agents"], row["seed"]) == ("nearest", 2, 1)
    ours = json.loads((out / "runs" / f"{row['run']}.json").read_text())
    theirs = json.loads(direct.read_text())
    ours.pop("wall_seconds"), theirs.pop("wall_seconds")
    assert ours == theirs
    assert row["makespan"] == theirs["makespan"]
    assert row["total_time_all"] == theirs["metrics"]["total_time_all"]


def test_failing_runs_are_recorded_and_do_not_stop_the_sweep(tmp_path):
    spec = 'mission = "traversal"\ngrid = "3x3"\nagents = [1, 40, 2]\nseeds = [0, 1]\n'
    out = tmp_path / "out"
    result = sweep(write_spec(tmp_path, spec), out)
    assert (result.ran, result.failed) == (6, 2)
    rows = pq.read_table(out / "results.parquet").to_pylist()
    assert [r["agents"] for r in rows] == [1, 1, 40, 40, 2, 2]
    failed = [r for r in rows if r["error"]]
    assert [r["agents"] for r in failed] == [40, 40]
    assert all("40 agents but the map has only 9 free cells" in r["error"] for r in failed)
    assert all(r["makespan"] is None and r["complete"] is None for r in failed)
    info = json.loads((out / "runs" / f"{failed[0]['run']}.error.json").read_text())
    assert info["params"]["agents"] == 40 and info["seed"] == 0 and info["error"]
    assert info["mission"] == "traversal"
    # failures count as finished; --retry-failed runs them again
    again = sweep(out.parent / "spec.toml", out)
    assert (again.ran, again.skipped) == (0, 6)
    retried = sweep(out.parent / "spec.toml", out, retry_failed=True)
    assert (retried.ran, retried.skipped, retried.failed) == (2, 4, 2)


def test_interrupted_sweep_resumes_and_skips_finished_runs(tmp_path):
    path = write_spec(tmp_path)
    out = tmp_path / "out"
    seen: list[str] = []

    def ctrl_c_after_three(outcome):
        seen.append(outcome.run_id)
        if len(seen) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(path, out, on_outcome=ctrl_c_after_three)
    assert len(list((out / "runs").glob("*.json"))) == 3
    assert len(pq.read_table(out / "results.parquet")) == 3  # written on the way out
    # a driver killed before its journal line: the record alone still counts as finished
    (out / "journal.jsonl").write_text(
        (out / "journal.jsonl").read_text().splitlines()[0] + "\n{truncated"
    )
    rerun: list[str] = []
    result = sweep(path, out, on_outcome=lambda o: rerun.append(o.run_id))
    assert (result.skipped, result.ran) == (3, 5)
    assert not set(rerun) & set(seen)
    fresh = tmp_path / "fresh"
    sweep(path, fresh)
    assert table_rows(out) == table_rows(fresh)
    assert records(out) == records(fresh)


def _await_records(proc: subprocess.Popen, out: Path, count: int = 3) -> None:
    """Wait (at most a minute) until the sweep in ``proc`` has written ``count`` records."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and proc.poll() is None:
        if len(list((out / "runs").glob("*.json"))) >= count:
            return
        time.sleep(0.01)


def _sigint_default() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)  # as a terminal's process has it


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_that_lands_in_a_finalizer_still_ends_the_sweep(tmp_path, capsys, monkeypatch,
                                                                  sig):
    """A signal handler's KeyboardInterrupt raised inside a weakref callback (a
    WeakKeyDictionary's clean-up while a run frees its objects) is printed and dropped by
    Python: a sweep then ran all its remaining runs after a SIGTERM and exited 0 (seen as a
    rare failure of the test above)."""
    import weakref

    import swarmex.experiments.sweep as sweep_mod

    real = sweep_mod.run_task
    done = []

    class Freed:
        pass

    def run_and_free(task, runs_dir):
        outcome = real(task, runs_dir)
        done.append(task)
        if len(done) == 2:  # the signal arrives while a callback of a freed object runs
            obj = Freed()
            ref = weakref.ref(obj, lambda _: signal.getsignal(sig)(sig, None))  # noqa: F841
            del obj
        return outcome

    monkeypatch.setattr(sweep_mod, "run_task", run_and_free)
    spec = tmp_path / "spec.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = [1, 2]\nseeds = 5\n',
                    encoding="utf-8")
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--backend", "serial"]) == 130
    assert len(done) == 2 and len(list((out / "runs").glob("*.json"))) == 2
    assert "interrupted" in capsys.readouterr().err
    assert main(["sweep", str(spec), "--out", str(out), "--backend", "serial"]) == 0  # resumes
    assert len(done) == 10


@pytest.mark.timeout(120)
@pytest.mark.parametrize("backend", ["local", "serial"])
@pytest.mark.parametrize("signals", [(signal.SIGINT, signal.SIGINT), (signal.SIGTERM,)],
                         ids=["ctrl-c-twice", "sigterm"])
def test_two_quick_ctrl_cs_end_the_sweep_and_keep_the_table(tmp_path, backend, signals):
    """A terminal or ``timeout -s INT`` often delivers Ctrl-C twice: the second one used to
    land in the pool's shutdown, and the sweep hung for ever (or died in a traceback), or,
    serially, left no results table. A scheduler or ``kill`` sends SIGTERM: the same."""
    spec = tmp_path / "spec.toml"
    spec.write_text('mission = "traversal"\ngrid = "20x20"\nagents = [3, 4]\nseeds = 100\n',
                    encoding="utf-8")
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "swarmex", "sweep", str(spec), "--out", str(out),
           "--backend", backend, "--workers", "2"][: None if backend == "local" else -2]
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                            preexec_fn=_sigint_default, text=True)
    try:
        _await_records(proc, out)
        for sig in signals:
            proc.send_signal(sig)
            time.sleep(0.05)  # a second one lands while the first is being handled
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "interrupted" in err
    finished = len(list((out / "runs").glob("*.json")))
    assert 3 <= finished < 200
    assert len(pq.read_table(out / "results.parquet")) == finished


def test_a_worker_count_beyond_reason_is_refused_and_the_pool_fits_the_runs(tmp_path, capsys,
                                                                          monkeypatch):
    """``--workers 100000`` forked thousands of processes for a 4-run sweep."""
    path = write_spec(tmp_path)
    assert main(["sweep", str(path), "--workers", "100000", "--out", str(tmp_path / "o")]) == 2
    assert "--workers must be between 1 and 1024, got 100000" in capsys.readouterr().err
    from swarmex.experiments import sweep as sweep_module

    sizes: list[int] = []
    real_local = sweep_module._local
    monkeypatch.setattr(sweep_module, "_local",
                        lambda tasks, workers, *a, **k: (sizes.append(workers),
                                                         real_local(tasks, workers, *a, **k)))
    sweep(path, tmp_path / "fit", backend="local", workers=64)
    assert sizes == [8]  # the spec's 8 runs: no idle forks


@pytest.mark.parametrize(("extra", "says"), [
    (["--backend", "serial", "--workers", "4"], "--workers is for --backend local or ray"),
    (["--ray-address", "127.0.0.1:1"], "--ray-address is for --backend ray, not local"),
])
def test_an_option_the_backend_would_ignore_is_refused(tmp_path, capsys, extra, says):
    path = write_spec(tmp_path)
    assert main(["sweep", str(path), "--out", str(tmp_path / "o"), *extra]) == 2
    assert says in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(("text", "says"), [
    ('mission = "traversal"\ngrid = "4x4"\nagents = 1\nseeds = 100000000\n',
     "seeds = 100,000,000: a sweep has at most 1,000,000 runs"),
    ('mission = "traversal"\ngrid = "4x4"\nagents = [1, 2, 3]\nseeds = 400000\n',
     "1,200,000 runs; a sweep has at most 1,000,000"),
])
def test_a_sweep_too_large_to_hold_is_refused_at_once(tmp_path, capsys, text, says):
    """seeds = 100000000 filled 4 GB of memory with run lists before printing a word."""
    path = write_spec(tmp_path, text)
    assert main(["sweep", str(path), "--out", str(tmp_path / "o")]) == 2
    assert says in capsys.readouterr().err


def test_local_pool_equals_serial_bit_for_bit(tmp_path):
    path = write_spec(tmp_path)
    sweep(path, tmp_path / "serial", backend="serial")
    result = sweep(path, tmp_path / "local", backend="local", workers=2)
    assert (result.ran, result.failed) == (8, 0)
    assert table_rows(tmp_path / "local") == table_rows(tmp_path / "serial")
    assert records(tmp_path / "local") == records(tmp_path / "serial")


@pytest.mark.parametrize(
    "address, message",
    [
        (
            "127.0.0.1:{port}",
            "no Ray cluster answers there",
        ),  # nothing listens: no minutes-long retry
        ("nonsense", "--ray-address must be HOST:PORT"),
    ],
)
def test_unreachable_ray_address_exits_2_with_one_line(tmp_path, capsys, address, message):
    import socket

    pytest.importorskip("ray", reason="ray is not installed (pip install 'swarmex[ray]')")
    with socket.socket() as s:  # a port that was free a moment ago: nothing listens there
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    path = write_spec(tmp_path)
    argv = ["sweep", str(path), "--backend", "ray", "--out", str(tmp_path / "o")]
    code = main([*argv, "--ray-address", address.format(port=port)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and message in err
    assert not list((tmp_path / "o").glob("runs/*"))


def test_ray_backend_without_ray_exits_2_with_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray -> ImportError
    path = write_spec(tmp_path)
    code = main(["sweep", str(path), "--backend", "ray", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.splitlines() == [
        "swarmex: error: --backend ray needs ray: pip install 'swarmex[ray]'"
    ]


def test_ray_equals_serial(tmp_path):
    """Ray (installed with the dev extra) gives the serial backend's table and records."""
    pytest.importorskip("ray", reason="ray is not installed (pip install 'swarmex[ray]')")
    path = write_spec(tmp_path)
    sweep(path, tmp_path / "serial")
    sweep(path, tmp_path / "ray", backend="ray", workers=2)
    assert table_rows(tmp_path / "ray") == table_rows(tmp_path / "serial")
    assert records(tmp_path / "ray") == records(tmp_path / "serial")


# ---------------------------------------------------------------------------- summary


def test_cli_summary_prints_means_and_cis(tmp_path, capsys):
    path = write_spec(tmp_path)
    out = tmp_path / "out"
    code = main(
        [
            "sweep",
            str(path),
            "--backend",
            "serial",
            "--out",
            str(out),
            "--summary",
            "--metric",
            "total_time_all",
        ]
    )
    text = capsys.readouterr().out
    assert code == 0
    assert "8/8 runs finished" in text
    assert "±" in text and "total_" in text and "nearest" in text
    rows = table_rows(out)
    mine = [r["makespan"] for r in rows if r["algorithm"] == "madgta" and r["agents"] == 2]
    s = summarize(mine)
    assert _mean_ci(s.mean, s.half_width) in text
    assert _mean_ci(1234.5, 0.5) == "1,234 ± 0.5" and _mean_ci(12.34, 5.678) == "12.3 ± 5.68"


def test_summary_metric_names_checked_before_are_columns_after(tmp_path, capsys):
    """``--metric metrics.NAME`` and a declared metric no run wrote (the solver figures
    without an ``optimal`` run) pass the check before the runs, so the summary after them
    must show them, not exit 2 once the whole sweep has run."""
    spec = write_spec(tmp_path, 'mission = "traversal"\ngrid = "3x3"\nagents = [1, 2]\n')
    out = tmp_path / "out"
    code = main(["sweep", str(spec), "--backend", "serial", "--out", str(out), "--summary",
                 "--metric", "metrics.total_time_all", "--metric", "objective_value"])
    text = capsys.readouterr().out
    assert code == 0
    assert "objective_value" in text and "—" in text
    assert "total_time_all" in text
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out), "--summary",
                 "--metric", "total_tim"]) == 2  # a typo still stops before any run
    capsys.readouterr()
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                 "--metric", "nodes_done_all"]) == 0  # --metric alone: its summary is shown
    assert "nodes_done_all" in capsys.readouterr().out
    # the paired table left a metric no run wrote out without a word
    assert main(["sweep", str(spec), "--backend", "serial", "--out", str(out),
                 "--baseline", "agents=1", "--metric", "objective_value"]) == 0
    said = capsys.readouterr()  # a note goes to stderr, as every command's notes do
    assert "note: no run wrote objective_value, so it is not compared" in said.err
    assert "note:" not in said.out


def test_a_count_a_record_leaves_out_is_0_in_the_table(tmp_path):
    """A record's tables of counts leave out what counted nothing (a lone robot sends no
    GOAL; no replan for a reason): the column is 0 for that run, not null, or the means, CIs,
    plots and pairs silently dropped it. A failed run and an unknown time stay null."""
    spec = write_spec(tmp_path, 'mission = "exploration"\nempty = "8x8"\nrobots = [1, 2]\n')
    out = tmp_path / "out"
    sweep(spec, out)
    rows = {r["robots"]: r for r in table_rows(out)}
    lone = next(r for r in records(out).values() if r["params"]["robots"] == 1)["metrics"]
    assert "GOAL" not in lone["messages_by_kind"] and lone["replan_reasons"] == {}
    assert rows[1]["messages_by_kind.GOAL.messages"] == 0
    assert rows[1]["replan_reasons.seen"] == 0
    assert rows[1]["messages_by_kind.RERR.bytes"] == 0  # declared, written by no run
    assert rows[2]["messages_by_kind.GOAL.messages"] > 0

    from swarmex.experiments.sweep import build_table
    from swarmex.experiments.sweep_worker import Outcome

    loaded = load_sweep_spec(spec)
    runs = loaded.runs()
    outcomes = {
        runs[0].run_id: Outcome(0, runs[0].run_id, ok=True, complete=False, metrics={}),
        runs[1].run_id: Outcome(1, runs[1].run_id, ok=False, error="boom"),
    }
    table = build_table(loaded, runs, outcomes).to_pylist()
    assert table[0]["replan_reasons.seen"] == 0 and table[0]["makespan"] is None
    assert table[1]["replan_reasons.seen"] is None  # a failed run counted nothing known


def test_a_declared_table_entry_no_column_holds_shows_a_dash(tmp_path, capsys):
    """``--metric messages_by_kind.GOAL.messages`` passes the check before the runs; a table
    without that column (written before count entries were columns) must show "—" after
    them, not exit 2 with no summary once the whole sweep has run."""
    import pyarrow.parquet as pq_

    from swarmex.cli.commands_sweep import print_summary

    spec = write_spec(tmp_path, 'mission = "exploration"\nempty = "8x8"\nrobots = 1\n')
    out = tmp_path / "out"
    sweep(spec, out)
    table = pq_.read_table(out / "results.parquet")
    old = table.drop_columns([c for c in table.column_names if ".GOAL." in c])
    pq_.write_table(old.replace_schema_metadata(table.schema.metadata), out / "results.parquet")
    capsys.readouterr()
    print_summary(out, ["messages_by_kind.GOAL.messages", "unicasts.sent"])
    text = capsys.readouterr().out
    assert "messages_by_kind.GOAL.messages" in text and "—" in text
    with pytest.raises(InputError, match="no column"):
        print_summary(out, ["messages_by_kind.GOAL.mesages"])


def test_a_damaged_record_is_run_again_with_one_warning(tmp_path, capsys):
    """A 0-byte or cut-short record (a power loss after an un-fsynced rename) crashed resume
    with a JSON traceback; it now counts as not finished: one warning line names it, and
    its run is run again, journal or not."""
    spec = write_spec(tmp_path)
    out = tmp_path / "out"
    argv = ["sweep", str(spec), "--backend", "serial", "--out", str(out)]
    assert main(argv) == 0
    good = records(out)
    names = sorted(good)
    (out / "runs" / names[0]).write_text("")  # the journal knows it
    capsys.readouterr()
    assert main(argv) == 0
    text = capsys.readouterr()
    assert "(7 finished before, 1 to run)" in text.out
    assert text.err.count("warning:") == 1 and "Traceback" not in text.err
    assert f"{names[0]}: unreadable (empty); its run is run again" in text.err
    assert records(out) == good
    (out / "journal.jsonl").unlink()  # the driver died before its journal line
    (out / "runs" / names[1]).write_text('{"truncated')
    (out / "runs" / names[2]).write_text("")
    with pytest.warns(UserWarning, match="unreadable") as said:
        result = sweep(spec, out)
    assert sorted(names[1] in str(w.message) for w in said) == [False, True]
    assert (result.skipped, result.ran) == (6, 2) and records(out) == good


def _movingai(rows: list[str]) -> str:
    return f"type octile\nheight {len(rows)}\nwidth {len(rows[0])}\nmap\n" + "\n".join(rows)


def test_a_run_id_follows_the_map_file_it_reads_not_its_name(tmp_path, capsys):
    """Two specs in different folders with the same ``map = "m.map"`` shared run ids, so
    the second sweep into the same --out silently reused the first one's results; a map
    edited in place was reused on resume too. An unchanged sweep still resumes."""
    text = 'mission = "traversal"\nmap = "m.map"\nagents = 1\nseeds = 2\n'
    maps = {"cA": ["....", "....", "....", "...."], "cB": ["....", ".@@.", "....", "...."]}
    specs = {}
    for name, rows in maps.items():
        (tmp_path / name).mkdir()
        (tmp_path / name / "m.map").write_text(_movingai(rows))
        specs[name] = write_spec(tmp_path / name, text)
    out = tmp_path / "shared"
    a, b = sweep(specs["cA"], out), sweep(specs["cB"], out)
    assert (a.skipped, a.ran) == (0, 2) and (b.skipped, b.ran) == (0, 2)
    recs = records(out).values()
    assert sorted(r["world"]["free_cells"] for r in recs) == [14, 14, 16, 16]
    assert (sweep(specs["cB"], out).skipped, sweep(specs["cA"], out).ran) == (2, 0)
    (tmp_path / "cA" / "m.map").write_text(_movingai(maps["cA"][:3]))  # edited in place
    edited = sweep(specs["cA"], out)
    assert (edited.skipped, edited.ran) == (0, 2)


def test_a_ros_map_id_follows_its_image_too(tmp_path):
    from swarmex.experiments.sweep_spec import InputFiles

    (tmp_path / "m.yaml").write_text("image: m.pgm\nresolution: 0.5\n")
    (tmp_path / "m.pgm").write_bytes(b"P5 2 1 255\n\xff\xff")
    before = InputFiles("exploration", tmp_path).digests({"map": "m.yaml"})
    (tmp_path / "m.pgm").write_bytes(b"P5 2 1 255\n\xff\x00")
    after = InputFiles("exploration", tmp_path).digests({"map": "m.yaml"})
    assert set(before) == {"map"} and before != after


def test_killed_driver_loses_no_finished_run(tmp_path):
    """SIGKILL the CLI mid-sweep: every record it wrote is kept, and the rerun skips them."""
    spec = write_spec(tmp_path, 'mission = "traversal"\ngrid = "3x3"\nagents = 1\nseeds = 40\n')
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "swarmex", "sweep", str(spec), "--backend", "serial"]
    proc = subprocess.Popen(
        [*cmd, "--out", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    try:
        _await_records(proc, out)
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait(timeout=10)
    kept = sorted(p.name for p in (out / "runs").glob("*.json"))
    assert 3 <= len(kept) < 40, "the sweep should have been killed part way"
    for name in kept:  # atomic writes: no half-written record survives a kill
        json.loads((out / "runs" / name).read_text())
    result = sweep(spec, out)
    assert result.skipped == len(kept)  # records without a journal line count too
    assert result.ran == 40 - len(kept) and result.failed == 0
    assert len(pq.read_table(out / "results.parquet")) == 40


def crash_or_run(task, runs_dir):
    """A worker function whose "crash" tasks kill their process, like a segfault would."""
    from swarmex.experiments.sweep_worker import run_task

    if task.mission == "crash":
        os._exit(3)
    return run_task(task, runs_dir)


def tiny_traversal_tasks(n: int) -> list:
    """``n`` 3x3 single-agent traversal tasks, ids r0..r{n-1} (seed = index)."""
    from swarmex.experiments.sweep_worker import Task

    values = {"grid": "3x3", "agents": 1}
    return [Task(i, f"r{i}", "traversal", {**values, "seed": i}) for i in range(n)]


def test_a_run_that_kills_its_worker_is_recorded_and_the_rest_finish(tmp_path):
    from swarmex.experiments.sweep import _local
    from swarmex.experiments.sweep_worker import Task

    tasks = tiny_traversal_tasks(4)
    tasks.insert(1, Task(99, "boom", "crash", {}))
    got = []
    _local(tasks, 2, "traversal", tmp_path, got.append, runner=crash_or_run)
    by_id = {o.run_id: o for o in got}
    assert sorted(by_id) == sorted(t.run_id for t in tasks) and len(got) == 5
    assert not by_id["boom"].ok and "worker process died" in by_id["boom"].error
    assert all(by_id[f"r{i}"].ok for i in range(4))


def test_workers_that_cannot_run_stop_the_sweep_without_recording_failures(tmp_path):
    from swarmex.experiments.sweep import _local
    from swarmex.experiments.sweep_worker import Task

    got = []
    with pytest.raises(InputError, match="died 3 times in a row"):
        tasks = [Task(i, f"c{i}", "crash", {}) for i in range(5)]
        _local(tasks, 2, "traversal", tmp_path, got.append, runner=crash_or_run)
    assert got == []


def test_a_crash_inside_a_chunk_loses_only_unfinished_runs(tmp_path):
    """Small runs travel in chunks; a crash mid-chunk keeps the runs recorded before it."""
    from swarmex.experiments.sweep import _local
    from swarmex.experiments.sweep_worker import Task

    tasks = tiny_traversal_tasks(60)
    tasks.insert(30, Task(99, "boom", "crash", {}))
    got = []
    _local(tasks, 2, "traversal", tmp_path, got.append, runner=crash_or_run)
    ids = [o.run_id for o in got]
    assert sorted(ids) == sorted(t.run_id for t in tasks), "each run finishes exactly once"
    by_id = {o.run_id: o for o in got}
    assert not by_id["boom"].ok and all(by_id[f"r{i}"].ok for i in range(60))
    assert len(list(tmp_path.glob("r*.json"))) == 60


def slow_job(job: tuple[str, int]) -> int:
    """A pool job that leaves a mark when it starts, then takes a while."""
    folder, index = job
    Path(folder, f"started-{index}").touch()
    time.sleep(1.0)
    return index


def test_ctrl_c_waits_for_the_jobs_running_and_starts_no_other(tmp_path):
    """ProcessPoolExecutor moves queued chunks into its call queue, where shutdown cannot
    cancel them: one Ctrl-C used to start another full run after the interrupt (a 200 s
    run on a large map). Now the worker sees the stop flag and skips it."""
    from swarmex.experiments.pool import run_local

    def on_alarm(signum, frame):
        if not (tmp_path / "started-0").exists():  # a slow fork: not yet, look again
            signal.setitimer(signal.ITIMER_REAL, 0.05)
            return
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, 0.3)  # a Ctrl-C while job 0 runs
    t0 = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            run_local([(str(tmp_path), i) for i in range(4)], slow_job, 1, lambda j, r: None)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["started-0"]
    assert time.monotonic() - t0 < 10  # it waited for job 0 only (a second one would
    # have left its mark); the bound only catches a hang on a loaded machine


def test_chunk_size_follows_run_time_and_shrinks_at_the_end():
    from swarmex.experiments.pool import CHUNK_MAX
    from swarmex.experiments.pool import chunk_size as _chunk_size

    assert _chunk_size(None, 1000, 2) == 1  # no run timed yet
    assert _chunk_size(0.001, 1000, 2) == CHUNK_MAX  # tiny runs: the biggest chunks
    assert _chunk_size(0.02, 1000, 2) == 5  # about 0.1 s of work per chunk
    assert _chunk_size(5.0, 1000, 2) == 1  # long runs one at a time (Ctrl-C stays quick)
    assert _chunk_size(0.001, 20, 2) == 2  # the tail: a quarter of a fair share


def test_the_progress_bar_is_silent_in_a_pipe(tmp_path, capsys):
    # Rich printed a non-terminal bar's last state on stop: "sweep ━━━ 8/8 runs/s" in a log
    path = write_spec(tmp_path)
    assert main(["sweep", str(path), "--backend", "serial", "--out", str(tmp_path / "o")]) == 0
    captured = capsys.readouterr()
    assert "runs/s" not in captured.err + captured.out
    assert "8/8 runs finished" in captured.out


def test_the_progress_bar_draws_on_a_terminal():
    import io

    from rich.console import Console

    from swarmex.experiments.progress import runs_progress

    screen = io.StringIO()
    bar = runs_progress("sweep", Console(file=screen, force_terminal=True, width=100))
    task = bar.add_task("", total=2)
    with bar:
        bar.advance(task, 2)
    assert "2/2" in screen.getvalue() and "runs/s" in screen.getvalue()
    piped = io.StringIO()
    bar = runs_progress("sweep", Console(file=piped, force_terminal=False))
    with bar:
        bar.advance(bar.add_task("", total=2), 2)
    assert piped.getvalue() == ""


def test_an_interrupted_table_has_every_record_on_disk(tmp_path):
    # Ctrl-C with 87 records on disk left 83 rows: runs a worker had written but whose
    # outcome was still on its way to the driver were missing from results.parquet
    path = write_spec(tmp_path)
    fresh = tmp_path / "fresh"
    sweep(path, fresh)
    ids = [r["run"] for r in pq.read_table(fresh / "results.parquet").to_pylist()]
    out = tmp_path / "out"
    seen: list[str] = []

    def ctrl_c_with_one_in_flight(outcome):
        seen.append(outcome.run_id)
        if len(seen) == 3:  # a worker has just written the last run's record
            (out / "runs" / f"{ids[-1]}.json").write_text(
                (fresh / "runs" / f"{ids[-1]}.json").read_text()
            )
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(path, out, on_outcome=ctrl_c_with_one_in_flight)
    rows = pq.read_table(out / "results.parquet").to_pylist()
    assert [r["run"] for r in rows] == [*ids[:3], ids[-1]]
    assert rows[-1]["makespan"] == table_rows(fresh)[-1]["makespan"]


def test_the_spec_in_docs_sweeps_runs_without_failures(tmp_path):
    # its [fixed] nest (0,9) lay outside the 8x8 grid of its own axis: half its runs failed
    import re

    doc = (Path(__file__).resolve().parents[2] / "docs" / "sweeps.md").read_text()
    text = re.search(r"```toml\n(.*?)```", doc, re.S).group(1)
    result = sweep(write_spec(tmp_path, text.replace("seeds = [0, 1, 2]", "seeds = [0]")),
                   tmp_path / "o")
    assert (result.total, result.failed) == (8, 0)


def test_algorithm_and_its_option_together_are_refused(tmp_path, capsys):
    # the run used `algorithm`, while the table's `planner` column named the other one
    env = Path(__file__).resolve().parents[2] / "examples" / "roadmap_fig8.json"
    path = write_spec(
        tmp_path,
        f'mission = "roadmap"\nenv = "{env}"\nagents = 2\nnodes = 40\nstep = 40\n'
        'sensor-range = 25\nplanner = ["prm"]\nalgorithm = ["wma-rrt"]\n',
    )
    code = main(["sweep", str(path), "--backend", "serial", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "algorithm and planner are the same option" in err
    assert not (tmp_path / "o" / "runs").exists() or not list((tmp_path / "o" / "runs").iterdir())


def test_the_sweep_lines_are_not_folded(tmp_path, capsys):
    # Rich folded "sweep: … → DIR" at 80 columns, cutting the folder's path in two in a log
    path = write_spec(tmp_path)
    out = tmp_path / ("a-long-folder-name-" * 4) / "o"
    assert main(["sweep", str(path), "--backend", "serial", "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].endswith(f"→ {out}") and lines[1].endswith(str(out / "results.parquet"))


def test_a_missing_input_file_stops_the_sweep_before_any_run(tmp_path, capsys):
    # every run failed with "environment file not found", one error file each
    path = write_spec(
        tmp_path,
        'mission = "roadmap"\nenv = ["fig8.json"]\nagents = 2\nnodes = 40\nstep = 40\n'
        'sensor-range = 25\nseeds = 3\n',
    )
    code = main(["sweep", str(path), "--backend", "serial", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert f"env = {tmp_path / 'fig8.json'}: no such file" in err
    assert not list((tmp_path / "o").glob("runs/*"))


def test_a_list_option_swept_element_by_element_is_noted(tmp_path, capsys):
    # a scenario file's `obstacles = [...]` run as a spec swept one wall cell per run, silently
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "5x5"\nagents = 2\n'
                    'obstacles = ["2,1", "2,2"]\nnests = ["0,0"]\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "a"), "--backend", "serial"]) == 0
    out = capsys.readouterr().err
    assert ("note: obstacles is an axis of 2 values, one per run; for one list of obstacles in"
            " every run, put it under [fixed] (docs/sweeps.md)") in out
    assert "nests is an axis" not in out  # one value: nothing to misread
    spec.write_text('mission = "traversal"\ngrid = "5x5"\nagents = [1, 2]\n'
                    '[fixed]\nobstacles = ["2,1", "2,2"]\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "b"), "--backend", "serial"]) == 0
    assert "note:" not in capsys.readouterr().err
    import swarmex

    with pytest.warns(UserWarning, match=r"obstacles is an axis of 2 values, one per run; for"
                      r" one list of obstacles in every run, give it in fixed= or as a tuple"):
        swarmex.sweep("traversal", out=tmp_path / "c", grid="5x5", agents=2,
                      obstacles=["2,1", "2,2"], backend="serial", progress=False)


def test_a_relative_change_over_fewer_pairs_says_how_many():
    # a pair whose baseline is 0 has no ratio: the cell read as if over every pair counted
    from types import SimpleNamespace

    from swarmex.cli.commands_sweep import _relative

    rel = summarize([0.5, 1.5])
    every = SimpleNamespace(relative=rel, pairs=2, relative_pairs=2)
    fewer = SimpleNamespace(relative=rel, pairs=3, relative_pairs=2)
    assert _relative(every) == "100.0 ± 635.3 %"  # t(1) = 12.706 · 0.7071 / √2 = 6.353
    assert _relative(fewer) == "100.0 ± 635.3 % (2 pairs)"


def test_a_stop_noted_earlier_in_a_python_session_does_not_stop_a_later_sweep(tmp_path):
    # a second Ctrl-C while a pool shut down left the note set in a notebook's process:
    # every later sweep stopped at once, with no Ctrl-C (review of 30 Nov 2026)
    import swarmex
    from swarmex.engine import interrupts

    interrupts.note()  # however it came to be set
    swarmex.sweep("traversal", out=tmp_path / "s", grid=(4, 4), agents=[1, 2], seeds=2,
                  backend="serial", progress=False)
    assert len(list((tmp_path / "s" / "runs").glob("*.json"))) == 4


def test_a_record_that_cannot_be_read_now_is_not_deleted(tmp_path, monkeypatch, capsys):
    # a permission or network file system error is not a damaged record: removing it lost
    # a finished run; the sweep now stops and names the file
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = 1\nseeds = 1\n')
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--backend", "serial"]) == 0
    (record,) = (out / "runs").glob("*.json")
    (out / "journal.jsonl").unlink()  # so the resume reads the record itself
    real = Path.read_text

    def denied(self, *a, **kw):
        if self == record:
            raise PermissionError(13, "Permission denied")
        return real(self, *a, **kw)

    monkeypatch.setattr(Path, "read_text", denied)
    assert main(["sweep", str(spec), "--out", str(out), "--backend", "serial"]) == 2
    assert "cannot read this finished run's file (Permission denied)" in capsys.readouterr().err
    assert record.exists()


def test_an_option_every_run_ignores_is_noted(tmp_path, capsys):
    # one traverse run says "--objective is ignored"; a sweep of online policies at
    # objective = "makespan" said nothing, and its objective column meant nothing
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = [1, 2]\nseeds = 1\n'
                    '[fixed]\nobjective = "makespan"\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "a"), "--backend", "serial"]) == 0
    assert ("note: objective is ignored in every run: only optimal minimises an objective"
            " (makespan); madgta plays its own rule") in capsys.readouterr().err
    # optimal among the algorithms reads it: nothing to say
    spec.write_text('mission = "traversal"\ngrid = "3x3"\nagents = 1\nseeds = 1\n'
                    'algorithm = ["madgta", "optimal"]\n[fixed]\nobjective = "makespan"\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "b"), "--backend", "serial"]) == 0
    assert "ignored" not in capsys.readouterr().err
    import swarmex

    with pytest.warns(UserWarning, match="objective is ignored in every run"):
        swarmex.sweep("traversal", out=tmp_path / "c", grid=(4, 4), agents=[1, 2],
                      fixed={"objective": "makespan"}, backend="serial", progress=False)


def test_a_file_axis_is_compared_by_the_files_the_runs_read(tmp_path, monkeypatch):
    # relative to the spec's folder, as the runs read them: parsed from the current folder,
    # two different fleets there were "one value twice" when the folder held two equal ones
    spec_dir, here = tmp_path / "spec", tmp_path / "here"
    spec_dir.mkdir()
    here.mkdir()
    (spec_dir / "a.csv").write_text("id,job_time\n1,5\n2,5\n")
    (spec_dir / "b.csv").write_text("id,job_time\n1,9\n2,9\n")
    for name in ("a.csv", "b.csv"):
        (here / name).write_text("id,job_time\n1,5\n2,5\n")
    spec = spec_dir / "s.toml"
    spec.write_text('mission = "traversal"\nseeds = 1\ngrid = "4x4"\nagents = 2\n'
                    'fleet = ["a.csv", "b.csv"]\n')
    monkeypatch.chdir(here)
    assert len(load_sweep_spec(spec).runs()) == 2
    # and one file named two ways from the spec's folder is one value, whatever the
    # current folder holds (read from there, "a.csv" and "../spec/a.csv" were two files)
    spec.write_text('mission = "traversal"\nseeds = 1\ngrid = "4x4"\nagents = 2\n'
                    'fleet = ["a.csv", "../spec/a.csv"]\n')
    with pytest.raises(InputError, match="lists one value twice"):
        load_sweep_spec(spec)


def test_a_local_sweep_forks_no_more_than_a_few_processes_per_core(tmp_path, monkeypatch):
    # 1000 workers asked for on 2 cores: 8 processes, as the reproductions fork
    import os

    import swarmex.experiments.sweep as sweep_module

    seen = []
    monkeypatch.setattr(os, "cpu_count", lambda: 2)

    def local(tasks, workers, *args, **kwargs):
        seen.append(workers)
        raise KeyboardInterrupt  # the pool is not what is checked here

    monkeypatch.setattr(sweep_module, "_local", local)
    spec = tmp_path / "s.toml"
    spec.write_text('mission = "traversal"\ngrid = "4x4"\nagents = 1\nseeds = 12\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "o"), "--workers", "1000"]) == 130
    assert seen == [8]


@pytest.mark.parametrize("text", [
    # optimal plans offline (perfect radio, reliable jobs); only recall reads found
    'mission = "traversal"\ngrid = "3x3"\nagents = 1\nseeds = 1\n'
    'algorithm = ["madgta", "optimal"]\n[fixed]\nloss = 0.1\njob_failure = 0.1\n',
    'mission = "foraging"\ngrid = 16\nagents = 4\nseeds = 1\nfood_units = 2\n'
    'algorithm = ["strips", "recall"]\n[fixed]\nfound = "3,4;10,12"\n',
])
def test_a_value_one_algorithm_ignores_does_not_fail_its_rows(tmp_path, capsys, text):
    # these options were refused with the algorithm that ignores them, so a sweep that held
    # them fixed while it varied the algorithm ended "2/2 runs finished, 1 failed"
    spec = tmp_path / "s.toml"
    spec.write_text(text)
    assert main(["sweep", str(spec), "--out", str(tmp_path / "a"), "--backend", "serial"]) == 0
    assert "2/2 runs finished (2 now), 0 failed" in capsys.readouterr().out


def test_an_ignored_option_is_noted_when_the_spec_names_the_planner_algorithm(tmp_path):
    # a spec's `algorithm` key is the roadmap's --planner: the check read it as an unknown
    # option, every configuration failed to parse, and the note was never given
    from swarmex.experiments.sweep_spec import always_ignored, load_sweep_spec

    env = Path(__file__).resolve().parents[2] / "examples" / "roadmap_fig11.json"
    spec = tmp_path / "s.toml"
    for key in ("algorithm", "planner"):
        spec.write_text(f'mission = "roadmap"\n{key} = ["wma-rrt", "prm"]\nseeds = 1\n'
                        f'[fixed]\nenv = "{env}"\nagents = 2\nnodes = 50\nstep = 5.0\n'
                        'sensor_range = 10.0\ntask = "coverage"\ngoal = "100,100"\n')
        assert always_ignored(load_sweep_spec(spec)) == [
            ("goal", "only the search task reads a goal, not coverage")]
