"""``swarmex serve --inject-loss 0.3`` end to end (issue 15, item 2): real processes on
127.0.0.1, with and without done-nodes lists. Each networked run is exactly the protocol's
socket-free run with the same losses (the server draws them in stream order), and merging
the lists costs fewer duplicate jobs and no more missed nodes than going without."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from swarmex.missions.traversal import uniform_agents
from swarmex.net.traversal import Mission, run_inprocess
from swarmex.worlds import GridWorld
from tests.e2e.test_cli_traversal import free_mask
from tests.net.netproc import Procs, endpoint

pytestmark = pytest.mark.timeout(120)

OBSTACLES = [(2, 2), (3, 3), (4, 1), (5, 5)]
GRID = ["--grid", "8x8", "--obstacles", ";".join(f"{x},{y}" for x, y in OBSTACLES)]


def _served(tmp_path: Path, lists: bool) -> dict:
    out = tmp_path / f"net-{lists}.json"
    with Procs() as procs:
        server = procs.start(
            "server", "serve", *GRID, "--agents", 3, "--seed", 4, "--port", 0,
            "--time-scale", 0, "--inject-loss", 0.3, "--timeout", 60, "--json", out,
            *([] if lists else ["--no-done-lists"]),
        )
        agents = procs.start("agents", "agent", "--connect", endpoint(server), "--count", 3,
                             "--server-timeout", 20)
        assert server.wait(90) == 0, server.output
        assert agents.wait(15) == 0, agents.output
    return json.loads(out.read_text())


def _protocol(lists: bool) -> tuple[dict, np.ndarray, GridWorld]:
    world = GridWorld(free_mask(8, 8, OBSTACLES))
    mission = Mission(world, uniform_agents([0, 0, 0], 2.22, 10.0), seed=4, done_lists=lists)
    cores, rec = run_inprocess(mission, 0.3)
    return cores, rec.job_count, world


def test_lossy_networked_runs_with_and_without_merged_lists(tmp_path: Path) -> None:
    figures = {}
    for lists in (True, False):
        net = _served(tmp_path, lists)
        cores, job_count, world = _protocol(lists)
        assert net["complete"]
        n = net["network"]
        assert n["inject_loss"] == 0.3 and n["lost_deliveries"] > 0
        assert net["params"]["network"]["inject_loss"] == 0.3
        pos = world.graph.pos
        for entry, (_, core) in zip(net["agents"], sorted(cores.items()), strict=True):
            assert entry["trajectory"] == [[t, *pos[v].tolist()] for t, v in core.log.trajectory]
        m = net["metrics"]
        assert m["duplicate_jobs"] == int(np.maximum(job_count - 1, 0).sum())
        figures[lists] = (m["duplicate_jobs"], m["nodes_missed"], net["makespan"])
    # seed 4: merged 2 duplicate jobs, makespan 256.6 s; bare 32 and 423.2 s (docs/net.md)
    (merged_dup, merged_missed, merged_span), (bare_dup, bare_missed, bare_span) = (
        figures[True], figures[False])
    assert merged_dup < bare_dup and merged_missed <= bare_missed and merged_span < bare_span
