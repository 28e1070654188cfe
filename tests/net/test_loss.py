"""Done-nodes lists over a lossy radio (issue 15, item 2), measured with the networked
runtime's own fault injection (``serve --inject-loss``; here its socket-free twin
``run_inprocess(mission, loss)``, which draws the same losses).

A lost C07 leaves a receiver believing a done node is vacant; without lists it does that
job again. With the lists (done nodes and, as the thesis's KM, the sender's known walls)
every later broadcast of anyone repairs the belief. docs/net.md quotes these figures.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.errors import InputError
from swarmex.missions.traversal import uniform_agents
from swarmex.net import wire
from swarmex.net.traversal import Loss, Mission, message_of, run_inprocess
from swarmex.worlds import random_obstacles


def _run(size: int, agents: int, seed: int, lists: bool, loss: float) -> tuple[int, int]:
    world = random_obstacles(size, size, 0.2, seed=seed)
    nest = int(np.flatnonzero(world.free.ravel())[0])
    mission = Mission(world, uniform_agents([nest] * agents, 2.22, 10.0), seed=seed,
                      done_lists=lists)
    _, rec = run_inprocess(mission, loss)
    reach = rec.reachable()
    duplicates = int(np.maximum(rec.job_count - 1, 0).sum())
    missed = int((rec.job_count[reach] == 0).sum())
    return duplicates, missed


def test_merging_lists_costs_far_fewer_duplicate_jobs_at_30_percent_loss() -> None:
    merged = np.array([_run(10, 4, s, True, 0.3) for s in range(6)])
    bare = np.array([_run(10, 4, s, False, 0.3) for s in range(6)])
    # figures (10 seeds, docs/net.md): 1.3 against 57.8 duplicate jobs a run, 0 missed
    assert merged[:, 0].sum() * 10 < bare[:, 0].sum()
    assert merged[:, 1].sum() <= bare[:, 1].sum()
    assert merged[:, 1].sum() == 0  # an agent stops only when it believes all is done


def test_without_loss_nothing_is_done_twice() -> None:
    for lists in (True, False):
        assert _run(10, 4, 1, lists, 0.0) == (0, 0)


def test_the_loss_draws_follow_the_stream_and_spare_the_sender() -> None:
    a, b = Loss(5, 0.3, 7), Loss(5, 0.3, 7)
    draws = [a.draw(s) for s in (1, 2, 3, 4, 5) * 20]
    assert all(np.array_equal(d, b.draw(s)) for d, s in zip(draws, (1, 2, 3, 4, 5) * 20,
                                                            strict=True))
    assert not any(d[s - 1] for d, s in zip(draws, (1, 2, 3, 4, 5) * 20, strict=True))
    assert 0.2 < a.lost / (100 * 4) < 0.4
    with pytest.raises(InputError, match="--inject-loss"):
        Loss(3, 1.0, 0)


def test_the_wire_carries_the_known_walls_and_receivers_merge_them() -> None:
    b = wire.Broadcast("C05", 2, 4, 0, 1, np.array([3]), np.array([2]), (), 1.0, 2.0,
                       walls=np.array([7, 9]))
    back = wire.decode_broadcast(b.frame())
    assert back.walls is not None and back.walls.tolist() == [7, 9]
    msg = message_of(back)
    assert msg.done_list is not None and len(msg.done_list) == 4
    assert msg.done_list[3].tolist() == [7, 9]
    # a broadcast without a list keeps the 11 fields of before
    plain = wire.Broadcast("C06", 2, 4)
    assert len(plain.to_wire()) == 11 and wire.decode_broadcast(plain.frame()).walls is None
    lost = wire.pack(["LOST", b.frame()])
    assert wire.decode_message(lost)[0] == "LOST"
    with pytest.raises(wire.EncodingError):
        wire.check_control(["LOST", "not a frame"])
