"""The mesh counts a robot's messages as the simulator does.

``messages_sent`` and ``bytes_sent`` compare the two runtimes (docs/net.md's bench). The
mesh counted socket frames: a heartbeat once per node in the air (the display included),
and the harness's STATUS and HELLO as robots' messages. Here a robot process's own
transmissions are replayed on the simulator's radio (:class:`DiscNetwork`: ``broadcast``,
``unicast``, ``unicast_many``, the primitives the simulator's ``Wire`` sends with) and the
counts must agree, kind by kind. A display and three robots run in this process, sockets
on 127.0.0.1, no process started."""

from __future__ import annotations

import time

import numpy as np
import pytest

from swarmex.comm.mesh import DiscNetwork, Fanout
from swarmex.missions.exploration import ExplorationParams
from swarmex.missions.exploration.messages import Heartbeat
from swarmex.missions.exploration.robot import RADIO
from swarmex.net.mesh_frames import DISPLAY, encode_radio
from swarmex.net.mesh_scenario import MeshOptions, write_scenario
from swarmex.worlds.metric import empty_metric

pytestmark = pytest.mark.timeout(120)


def test_a_robot_counts_its_messages_as_the_simulator_does(tmp_path):
    from swarmex.net.mesh_display import DisplayProcess
    from swarmex.net.mesh_robot import RobotProcess

    grid = empty_metric(3, 3)
    params = ExplorationParams(robots=3, laser_range=1.0, comm_range=10.0, seed=1)
    write_scenario(tmp_path, grid, params, MeshOptions(), tmp_path / "mesh.json")
    display = DisplayProcess(tmp_path)
    robots = [RobotProcess(tmp_path, i) for i in range(3)]
    try:
        r0 = robots[0]
        for nid in (1, 2, DISPLAY):  # connect first: a send must not time out here
            r0._socket_to(nid)
        time.sleep(0.3)
        sent: list[list] = []
        real = r0.send_out

        def capture(out):  # every transmission list the robot puts on the air
            out = list(out)
            sent.append(out)
            real(out)

        r0.send_out = capture  # type: ignore[method-assign]
        for rid in (1, 2):  # two neighbours heard: NEED_MAP unicasts to each
            pos = robots[rid].pos()
            r0.on_frame(encode_radio(rid, pos, Heartbeat(rid, *pos)))
        for _ in range(20):  # two heartbeats (at the robot's phase, 10 ticks apart) and
            # the scans of every move flooded to both neighbours
            r0.tick()
            r0.t += 1
        r0.status()  # the harness's: not a message

        net = DiscNetwork(3, 10.0)
        net.move(np.zeros((3, 2)))  # everyone in range: every copy delivered
        for out in sent:
            for dst, msg in out:
                if dst == RADIO:
                    net.broadcast(0, msg)
                elif isinstance(dst, Fanout):
                    net.unicast_many(0, dst, msg)
                else:
                    net.unicast(0, dst, msg)
        sim = net.totals()
        tr = r0.traffic.to_dict()
        assert sim["by_kind"]["HEARTBEAT"]["messages"] == 2
        assert {"SCAN", "NEED_MAP"} <= set(sim["by_kind"])
        assert tr["by_kind"] == sim["by_kind"]
        assert tr["messages_out"] == sim["messages_sent"]
        assert tr["message_bytes_out"] == sim["bytes_sent"]
        # the harness apart: the STATUS of every 5 ticks and the one above, nothing else
        assert set(tr["harness_by_kind"]) == {"STATUS"}
        assert tr["harness_out"] == tr["harness_by_kind"]["STATUS"]["messages"] == 5
        # the sockets carried a heartbeat to each of the three others in the air
        beats = 2 * 3
        copies = sim["messages_sent"] - 2 + beats + tr["harness_out"]
        assert tr["frames_out"] + tr["send_timeouts"] == copies
    finally:
        for r in robots:
            r.close()
        display.close()
        display.view.close(0)
