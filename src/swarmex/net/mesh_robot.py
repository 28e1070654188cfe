"""A robot process of the mesh: the simulator's explorer driven by a wall clock and sockets.

The very :class:`~swarmex.missions.exploration.robot.ExplorerRobot` the simulator runs, with
its laser reading the true world in this process, its messages put on the emulated radio
(:class:`~swarmex.net.mesh_node.Node`) and its telemetry (STATUS, REPORT) sent to the
display on the control link. Apart from the display because the two processes share only
the node and the frames.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import zmq

from swarmex.comm.aodv import Routed
from swarmex.comm.mesh import Fanout
from swarmex.comm.message import PackedMessage
from swarmex.net import wire
from swarmex.net.mesh_frames import (
    DISPLAY,
    RADIO_KIND,
    control_message,
    encode_radio,
    radio_message,
)
from swarmex.net.mesh_node import Node
from swarmex.net.mesh_record import _by_origin
from swarmex.net.mesh_scenario import read_scenario
from swarmex.net.routing import unicast_counts, wants_feedback

STATUS_EVERY = 5  # ticks between STATUS frames (at most; and at least every STATUS_WALL s)
STATUS_WALL = 0.25  # wall seconds: liveness must not depend on the time scale


class RobotProcess(Node):
    """One robot: its :class:`ExplorerRobot`, its laser on the truth, its radio."""

    def __init__(self, run_dir: Path, rid: int) -> None:
        from swarmex.missions.exploration.sim import build_robots, legal_step
        from swarmex.sensing.laser import Laser

        grid, params, options, _ = read_scenario(run_dir)
        super().__init__(rid, run_dir, options, params.seed)
        self.grid = grid
        self.params = params
        rng = np.random.default_rng(params.seed)  # the simulator's phases, robot by robot
        robots, starts, laser = build_robots(grid, params, rng, routing=params.aodv)
        self.robot = robots[rid]
        self.laser: Laser = laser
        self.legal_step = legal_step
        self.truth = grid.free
        self.trajectory: list[list[int]] = [[0, *starts[rid]]]
        self.unsent_moves: list[list[int]] = [[0, *starts[rid]]]
        self.t = 0
        self.stop = False
        self.go = False
        self.last_control = time.monotonic()
        self.status_at = 0.0
        from swarmex.missions.exploration.params import max_ticks_for

        self.max_ticks = params.max_ticks or max_ticks_for(grid, params.laser_range)

    def pos(self) -> tuple[int, int]:
        return self.robot.pos

    def send_out(self, out: Iterable[tuple[int | Fanout, PackedMessage | Routed]]) -> None:
        """Put the robot's messages on the air. With AODV, a unicast (application unicast,
        routed hop, RREP) that cannot be sent is a broken link: the robot re-queues it and
        rediscovers (:meth:`ExplorerRobot.link_failed`), as in the simulator. A
        :class:`Fanout` (one message to several neighbours) goes out as a frame each."""
        from swarmex.missions.exploration.robot import RADIO

        routed = self.robot.aodv is not None
        for dst, msg in out:
            if routed and dst != RADIO and wants_feedback(msg):
                for nid in dst if isinstance(dst, Fanout) else (dst,):  # a unicast each
                    if not self.unicast_frame(nid, msg, self.pos(), self.t):
                        self.send_out(self.robot.link_failed(nid, msg, self.t))
                continue
            frame = encode_radio(self.id, self.pos(), msg)
            if isinstance(dst, Fanout):  # one message to several neighbours: a copy each
                self.transmit(dst, msg, frame)
            elif dst == RADIO:  # heartbeat: to everyone in the air; range decides who hears
                self.broadcast(msg, frame)
            else:
                self.transmit((dst,), msg, frame)

    def control(self, obj: list[Any]) -> None:
        """A frame on the control link to the display (the harness, not the radio)."""
        self.send_control(DISPLAY, obj)

    def on_frame(self, frame: bytes) -> None:
        from swarmex.missions.exploration.messages import Heartbeat

        try:
            obj = wire.unpack(frame)
            if isinstance(obj, list) and obj and obj[0] == RADIO_KIND:
                src, where, msg = radio_message(obj, self.grid.shape)
            else:
                cmd = control_message(obj)
                if cmd[0] == "NACK":  # a unicast of ours was out of the receiver's range
                    self._refused(int(cmd[1]), int(cmd[2]))
                    return
                self.last_control = time.monotonic()
                if cmd[0] == "STOP":
                    self.stop = True
                elif cmd[0] == "GO":
                    self.go = True
                return
        except wire.WireError:
            self.traffic.bad_frames += 1
            return
        if src == self.id:
            return
        if not self.admitted(obj, src, self.pos(), where, self.grid.cell, self.params.comm_range):
            return
        if src == DISPLAY and isinstance(msg, Heartbeat):
            self.robot.mesh.hear(DISPLAY, self.t)  # the display is a router, not a teammate
            if self.robot.aodv is not None:  # ... and one AODV may route through
                self.send_out(self.robot.aodv.hello(DISPLAY, self.t))
            return
        self.arrived(msg)
        self.send_out(self.robot.on_message(src, msg, self.t))  # type: ignore[arg-type]

    def _refused(self, by: int, seq: int) -> None:
        msg = self.link.refused(by, seq)
        if msg is not None:
            self.send_out(self.robot.link_failed(by, msg, self.t))

    def tick(self) -> None:
        r = self.robot
        t = self.t
        moved = t == 0
        if t > 0:
            step = r.next_step()
            if step is not None:
                if not self.legal_step(self.truth, r.pos, step):
                    raise RuntimeError(f"robot {self.id} asked for an illegal step")
                r.moved(step)
                moved = True
                self.trajectory.append([t, step[0], step[1]])
                self.unsent_moves.append([t, step[0], step[1]])
        if moved:
            self.send_out(r.observe(self.laser.cast(self.truth, *r.pos), t))
        self.send_out(r.housekeeping(t))
        self.send_out(r.maybe_plan(t))
        self.link.prune(t)
        if t % STATUS_EVERY == 0:
            self.status()

    def status(self) -> None:
        self.status_at = time.monotonic()
        r = self.robot
        self.control(["STATUS", self.id, {
            "t": self.t, "x": r.pos[0], "y": r.pos[1], "finished": r.finished,
            "stopped": self.t > self.max_ticks,
            "goal": None if r.goal is None else list(r.goal), "moves": self.unsent_moves,
        }])
        self.unsent_moves = []

    def report(self) -> dict[str, Any]:
        r = self.robot
        s = r.stats
        free = r.belief.grid.logodds < 0
        return {
            "steps": s.finished_at if s.finished_at is not None else self.t,
            "finished_at": s.finished_at,
            "ticks": self.t,
            "moves": s.moves, "plans": s.plans, "replans": s.replans,
            "replan_reasons": dict(sorted(s.reasons.items())),
            "plan_ticks": list(s.plan_ticks), "scans": s.scans,
            "archive": len(r.belief.archive), "conflicts": s.conflicts,
            "scans_by_origin": _by_origin(r.belief.archive.scans),
            "change_goals_sent": s.change_goals_sent,
            "blacklisted_regions": s.blacklisted_regions,
            "trajectory": self.trajectory,
            "free": np.packbits(free.ravel()).tobytes(),
            "traffic": self.traffic.to_dict(),
            "unicasts": unicast_counts(r.aodv, s.gap_requests),
            "multihop_in": dict(sorted(self.multihop_in.items())),
            "link_refusals": self.link.refusals,
        }

    def warm_up(self) -> None:
        """A first tick on a scratch copy of this robot, before saying HELLO: loading the
        compiled kernels (laser, maps, planning) can take seconds on a busy machine, long
        enough to look dead to the display."""
        from swarmex.missions.exploration.sim import build_robots

        robots, _, laser = build_robots(self.grid, self.params,
                                        np.random.default_rng(self.params.seed),
                                        routing=self.params.aodv)
        r = robots[self.id]
        r.observe(laser.cast(self.truth, *r.pos), 0)
        r.housekeeping(0)
        r.maybe_plan(0)

    def run(self) -> int:
        opts = self.options
        tick_wall = 0.1 * opts.time_scale
        self.warm_up()
        self.last_control = time.monotonic()
        deadline = time.monotonic() + opts.timeout
        hello_at = 0.0
        # HELLO until GO: the display may come up after us
        while not self.go and not self.stop:
            now = time.monotonic()
            if now > deadline or now - self.last_control > opts.start_timeout + 5:
                return 3
            if now >= hello_at:
                self.control(["HELLO", self.id, self.endpoint])
                hello_at = now + 0.5
            if self.pull.poll(100):
                for f in self.recv_all():
                    self.on_frame(f)
        next_tick = time.monotonic()
        kill_at = opts.inject_kill.get(self.id)
        max_ticks = self.max_ticks
        while not self.stop:
            now = time.monotonic()
            if now > deadline or now - self.last_control > max(10.0, 4 * opts.dead_after):
                return 3  # the display (the experiment) is gone
            if now >= next_tick:
                if kill_at is not None and self.t >= kill_at:
                    os._exit(137)  # fault injection: no goodbye, sockets left as they are
                if self.t <= max_ticks:
                    self.tick()
                    self.t += 1
                next_tick += tick_wall
                if next_tick < now - 1.0:  # far behind (a slow machine): do not burst
                    next_tick = now
            if time.monotonic() - self.status_at >= STATUS_WALL:
                self.status()  # telemetry is also the display's proof of life
            wait = max(0.0, min(next_tick, self.status_at + STATUS_WALL) - time.monotonic())
            if self.pull.poll(int(wait * 1000)):
                for f in self.recv_all():
                    self.on_frame(f)
                    if self.stop:
                        break
        self.status()
        self.control(["REPORT", self.id, self.report()])
        sock = self.push.get(DISPLAY)
        if sock is not None:  # let the report leave before the sockets close
            sock.setsockopt(zmq.LINGER, 3000)
        return 0
