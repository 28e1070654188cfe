"""``swarmex reproduce traversal``: bad ``--out`` and Ctrl-C end in one line, like the other
reproductions (the run itself is tested in tests/studies/traversal); every reproduction says
when it compiles its kernels."""

from __future__ import annotations

import pytest

from swarmex.cli import main


@pytest.mark.parametrize("sub", ["afile/sub", "/proc/swarmex-no-such-dir"])
def test_an_out_folder_that_cannot_be_made_is_one_line(tmp_path, capsys, sub):
    # mkdir's NotADirectoryError / FileNotFoundError came out as a traceback (exit 1)
    (tmp_path / "afile").write_text("")
    out = sub if sub.startswith("/") else str(tmp_path / sub)
    assert main(["reproduce", "traversal", "--quick", "--out", out]) == 2
    err = capsys.readouterr().err
    assert err.startswith("swarmex: error: --out: cannot write") and err.count("\n") == 1


def test_ctrl_c_says_where_the_finished_runs_are(tmp_path, capsys, monkeypatch):
    # the plain "swarmex: interrupted" did not say that the finished runs were kept, nor
    # how to resume, as the other reproductions' messages do
    import swarmex.studies.traversal as study

    def ctrl_c(out, *args, **kwargs):
        if finished:
            out.mkdir(parents=True, exist_ok=True)
            (out / "traversal.json").write_text('{"runs": {"r1": {}}}')  # a run had finished
        raise KeyboardInterrupt

    monkeypatch.setattr(study, "reproduce", ctrl_c)
    out = tmp_path / "rep"
    finished = True
    assert main(["reproduce", "traversal", "--quick", "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"finished runs are saved in {out / 'traversal.json'}" in err and "resume" in err
    # stopped before any run finished: it named a file that did not exist
    finished, out = False, tmp_path / "early"
    assert main(["reproduce", "traversal", "--quick", "--out", str(out)]) == 130
    assert capsys.readouterr().err == (
        "swarmex: interrupted; no run had finished, so nothing was kept\n")



@pytest.mark.parametrize("name", ["traversal", "exploration", "foraging", "roadmap"])
def test_a_compile_says_so(tmp_path, capsys, monkeypatch, name):
    # the first reproduction after an install compiled its kernels for 8-15 s of CPU (on 2
    # workers, each compiled them: ~30 s) without a word, so it looked hung
    import importlib

    import numba

    from swarmex.cli import compiling

    @numba.njit  # a fresh dispatcher: its first call compiles
    def twice(x):
        return 2 * x

    def compiles(out, **kwargs):
        assert twice(3) == 6
        return {"runs": 0, "executed": 0, "workers": 1, "elapsed_s": 0.0,
                "report": out / "traversal.md", "figures": [], "json": out / "traversal.json"}

    compiling._said = False
    monkeypatch.setattr(importlib.import_module(f"swarmex.studies.{name}"), "reproduce", compiles)
    assert main(["reproduce", name, "--quick", "--out", str(tmp_path)]) == 0
    assert capsys.readouterr().err == f"swarmex: {compiling.MESSAGE}\n"


def test_ctrl_c_before_any_run_finished_in_the_real_study_says_nothing_was_kept(
    tmp_path, capsys, monkeypatch
):
    # the study writes its JSON, with no run, even when stopped during the first compile:
    # the line named that empty file as where "finished runs are saved"
    import swarmex.studies.traversal.pipeline as pipeline

    def stopped(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(pipeline, "run_jobs", stopped)
    out = tmp_path / "rep"
    assert main(["reproduce", "traversal", "--quick", "--out", str(out)]) == 130
    assert (out / "traversal.json").exists()
    assert capsys.readouterr().err == (
        "swarmex: interrupted; no run had finished, so nothing was kept\n")

