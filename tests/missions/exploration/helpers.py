"""Small builders shared by the exploration tests."""

from __future__ import annotations

import numpy as np

from swarmex.comm.mesh import DiscNetwork
from swarmex.missions.exploration.robot import ExplorerRobot, RobotConfig
from swarmex.missions.exploration.sim import Wire
from swarmex.missions.exploration.strategies import GoalContext, get_strategy
from swarmex.sensing.frontiers import Frontiers
from swarmex.sensing.laser import Laser

CELL = 0.05


def config(shape=(40, 400), strategy="greedy-exclusion", laser_m=0.5) -> RobotConfig:
    laser = Laser(laser_m, 90, CELL)
    return RobotConfig(
        shape=shape, angles=laser.angles, laser_cells=laser.range_cells, radius_cells=2.0,
        min_region=4, strategy=get_strategy(strategy),
    )


def team(cells, range_m, cfg=None):
    """Robots at ``cells`` (x, y) on an empty-truth grid, with their radio network."""
    cfg = cfg or config()
    robots = [ExplorerRobot(i, cfg, c) for i, c in enumerate(cells)]
    net = DiscNetwork(len(robots), range_m)
    wire = Wire(net, robots)
    place(robots, net)
    return robots, net, wire


def place(robots, net) -> None:
    net.move(np.array([r.pos for r in robots], dtype=np.float64) * CELL)


def scan(robot, t=0):
    """The robot's own scan of an open field (nothing within range)."""
    laser_cells = robot.cfg.laser_cells
    return robot.observe(np.full(len(robot.cfg.angles), laser_cells), t)


def heartbeats(robots, wire, t) -> None:
    for r in robots:
        wire.send(r.id, r.housekeeping(t))
    wire.settle(t)


def goal_context(cells, dists, **kw):
    """A GoalContext whose candidates are ``cells`` (x, y), each its own frontier region,
    ``dists`` steps from a robot at (0, 0)."""
    xs = np.array([c[0] for c in cells])
    ys = np.array([c[1] for c in cells])
    fr = Frontiers(ys, xs, np.arange(len(cells)), np.ones(len(cells), int), 0)
    return GoalContext(me=0, pos=(0, 0), frontiers=fr, eligible=np.ones(len(cells), bool),
                       dist=np.array(dists), laser_cells=10.0, **kw)
