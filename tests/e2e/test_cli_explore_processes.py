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


def test_processes_count_messages_as_the_simulator_and_the_harness_apart(tmp_path):
    """``messages_sent`` is the radio's messages, as the simulator counts them (a heartbeat
    once, not once per node in the air); the control link's STATUS and HELLO are reported
    apart (they were counted as robots' messages)."""
    out = tmp_path / "mesh.json"
    code = main(["explore", "--empty", "3x3", "--robots", "2", "--processes", "--json", str(out)])
    assert code == 0
    m = json.loads(out.read_text())["metrics"]
    by_kind = m["messages_by_kind"]
    assert not {"STATUS", "HELLO", "NACK", "REPORT"} & set(by_kind)
    assert m["messages_sent"] == sum(v["messages"] for v in by_kind.values())
    assert m["bytes_sent"] == sum(v["bytes"] for v in by_kind.values())
    assert set(m["harness_by_kind"]) >= {"STATUS", "HELLO"}
    assert m["harness_by_kind"]["HELLO"]["messages"] >= 2
    assert m["harness_messages"] == sum(v["messages"] for v in m["harness_by_kind"].values())
    # a heartbeat is one message (27 bytes: the simulator's size), sent to the 2 others in
    # the air (the other robot and the display) as 2 frames
    beats = by_kind["HEARTBEAT"]
    assert beats["bytes"] == 27 * beats["messages"]
    assert m["frames_sent"] > m["messages_sent"] + m["harness_messages"]


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
