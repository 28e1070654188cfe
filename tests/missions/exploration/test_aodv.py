"""AODV route discovery in the simulated mesh: routes, delivery, link breaks, expiry.

Robots stand on a line 4 m apart with a 5 m radio, so each hears only its line neighbours
and every unicast from one end to the other needs the intermediate robots. Hop counts are
checked against an independent computation: BFS distances on the radio's range graph.
"""

from __future__ import annotations

import dataclasses

import msgpack
import numpy as np
import pytest
from scipy.sparse.csgraph import shortest_path

from swarmex.comm.aodv import AodvNode, Rerr, Routed, Rrep, Rreq
from swarmex.comm.mesh import DiscNetwork
from swarmex.missions.exploration import ExplorationParams, run_exploration, sim
from swarmex.missions.exploration.messages import ChangeGoal, NeedMap
from swarmex.missions.exploration.record import exploration_metrics
from swarmex.worlds.metric import empty_metric, load_metric
from tests.missions.exploration.helpers import config, heartbeats, place, team

LINE = [(10 + 80 * i, 20) for i in range(4)]  # A, B, C, D


def aodv_team(cells, range_m=5.0):
    cfg = dataclasses.replace(config(), aodv=True)
    robots, net, wire = team(cells, range_m, cfg)
    log: list[tuple[int, int, str]] = []
    unicast = net.unicast

    def logged(src, dst, msg):
        log.append((src, dst, msg.kind))
        return unicast(src, dst, msg)

    many = net.unicast_many

    def logged_many(src, dsts, msg):
        log.extend((src, d, msg.kind) for d in dsts)
        return many(src, dsts, msg)

    net.unicast = logged
    net.unicast_many = logged_many
    return robots, net, wire, log


def bfs_hops(net) -> np.ndarray:
    return shortest_path(net.in_range.astype(np.int8), unweighted=True, directed=False)


def kinds(net) -> dict[str, int]:
    return {k: v["messages"] for k, v in net.totals()["by_kind"].items()}


def hops_of(log, kind):
    return [(s, d) for s, d, k in log if k == kind]


def test_unicast_across_a_line_finds_the_route_and_is_delivered_once():
    robots, net, wire, log = aodv_team(LINE)
    heartbeats(robots, wire, 0)
    a, b, c, d = robots
    assert [sorted(r.mesh.neighbours) for r in robots] == [[1], [0, 2], [1, 3], [2]]
    d.observe(np.full(len(d.cfg.angles), d.cfg.laser_cells), 1)  # a scan only D holds
    assert (3, 0) not in a.belief.archive
    log.clear()
    before = kinds(net)
    got = [r.aodv.stats.delivered for r in robots]  # the neighbours' direct NEED_MAP/MAP
    wire.send(0, a.unicast(3, NeedMap(0, a.belief.archive.summary()), 1), 1)
    wire.settle(1)
    after = kinds(net)
    # one RREQ flood (A->B, B->C, C->D: nobody sends back), one RREP back along it
    assert after["RREQ"] - before.get("RREQ", 0) == 3
    assert hops_of(log, "RREP") == [(3, 2), (2, 1), (1, 0)]
    # the request went A->B->C->D and D's MAP came back D->C->B->A, each exactly once
    assert hops_of(log, "NEED_MAP") == [(0, 1), (1, 2), (2, 3)]
    assert hops_of(log, "MAP") == [(3, 2), (2, 1), (1, 0)]
    assert [r.aodv.stats.delivered - g for r, g in zip(robots, got, strict=True)] == [1, 0, 0, 1]
    assert d.aodv.stats.delivered_multihop == 1 and a.aodv.stats.delivered_multihop == 1
    assert (3, 0) in a.belief.archive  # the MAP's scan reached the requester
    # route tables: next hops along the line, hop counts = BFS distances on the range graph
    dist = bfs_hops(net)
    expect_next = {(0, 3): 1, (1, 3): 2, (2, 3): 3, (3, 0): 2, (2, 0): 1, (1, 0): 0}
    for (node, dest), nxt in expect_next.items():
        r = robots[node].aodv.routes[dest]
        assert r.valid and r.next_hop == nxt, (node, dest)
        assert r.hops == dist[node, dest], (node, dest)
    assert a.aodv.routes[3].hops == 3 and d.aodv.routes[0].hops == 3
    # precursors: who uses each route (RERRs go to them when it breaks)
    assert b.aodv.routes[3].precursors == {0} and c.aodv.routes[3].precursors == {1}
    # sequence numbers: A's RREQ raised its own; D's reply carried D's (now known to A)
    assert d.aodv.routes[0].seq == a.aodv.seq == 1 and a.aodv.routes[3].seq == d.aodv.seq
    # a second unicast uses the route: no new discovery
    n_rreq = kinds(net)["RREQ"]
    wire.send(0, a.unicast(3, ChangeGoal(0, (5, 5), 7.0), 2), 2)
    wire.settle(2)
    assert kinds(net)["RREQ"] == n_rreq and d.request == "change_goal"
    assert d.aodv.stats.delivered_multihop == 2


def test_link_break_sends_rerr_to_precursors_and_the_route_is_rediscovered():
    robots, net, wire, log = aodv_team(LINE)
    heartbeats(robots, wire, 0)
    a, b, c, d = robots
    wire.send(0, a.unicast(3, NeedMap(0, a.belief.archive.summary()), 1), 1)
    wire.settle(1)
    assert d.aodv.stats.delivered_multihop == 1
    # D drives round to the other side of A: out of C's range, next to A and B
    d.belief.pos = (50, 20)
    place(robots, net)
    assert not net.in_range[2, 3] and net.in_range[0, 3] and net.in_range[1, 3]
    log.clear()
    wire.send(0, a.unicast(3, NeedMap(0, a.belief.archive.summary()), 2), 2)
    wire.settle(2)
    # the hop C->D fails: C breaks the link and tells its precursor B, B tells A
    assert hops_of(log, "NEED_MAP") == [(0, 1), (1, 2), (2, 3)]
    assert hops_of(log, "RERR") == [(2, 1), (1, 0)]
    assert not any(r.aodv.route(3, 2) for r in (a, b, c))
    assert [p.dest for p in c.aodv.queue] == [3]  # C keeps the message (local repair)
    assert d.aodv.stats.delivered_multihop == 1
    # heartbeats introduce D to A and B; C's retried RREQ finds the new route
    for t in range(3, 60):
        heartbeats(robots, wire, t)
    assert d.aodv.stats.delivered_multihop == 2 and not c.aodv.queue
    assert c.aodv.stats.expired == 0
    dist = bfs_hops(net)
    r = c.aodv.routes[3]
    assert r.valid and r.next_hop == 1 and r.hops == dist[2, 3] == 2


def test_message_expires_if_the_link_never_comes_back():
    robots, net, wire, log = aodv_team(LINE)
    heartbeats(robots, wire, 0)
    a, _, c, d = robots
    wire.send(0, a.unicast(3, NeedMap(0, ()), 1), 1)
    wire.settle(1)
    d.belief.pos = (390, 39)  # out of everyone's range for good
    place(robots, net)
    wire.send(0, a.unicast(3, NeedMap(0, ()), 2), 2)
    wire.settle(2)
    assert [p.dest for p in c.aodv.queue] == [3]
    life = c.cfg.unicast_lifetime
    for t in range(3, life + 5):
        heartbeats(robots, wire, t)
    assert c.aodv.stats.expired == 1 and not c.aodv.queue
    assert d.aodv.stats.delivered_multihop == 1


def test_partitioned_destination_is_dropped_at_expiry_with_backoff():
    # A and B together; D alone far away: no route ever exists
    robots, net, wire, log = aodv_team([(10, 20), (90, 20), (390, 20)])
    heartbeats(robots, wire, 0)
    log.clear()
    a = robots[0]
    wire.send(0, a.unicast(2, NeedMap(0, ()), 0), 0)
    wire.settle(0)
    life = a.cfg.unicast_lifetime
    for t in range(1, life + 5):
        heartbeats(robots, wire, t)
    s = a.aodv.stats
    assert s.expired == 1 and not a.aodv.queue and robots[2].aodv.stats.delivered == 0
    assert robots[1].aodv.stats.delivered == 1  # only the direct NEED_MAP of the meeting
    # RREQs at 0, then after 1, 2, 4 heartbeat periods: 0, 10, 30, 70 (< 100 lifetime)
    assert s.discoveries == 4
    assert hops_of(log, "NEED_MAP") == []  # never transmitted: it waited in the queue


def test_hop_counts_equal_bfs_distances_on_a_random_mesh():
    rng = np.random.default_rng(3)
    for _ in range(20):  # a connected random layout
        xs, ys = rng.integers(0, 400, 9), rng.integers(0, 40, 9)
        cells = [(int(x), int(y)) for x, y in zip(xs, ys, strict=True)]
        robots, net, wire, _ = aodv_team(cells, range_m=4.0)
        dist = bfs_hops(net)
        if np.isfinite(dist).all() and dist.max() >= 3:
            break
    else:
        pytest.fail("no connected layout")
    heartbeats(robots, wire, 0)
    src = robots[0]
    for dest in range(1, len(robots)):
        wire.send(0, src.unicast(dest, NeedMap(0, ()), 1), 1)
        wire.settle(1)
    for dest in range(1, len(robots)):
        assert src.aodv.routes[dest].hops == dist[0, dest], dest
        want = 1 if dist[0, dest] > 1 else 0  # a neighbour got its NEED_MAP directly
        assert robots[dest].aodv.stats.delivered_multihop == want
        # the reverse route the request left at the destination is as short
        assert robots[dest].aodv.routes[0].hops == dist[dest, 0]


def test_routed_envelope_size_is_its_msgpack_encoding():
    pay = NeedMap(4, ((1, 0, 12), (3, 0, 7)))
    env = Routed(2, 4, 9, 123, pay)
    assert env.kind == "NEED_MAP"
    assert env.nbytes == len(msgpack.packb(env.to_dict(), use_bin_type=True))
    node = AodvNode(0, lambda but: [])
    assert node.send(5, pay, 0, 10) == [] and node.tick(11) == [] and node.stats.expired == 1


class LoggedNetwork(DiscNetwork):
    """A DiscNetwork that also lists every message copy put on the air."""

    log: list = []

    def broadcast(self, src, msg):
        self.log.append(msg)
        return super().broadcast(src, msg)

    def unicast(self, src, dst, msg):
        self.log.append(msg)
        return super().unicast(src, dst, msg)

    def unicast_many(self, src, dsts, msg):
        self.log.extend([msg] * len(dsts))
        return super().unicast_many(src, dsts, msg)


def test_exploration_with_aodv_routes_gap_requests_over_several_hops(monkeypatch):
    grid = load_metric_or_skip()
    p = ExplorationParams(robots=6, comm_range=5.0, seed=0)
    sent: list = []
    monkeypatch.setattr(LoggedNetwork, "log", sent)
    monkeypatch.setattr(sim, "DiscNetwork", LoggedNetwork)
    run = run_exploration(grid, p)
    team_m, _ = exploration_metrics(run)
    assert run.complete and team_m["explored_fraction"] >= 0.99
    u = team_m["unicasts"]
    assert u["gap_requests"] > 0 and u["delivered_multihop"] > 0 and u["discoveries"] > 0
    assert team_m["aodv_messages"] > 0 and team_m["aodv_bytes"] > 0
    by_kind = team_m["messages_by_kind"]
    assert team_m["aodv_messages"] == sum(
        by_kind.get(k, {"messages": 0})["messages"] for k in ("RREQ", "RREP", "RERR")
    )
    # independently: the control messages actually transmitted, sized by msgpack itself
    control = [m for m in sent if isinstance(m, (Rreq, Rrep, Rerr))]
    assert team_m["aodv_messages"] == len(control) > 0
    assert team_m["aodv_bytes"] == sum(
        len(msgpack.packb(m.to_dict(), use_bin_type=True)) for m in control
    )
    sent.clear()
    # without AODV nothing is routed and nothing is counted as routing
    off, _ = exploration_metrics(run_exploration(grid, dataclasses.replace(p, aodv=False)))
    assert off["aodv_messages"] == 0 and off["unicasts"]["sent"] == 0
    assert sent and not any(isinstance(m, (Rreq, Rrep, Rerr, Routed)) for m in sent)
    assert off["explored_fraction"] >= 0.99


def test_empty_world_with_aodv_completes_and_is_deterministic():
    grid = empty_metric(4, 4, 0.05)
    p = ExplorationParams(robots=4, comm_range=2.0, seed=2)
    a, _ = exploration_metrics(run_exploration(grid, p))
    b, _ = exploration_metrics(run_exploration(grid, p))
    assert a["explored_fraction"] >= 0.99
    assert a == b


def load_metric_or_skip():
    from swarmex.studies.exploration.design import maps_dir

    path = maps_dir() / "room-32-32-4.map"
    if not path.exists():
        pytest.skip("MovingAI maps not available")
    return load_metric(path, 0.25)


def test_routed_payload_is_forwarded_below_max_hops_and_dropped_at_it():
    """MAX_HOPS bounds a routed payload's hops (the IP TTL role, a guard against loops): one
    that arrives having made MAX_HOPS - 1 hops is forwarded, one that has made MAX_HOPS is
    dropped and counted, even though a valid route to its destination is held."""
    from swarmex.comm.aodv import MAX_HOPS

    pay = NeedMap(4, ((1, 0, 12),))

    def relay():
        node = AodvNode(1, lambda but: [n for n in (0, 2) if n != but])
        node.hello(0, 0)
        node.hello(2, 0)  # a valid one-hop route to 2, the destination
        assert node.route(2, 1) is not None
        return node

    node = relay()
    out, got = node.receive(0, Routed(0, 7, 2, 100, pay, MAX_HOPS - 1), 1)
    assert got == [] and node.stats.dropped_hops == 0
    assert len(out) == 1
    nxt, env = out[0]
    assert nxt == 2 and isinstance(env, Routed) and env.hops == MAX_HOPS
    assert (env.orig, env.dest, env.payload) == (7, 2, pay)

    node = relay()
    out, got = node.receive(0, Routed(0, 7, 2, 100, pay, MAX_HOPS), 1)
    assert out == [] and got == []
    assert node.stats.dropped_hops == 1 and node.stats.expired == 0


def _node_with_route_to_9(seq=5):
    """Node 0 (neighbours 1 and 2) holding a valid route to 9: seq ``seq``, 2 hops via 1."""
    node = AodvNode(0, lambda but: [n for n in (1, 2) if n != but])
    node.receive(1, Rrep(1, 0, 9, seq, 1, 30), 0)
    r = node.routes[9]
    assert (r.valid, r.seq, r.hops, r.next_hop) == (True, seq, 2, 1)
    return node


def test_same_seq_equal_hops_does_not_replace_the_route():
    """RFC 3561 §6.2: with equal sequence numbers a route is replaced only if the new hop
    count is *smaller*; an equally long route via another neighbour leaves the old one."""
    node = _node_with_route_to_9()
    node.receive(2, Rrep(2, 0, 9, 5, 1, 30), 1)  # seq 5, 2 hops, via 2
    r = node.routes[9]
    assert (r.seq, r.hops, r.next_hop) == (5, 2, 1)
    node.receive(2, Rrep(2, 0, 9, 5, 0, 30), 2)  # seq 5, 1 hop: shorter, so it wins
    assert (r.seq, r.hops, r.next_hop) == (5, 1, 2)


def test_same_seq_longer_route_is_not_fresher():
    """RFC 3561 §6.2: only a *greater* sequence number is fresher; the same seq with more
    hops must not replace the route, while a greater seq does even when longer."""
    node = _node_with_route_to_9()
    node.receive(2, Rrep(2, 0, 9, 5, 3, 30), 1)  # seq 5, 4 hops via 2
    r = node.routes[9]
    assert (r.seq, r.hops, r.next_hop) == (5, 2, 1)
    node.receive(2, Rrep(2, 0, 9, 6, 3, 30), 2)  # seq 6, 4 hops via 2: fresher
    assert (r.seq, r.hops, r.next_hop) == (6, 4, 2)


def test_intermediate_node_answers_a_rreq_with_an_equal_dest_seq():
    """RFC 3561 §6.6.2: an intermediate node with a valid route answers the RREQ when its
    destination seq is greater than *or equal to* the RREQ's, instead of relaying it."""
    node = _node_with_route_to_9(seq=5)
    out, _ = node.receive(2, Rreq(2, 7, 1, 1, 9, 5, 0), 1)  # from 7 via 2, wants 9 at seq 5
    assert len(out) == 1
    to, msg = out[0]
    assert to == 2 and isinstance(msg, Rrep)
    assert (msg.orig, msg.dest, msg.dest_seq, msg.hops) == (7, 9, 5, 2)
    # a RREQ asking for a fresher seq (6) is relayed, not answered
    out, _ = node.receive(2, Rreq(2, 7, 1, 2, 9, 6, 0), 2)
    assert [(to, type(m)) for to, m in out] == [(1, Rreq)]


def test_link_break_raises_the_destination_sequence_number():
    """RFC 3561 §6.11: on a link break the known destination seq of every route through it
    is incremented, and the RERR carries that raised number."""
    node = _node_with_route_to_9(seq=5)
    node.receive(2, Rreq(2, 7, 1, 1, 9, 5, 0), 1)  # 2 becomes a precursor of the route to 9
    out = node.link_broken(1, 2)
    r = node.routes[9]
    assert not r.valid and r.seq == 6
    # the RERR to the precursor lists 9 at seq 6 (and the neighbour 1 itself, seq unknown)
    assert [(to, m.unreachable) for to, m in out] == [(2, ((1, -1), (9, 6)))]
