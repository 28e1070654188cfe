"""``explore --processes`` is wired to the mesh runtime; its options are validated up front."""

from __future__ import annotations

import json

from swarmex.cli import main


def test_render_is_refused_with_processes(tmp_path, capsys):
    code = main(["explore", "--empty", "3x3", "--robots", "2", "--processes",
                 "--render", str(tmp_path / "x.png")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--processes" in err[0]


def test_loss_needs_processes(capsys):
    code = main(["explore", "--empty", "3x3", "--robots", "2", "--inject-loss", "0.1"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "--processes" in err[0]


def test_processes_run_completes(tmp_path):
    out = tmp_path / "mesh.json"
    code = main(["explore", "--empty", "3x3", "--robots", "2", "--processes", "--json", str(out)])
    assert code == 0 and out.exists()
    record = json.loads(out.read_text())
    assert record["params"]["aodv"] is True  # the processes route unicasts with AODV
    assert record["metrics"]["unicasts"]["sent"] > 0  # the first NEED_MAPs at least


def test_processes_without_aodv_send_one_hop_unicasts(tmp_path):
    out = tmp_path / "mesh.json"
    code = main(["explore", "--empty", "3x3", "--robots", "2", "--processes", "--no-aodv",
                 "--json", str(out)])
    assert code == 0
    record = json.loads(out.read_text())
    m = record["metrics"]
    assert record["params"]["aodv"] is False and m["unicasts"]["sent"] == 0
    assert m["aodv_messages"] == 0 and not m["multihop_in_by_kind"]


def test_processes_run_the_strategy_beyond_the_seed(tmp_path):
    """adaptive-exclusion (issue 17 item 2) keeps its per-robot state (start, ids heard,
    ticks alone, goal region) in the robot core, so one OS process per robot runs it too."""
    out = tmp_path / "adaptive.json"
    code = main(["explore", "--empty", "3x3", "--robots", "3", "--processes",
                 "--strategy", "adaptive-exclusion", "--json", str(out)])
    assert code == 0
    record = json.loads(out.read_text())
    assert record["params"]["strategy"] == "adaptive-exclusion"
    assert record["complete"] and record["metrics"]["explored_fraction"] >= 0.99
