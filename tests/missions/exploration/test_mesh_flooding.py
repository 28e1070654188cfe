"""Flooding with (origin, seq) de-duplication, multi-hop relay, catch-up and timeouts."""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.comm.mesh import DiscNetwork, MeshNode
from swarmex.errors import InputError
from tests.missions.exploration.helpers import heartbeats, place, scan, team


def test_mesh_node_basics():
    m = MeshNode(3, heartbeat_period=10, timeout=30, phase=4)
    assert [t for t in range(40) if m.heartbeat_due(t)] == [4, 14, 24, 34]
    assert m.hear(1, 0) and not m.hear(1, 5) and m.hear(2, 10)
    assert m.relay_targets(came_from=1) == [2]
    assert m.expire(36) == [1] and list(m.neighbours) == [2]
    assert m.first_time((1, 0)) and not m.first_time((1, 0)) and m.first_time((1, 1))
    with pytest.raises(InputError):
        DiscNetwork(2, -1.0)


def test_scan_reaches_a_line_of_robots_beyond_direct_range():
    # five robots 80 cells (4 m) apart, radio 5 m: each hears only its line neighbours
    robots, net, wire = team([(10 + 80 * i, 20) for i in range(5)], range_m=5.0)
    assert not net.in_range[0, 2] and not net.in_range[0, 4] and net.in_range[0, 1]
    heartbeats(robots, wire, 0)
    assert [sorted(r.mesh.neighbours) for r in robots] == [[1], [0, 2], [1, 3], [2, 4], [3]]
    before = net.totals()["by_kind"].get("SCAN", {"messages": 0})["messages"]
    wire.send(0, scan(robots[0]))
    wire.settle(0)
    assert all((0, 0) in r.belief.archive for r in robots)
    # one send per hop: 0->1, 1->2, 2->3, 3->4 (nobody sends back to whom it heard it from)
    assert net.totals()["by_kind"]["SCAN"]["messages"] - before == 4
    # the far end's map has the origin's cells: exploration knowledge crossed four hops
    assert robots[4].belief.grid.logodds[20, 10] < 0


def test_duplicates_are_dropped_in_a_triangle():
    robots, net, wire = team([(100, 20), (110, 20), (105, 28)], range_m=2.0)
    heartbeats(robots, wire, 0)
    wire.send(0, scan(robots[0]))
    wire.settle(0)
    # 0 sends to 1 and 2; each relays once to the other; the second copies are dropped
    assert net.totals()["by_kind"]["SCAN"]["messages"] == 4
    assert [len(r.belief.archive) for r in robots] == [1, 1, 1]
    assert [r.belief.grid.updates for r in robots] == [1, 1, 1]


def test_need_map_catch_up_when_groups_meet():
    # 0 and 1 explore together; 2 is far away with its own scans
    robots, net, wire = team([(10, 20), (30, 20), (390, 20)], range_m=2.0)
    heartbeats(robots, wire, 0)
    for t in range(3):
        wire.send(0, scan(robots[0], t))
    wire.send(2, scan(robots[2]))
    wire.settle(2)
    assert len(robots[1].belief.archive) == 3 and len(robots[2].belief.archive) == 1
    # 2 drives next to 1 (out of 0's range); a heartbeat round introduces them
    robots[2].belief.pos = (60, 20)
    place(robots, net)
    assert net.in_range[1, 2] and not net.in_range[0, 2]
    heartbeats(robots, wire, 10)
    kinds = net.totals()["by_kind"]
    assert kinds["NEED_MAP"]["messages"] >= 2 and kinds["MAP"]["messages"] == 2
    # everyone now holds all four scans: 2 got 0's via 1's MAP, and 0 got 2's scan from 1,
    # which passed on what its MAP taught it
    assert [len(r.belief.archive) for r in robots] == [4, 4, 4]


def test_silent_neighbour_is_dropped_and_forgotten():
    robots, net, wire = team([(10, 20), (30, 20)], range_m=2.0)
    heartbeats(robots, wire, 0)
    robots[1].belief.hear_goal(0, (50, 20), 3.0, 0)
    robots[0].belief.pos = (390, 20)
    place(robots, net)
    for t in range(1, 41):
        heartbeats(robots, wire, t)  # only those due send; 0 is out of range now
    assert 0 not in robots[1].mesh.neighbours
    assert 0 not in robots[1].belief.heard


def test_kdtree_links_of_a_large_team_equal_the_all_pairs_links(monkeypatch):
    """From KDTREE_FROM robots the links come from a k-d tree; they must be the all-pairs
    disc links: symmetric (j hears i when i hears j) and inclusive at exactly the range."""
    from swarmex.comm import mesh

    n, r = 300, 15.0
    assert n >= mesh.KDTREE_FROM
    p = np.random.default_rng(4).uniform(0, 100, size=(n, 2))
    p[:3] = [(0.0, 0.0), (r, 0.0), (9.0, 12.0)]  # 0-1 and 0-2 exactly r apart
    p[3:][np.hypot(*p[3:].T) <= r + 1.0] += 20.0  # keep the others out of 0's disc
    tree = DiscNetwork(n, r)
    tree.move(p)
    monkeypatch.setattr(mesh, "KDTREE_FROM", 10**9)
    pairs = DiscNetwork(n, r)
    pairs.move(p)
    assert 1000 < tree.in_range.sum() // 2 < 10000  # a few thousand links
    assert np.array_equal(tree.in_range, pairs.in_range)
    assert np.array_equal(tree.in_range, tree.in_range.T)
    assert tree.in_range[0, 1] and tree.in_range[1, 0]
    assert tree.in_range[0, 2] and tree.in_range[2, 0]
    # independent route: the brute-force disc rule
    d2 = ((p[:, None] - p[None]) ** 2).sum(axis=2)
    want = d2 <= r * r
    np.fill_diagonal(want, False)
    assert np.array_equal(tree.in_range, want)


def test_disc_link_at_exactly_the_range():
    """The disc model links two robots within ``range`` metres, the boundary included: a
    pair exactly 5 m apart (3-4-5) is linked, one a hair farther is not."""
    net = DiscNetwork(3, 5.0)
    net.move(np.array([[0.0, 0.0], [3.0, 4.0], [0.0, -5.000001]]))
    assert net.in_range[0, 1] and net.in_range[1, 0]
    assert not net.in_range[0, 2] and not net.in_range[2, 0]


def test_neighbour_is_kept_at_exactly_the_timeout():
    """A neighbour is dropped when silent for *longer* than the timeout: at exactly the
    timeout it stays, one tick later it goes."""
    m = MeshNode(0, heartbeat_period=10, timeout=30)
    m.hear(1, 0)
    assert m.expire(30) == [] and list(m.neighbours) == [1]
    assert m.expire(31) == [1] and list(m.neighbours) == []


def test_lost_copies_are_counted():
    """A unicast to a peer out of range is sent and lost (the send timeout drops it): it
    counts as sent and as lost, per copy, whichever send path is used."""
    net = DiscNetwork(3, 5.0)
    net.move(np.array([[0.0, 0.0], [4.0, 0.0], [100.0, 0.0]]))
    msg = type("M", (), {"kind": "X", "nbytes": 10})()
    assert net.unicast(0, 1, msg) and not net.unicast(0, 2, msg)
    assert net.totals()["messages_lost"] == 1
    net.unicast_many(0, [1, 2], msg)
    assert net.totals()["messages_lost"] == 2
    net.send_mask(0, 0b110, msg, "X", 10)
    t = net.totals()
    assert t["messages_lost"] == 3 and t["messages_sent"] == 6
