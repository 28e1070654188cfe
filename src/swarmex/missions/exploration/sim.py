"""The exploration simulator: the true world, the lasers, the radio and the 100 ms clock.

The simulator owns everything a robot must not see — the true grid, where every robot is,
who is in radio range — and drives :class:`~swarmex.missions.exploration.robot.ExplorerRobot`
objects through the same calls a networked runtime would make. One tick (100 ms, the
thesis's movement period; exploration time is counted in these *steps*) runs:

1. **motion** — every robot with a plan takes one step to an adjacent cell; the simulator
   checks the step against the truth (adjacent, free, no corner cutting) and refuses
   nothing a correct robot asks, so a refused step is a bug and raises;
2. **sensing** — every robot that moved (and every robot at tick 0) gets a laser scan
   ray-cast against the truth; a robot that stood still would get the same scan again from
   a static world and a noise-free laser, so it takes none;
3. **messages** — heartbeats and timeouts (and AODV's queue: expiries, discovery retries),
   then every queued message is delivered, relays included, until the network is quiet
   (instantaneous, :mod:`swarmex.comm.mesh`); a unicast whose next hop has left the range
   is reported to its sender at once (:class:`Wire`), as a send timeout would be;
4. **planning** — robots whose timer fires or who have a request plan, in id order, each
   one's GOAL delivered before the next plans.

Robots are points for each other: they may share a cell (the thesis's robots do not avoid
each other, spec §6.5; nor can they block each other — each Robot Application simulates its
laser from the map file and its own position, §3.1, so no robot is in another's world). The
run ends when every robot has finished (its map has no reachable frontier), at ``max_ticks``,
or when the frame hook raises :class:`~swarmex.missions.base.StopRun` (complete only if every
robot had finished by then); randomness (timer and heartbeat phases: the robots' processes did
not start at the same instant) comes from one generator seeded by ``seed``.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from swarmex.comm.aodv import Routed, Rrep
from swarmex.comm.mesh import Batch, DiscNetwork, Fanout, FloodLedger, bits
from swarmex.engine.collector import fewer_collections
from swarmex.missions.base import StopRun
from swarmex.missions.exploration.messages import Goal, ScanMsg, ScanRecord, scan_head_size
from swarmex.missions.exploration.params import (
    Cell,
    ExplorationParams,
    default_starts,
    max_ticks_for,
    min_region_cells,
    validate,
)
from swarmex.missions.exploration.paths import distance_steps
from swarmex.missions.exploration.robot import RADIO, UNICASTS, ExplorerRobot, Out, RobotConfig
from swarmex.missions.exploration.strategies import get_strategy
from swarmex.sensing.laser import Laser
from swarmex.sensing.occupancy import GridPool
from swarmex.worlds.metric import MetricGrid

FrameHook = Callable[[int, "ExplorationRun"], None]
StartHook = Callable[["ExplorationRun"], None]


@dataclass
class ExplorationRun:
    params: ExplorationParams
    grid: MetricGrid
    robots: list[ExplorerRobot]
    starts: tuple[Cell, ...]
    trajectories: list[list[tuple[int, int, int]]]  # per robot: (tick, x, y) at every move
    network: DiscNetwork
    makespan: int = 0
    complete: bool = False
    wall_seconds: float = 0.0
    reachable: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), bool))

    def team_free(self) -> np.ndarray:
        """Cells some robot's map holds as free."""
        out = np.zeros(self.grid.shape, dtype=bool)
        for r in self.robots:
            out |= r.belief.grid.logodds < 0
        return out

    def team_occupied(self) -> np.ndarray:
        out = np.zeros(self.grid.shape, dtype=bool)
        for r in self.robots:
            out |= r.belief.grid.logodds > 0
        return out

    def explored_fraction(self) -> float:
        total = int(self.reachable.sum())
        return float((self.team_free() & self.reachable).sum()) / total if total else 1.0


def reachable_free(free: np.ndarray, starts: tuple[Cell, ...]) -> np.ndarray:
    """True free cells connected to a start by 8-moves without corner cutting."""
    out = np.zeros(free.shape, dtype=bool)
    for x, y in starts:
        if not out[y, x]:
            out |= distance_steps(free, x, y) >= 0
    return out


def legal_step(free: np.ndarray, a: Cell, b: Cell) -> bool:
    """One 8-neighbour move onto a free cell, not squeezing between two walls."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    if max(abs(dx), abs(dy)) != 1 or not free[b[1], b[0]]:
        return False
    return not (dx and dy) or bool(free[a[1], b[0]] and free[b[1], a[0]])


_UNICAST = (*UNICASTS, Routed, Rrep)  # unicasts whose failed send a router learns of


class Wire:
    """Carries robots' outgoing ``(destination, message)`` lists over a :class:`DiscNetwork`.

    A robot that routes with AODV learns when a unicast (an application unicast, a routed
    hop or an RREP) cannot reach its next hop — the thesis's nanomsg send timeout — and
    reacts at once (:meth:`ExplorerRobot.link_failed`); floods and RERRs are fire-and-forget.
    A :class:`~swarmex.comm.mesh.Fanout` destination (a relay or a ``GOAL`` to every
    neighbour) travels as one batch.
    """

    def __init__(self, net: DiscNetwork, robots: list[ExplorerRobot]) -> None:
        self.net = net
        self.robots = robots
        self.t = 0
        self.ledger = FloodLedger()
        for r in robots:
            r.mesh.use_ledger(self.ledger)  # seen keys: one bitmask per key for the team
            for n in r.mesh.neighbours:  # robots built with neighbours already
                lst = self.ledger.listeners
                lst[n] = lst.get(n, 0) | (1 << r.id)
        self.delivered = 0  # copies handed to a robot (the rest were dropped unseen)
        self.heads = [scan_head_size(r.id) for r in robots]  # a relay's SCAN envelope, bytes

    def send(self, src: int, out: Out, t: int | None = None) -> None:
        if t is not None:
            self.t = t
        routed = self.robots[src].aodv is not None
        i = 0
        while i < len(out):  # consecutive sends of one message go out together
            dst, msg = out[i]
            if type(dst) is Fanout:
                self.net.unicast_many(src, dst, msg)
                i += 1
                continue
            j = i + 1
            while j < len(out) and out[j][1] is msg:
                j += 1
            if dst == RADIO:
                self.net.broadcast(src, msg)
            elif routed and type(msg) in _UNICAST:
                for d, m in out[i:j]:  # plain ids: a Fanout is handled above
                    if not self.net.unicast(src, cast(int, d), m):
                        self.send(src, self.robots[src].link_failed(cast(int, d), m, self.t))
            else:
                self.net.unicast_many(src, [cast(int, d) for d, _ in out[i:j]], msg)
            i = j

    def settle(self, t: int) -> None:
        """Deliver until the network is quiet (relays and replies included).

        A flooded copy whose every scan the receiver has already seen, from a sender it
        already knows, would be dropped by the receiver without effect; it is counted as
        sent but not handed over (the flood's main cost in Python calls). For a batch the
        ledger finds those receivers with a few bit operations: handing a copy to one
        receiver changes only that receiver, so the batch's mask, computed once, stays right
        for the receivers after it. A new flooded scan from a listed neighbour takes
        :meth:`_flood`, a ``GOAL`` from one :meth:`ExplorerRobot.take_goal`.
        """
        robots = self.robots
        holders = self.ledger.holders
        listeners = self.ledger.listeners
        self.t = t
        for src, dst, msg in self.net.drain_batches():
            if type(dst) is Batch:
                mask = dst.mask
                tm = type(msg)
                if tm is ScanMsg:
                    scans = msg.scans
                    if len(scans) == 1:  # a flooded scan: most receivers take it new
                        mask &= ~(holders.get(scans[0].key, 0) & listeners.get(src, 0))
                        if mask:
                            self._flood(src, mask, cast(ScanMsg, msg), t)
                        continue
                    mask &= ~(self.ledger.have_all(s.key for s in scans)
                              & listeners.get(src, 0))
                elif tm is Goal:
                    goal = cast(Goal, msg)
                    for d in bits(mask):
                        self.delivered += 1
                        r = robots[d]
                        out = r.take_goal(src, goal, t) if src in r.mesh.neighbours \
                            else r.on_message(src, msg, t)
                        if out:
                            self.send(d, out)
                    continue
                for d in bits(mask):
                    self.delivered += 1
                    self.send(d, robots[d].on_message(src, msg, t))
                continue
            r = robots[dst]
            if type(msg) is ScanMsg and src in r.mesh.neighbours:
                seen = r.mesh.seen
                scans = msg.scans
                if (scans[0].key in seen) if len(scans) == 1 else all(s.key in seen for s in scans):
                    continue
            self.delivered += 1
            self.send(dst, r.on_message(src, msg, t))

    def _flood(self, src: int, mask: int, msg: ScanMsg, t: int) -> None:
        """Hand one flooded scan from ``src`` to the robots of ``mask`` (in id order).

        A robot that has not seen the scan and lists ``src`` takes it
        (:meth:`ExplorerRobot.accept_scan`) and relays it to its other neighbours: the relay
        goes out from the neighbour bitmask through :meth:`DiscNetwork.send_mask`, which
        :meth:`DiscNetwork.unicast_many` uses for a :class:`Fanout` too (copies to every
        listed neighbour but ``src``, the ones out of range lost), and before the robot's own
        messages, as :meth:`ExplorerRobot.take_scan` orders them. Any other receiver takes
        the general path. The relay is ``msg`` itself: a receiver reads the scans and the
        queue entry's sender, never the message's ``src`` field (which keeps naming the
        first sender), and its size is counted here (``heads``), not read from it.
        """
        robots = self.robots
        net = self.net
        heads = self.heads
        kind = ScanMsg.kind
        rec = msg.scans[0]
        size = rec.nbytes
        # who has seen the scan: a receiver's own bit changes only when it takes it, so the
        # mask read once is right for each receiver of the loop (``key in mesh.seen``)
        seen = self.ledger.holders.get(rec.key, 0)
        for d in bits(mask):
            self.delivered += 1
            r = robots[d]
            mesh = r.mesh
            nb = mesh.neighbours
            if seen >> d & 1 or src not in nb:
                out = r.on_message(src, msg, t)
                if out:
                    self.send(d, out)
                continue
            asks = r.accept_scan(rec, t)
            if len(nb) > 1:  # the relay to every neighbour but src: the same scan, from d
                net.send_mask(d, mesh.neighbour_mask() & ~(1 << src), msg, kind,
                              heads[d] + size)
            if asks:
                self.send(d, asks)


def build_robots(
    grid: MetricGrid,
    params: ExplorationParams,
    rng: np.random.Generator,
    routing: bool = False,
) -> tuple[list[ExplorerRobot], tuple[Cell, ...], Laser]:
    """The team. ``routing`` turns AODV on (the simulator and the process mesh pass
    ``params.aodv``); off, every unicast goes to a direct neighbour."""
    laser = Laser(params.laser_range, params.beams, grid.cell)
    starts = params.starts or default_starts(grid, params.robots, params.robot_radius)
    radius_cells = params.robot_radius / grid.cell
    cfg = RobotConfig(
        shape=grid.shape,
        angles=laser.angles,
        laser_cells=laser.range_cells,
        radius_cells=radius_cells,
        min_region=min_region_cells(radius_cells),
        strategy=get_strategy(params.strategy),
        plan_period=params.plan_period,
        heartbeat_period=params.heartbeat_period,
        neighbour_timeout=params.neighbour_timeout,
        goal_ttl=2 * params.plan_period,
        aodv=routing,
        conflict_yield=params.conflict_yield,
        plan_pause=params.plan_pause,
    )
    plan_phase = rng.integers(0, params.plan_period, params.robots)
    hb_phase = rng.integers(0, params.heartbeat_period, params.robots)
    robots = [
        ExplorerRobot(i, cfg, starts[i], int(plan_phase[i]), int(hb_phase[i]))
        for i in range(params.robots)
    ]
    return robots, tuple(starts), laser


def run_exploration(
    grid: MetricGrid,
    params: ExplorationParams,
    on_frame: FrameHook | None = None,
    frame_every: int = 0,
    on_start: StartHook | None = None,
) -> ExplorationRun:
    """Run one exploration. ``on_frame(t, run)`` is called every ``frame_every`` ticks (and
    at the end); ``on_start(run)`` once the team is built, before tick 0 — the
    reinforcement-learning environment (:mod:`swarmex.envs.exploration_v0`) uses it to watch
    the robots and to hand their goal choice (the strategy in ``robot.cfg``) to its caller."""
    with fewer_collections():
        return _run(grid, params, on_frame, frame_every, on_start)


def _run(
    grid: MetricGrid,
    params: ExplorationParams,
    on_frame: FrameHook | None,
    frame_every: int,
    on_start: StartHook | None,
) -> ExplorationRun:
    validate(params, grid)
    t0 = time.perf_counter()
    rng = np.random.default_rng(params.seed)
    robots, starts, laser = build_robots(grid, params, rng, routing=params.aodv)
    pool = GridPool()  # every scan comes from this one truth: grids in one state are one
    store: dict[tuple[int, int], ScanRecord] = {}  # a key names one scan: one record each
    for r in robots:
        r.belief.grid.share(pool)
        r.belief.archive.share(store)
    n = len(robots)
    net = DiscNetwork(n, params.comm_range)
    run = ExplorationRun(
        params,
        grid,
        robots,
        starts,
        [[(0, x, y)] for x, y in starts],
        net,
        reachable=reachable_free(grid.free, starts),
    )
    truth = grid.free
    max_ticks = params.max_ticks or max_ticks_for(grid, params.laser_range)

    if on_start is not None:
        on_start(run)
    wire = Wire(net, robots)

    moved = [True] * n
    stopped = False
    for t in range(max_ticks + 1):
        if t > 0:
            for i, r in enumerate(robots):
                step = r.next_step()
                moved[i] = step is not None
                if step is None:
                    continue
                if not legal_step(truth, r.pos, step):
                    raise RuntimeError(f"robot {i} asked for an illegal step {r.pos}->{step}")
                r.moved(step)
                run.trajectories[i].append((t, step[0], step[1]))
        if any(moved):
            net.move(np.array([r.pos for r in robots], dtype=np.float64) * grid.cell)
        for i, r in enumerate(robots):
            if moved[i]:
                wire.send(i, r.observe(laser.cast(truth, *r.pos), t), t)
        for i, r in enumerate(robots):
            wire.send(i, r.housekeeping(t), t)
        wire.settle(t)
        for i, r in enumerate(robots):
            wire.send(i, r.maybe_plan(t), t)
            wire.settle(t)
        run.makespan = t
        run.complete = all(r.finished for r in robots)
        if on_frame is not None and frame_every > 0 and t % frame_every == 0:
            try:
                on_frame(t, run)
            except StopRun:
                stopped = True
                break
        if run.complete:
            break
    run.wall_seconds = time.perf_counter() - t0
    if not stopped and on_frame is not None and frame_every > 0 and run.makespan % frame_every:
        with contextlib.suppress(StopRun):  # the run has ended anyway
            on_frame(run.makespan, run)
    return run
