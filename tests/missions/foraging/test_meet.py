"""comm.meet: its plain-Python scan of short futures gives the numpy rule's answer."""

import numpy as np

from swarmex.missions.foraging import comm


def numpy_meet(me, future):
    d = np.abs(future[:, 0] - me[0]) + np.abs(future[:, 1] - me[1]) - 1
    ok = d <= np.arange(len(future))
    return int(np.argmax(ok)) if ok.any() else int(max(len(future) - 1, d[-1]))


def test_meet_is_the_first_round_a_robot_can_stand_next_to_the_future():
    rng = np.random.default_rng(3)
    for length in [1, 2, 3, comm.SHORT_FUTURE, comm.SHORT_FUTURE + 1, 40]:
        for _ in range(300):
            route = rng.integers(0, 12, size=(length, 2)).astype(np.int32)
            future = np.stack([route, route])[:, :, :].transpose(1, 0, 2)[:, 1]  # a strided view
            me = tuple(int(v) for v in rng.integers(0, 12, size=2))
            assert comm.meet(me, future) == numpy_meet(me, future)
            assert type(comm.meet(me, future)) is int
