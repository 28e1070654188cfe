"""One exploring robot of seed 003: its threads folded into reactions to ticks and messages.

The thesis's Robot Application runs five threads around three shared structures (§3.3).
Here the same logic is a plain object driven from outside — by the simulator now, by a
networked runtime later — through four calls, each returning the messages to send as
``(destination, message)`` pairs (destination :data:`RADIO` means a radio broadcast):

* :meth:`ExplorerRobot.observe` — the motion thread's scan: rasterise it into a local map,
  archive it, update the map, and flood it as ``SCAN``;
* :meth:`ExplorerRobot.housekeeping` — the message thread's heartbeat (every 1 s) and
  neighbour timeouts;
* :meth:`ExplorerRobot.on_message` — the message thread's reactions (below);
* :meth:`ExplorerRobot.maybe_plan` — the planning thread: on the 2 s timer or on request.

and :meth:`next_step` / :meth:`moved` for the motion itself. The robot sees only its belief:
its map, its archive, what neighbours told it, and its own pose (no localisation problem).

Reactions and the choices behind them (spec §6.3–6.7, 6.13):

* heartbeat from a robot not in the neighbour table → add it and send it ``NEED_MAP`` with a
  summary of the archive; any other message from an unknown sender also adds it (the
  thesis's reverse connection). ``NEED_MAP`` → reply ``MAP`` with the scans the requester
  lacks. Scans first learnt from a ``MAP`` are passed on as ``SCAN`` to the other
  neighbours, so that when two groups meet, both groups (not only the two robots that met)
  catch up. ``SCAN`` → integrate the new local maps and relay them (de-duplicated by
  ``(origin, seq)``, :class:`~swarmex.comm.mesh.MeshNode`).
* ``GOAL`` goes to the direct neighbours only ("new generated plan broadcasts to all
  neighbors"), when the strategy uses goals (greedy-exclusion). A neighbour's goal counts
  for exclusion while the neighbour stays in the table and for at most two planning periods
  (it is re-announced at every plan). A robot that finds no frontier announces "no goal".
* Conflict ("two robots have goals in the same area" = goals within the laser range):
  priority is the path length from the robot to its goal, **shorter is higher**, ties to the
  lower id. The lower-priority robot re-plans at once ("unscheduled re-planning"); the
  higher-priority one sends ``CHANGE_GOAL`` to the other, which re-plans. A robot plans at
  most once per tick, so a ping-pong between two robots that both fall back onto the same
  zone costs one plan per tick each — the end-of-exploration crowding the thesis reports.
* Two options (off by default; the team-size study, docs/exploration.md) make a re-plan
  cost what the thesis's explanation of its optimal team size needs it to cost (§4.2–4.3:
  more plan generations → more steps): ``conflict_yield`` — the loser of a conflict may not
  keep a goal in the winner's zone even when every candidate lies in some zone (off: the
  "prefers" fallback is plain greedy, usually the goal it had); ``plan_pause`` — the robot
  stands still for that many ticks after every plan generation (planning time, during which
  the motion thread would wait; off: planning is instantaneous, as in the thesis's step
  count, which the text never says planning interrupts).
* Unscheduled plans are also requested when the goal is reached and when the next cell of
  the path turns out blocked (the motion thread finds "no plan"). The timer keeps running
  from the robot's start: an unscheduled plan does not move it.
* A robot with no reachable frontier has *finished*; unreachable frontiers (e.g. behind a
  gap narrower than the robot) are blacklisted at each plan, not forever, since a later map
  may reveal a way round. A finished robot stays in the mesh (relays, answers ``NEED_MAP``),
  re-checks its map on the timer, and resumes if new frontiers appear.

Unicasts and AODV (spec §2.8, seed §3.3.5; ``RobotConfig.aodv``, on in the simulator and in
the process mesh). The messages addressed to one robot — ``NEED_MAP``, ``MAP``,
``CHANGE_GOAL`` — go through the thesis's unicast queue, :meth:`ExplorerRobot.unicast`: AODV
(:class:`~swarmex.comm.aodv.AodvNode`) sends them at once along a valid route or keeps them
while it discovers one, until their lifetime ends (``CHANGE_GOAL`` one planning period, after
which it is stale; the others ``unicast_lifetime``, 10 s). Heartbeats are AODV's hellos, a
neighbour timeout or a failed send (:meth:`link_failed`) a link break. Which of them can
need more than one hop is a reading of the seed:

* ``MAP`` answers a ``NEED_MAP`` and ``CHANGE_GOAL`` answers a ``GOAL``, and both requests
  come straight from a neighbour (``GOAL`` is one hop: "broadcasts to all neighbors"), so
  with instantaneous delivery their target is in range; AODV only matters for them if the
  link breaks before the reply leaves (then the reply is re-queued and re-routed). Multi-hop
  goal knowledge (flooded ``GOAL``) is not what the thesis describes, so ``CHANGE_GOAL``
  never starts from a robot two hops away.
* ``NEED_MAP`` to the **origin of missing scans**: seqs number each origin's scans, so a robot
  that holds (o, 7) but not (o, 5) knows it missed some (flood copies sent to a neighbour
  that had just left the range are lost), and o is the one robot sure to hold them — usually
  several hops away. The seed's ``NEED_MAP`` "inform[s] about the need to send the entire
  scans archive to the message sender"; sending it where the need can be met is our reading
  of its open trigger (spec §6.7). The ``MAP`` comes back along the reverse route. At most
  one such request per origin per unicast lifetime.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from swarmex.comm.aodv import AodvMessage, AodvNode, AodvTiming, Routed
from swarmex.comm.mesh import Fanout, MeshNode
from swarmex.missions.exploration.belief import ADDED_GAP, HELD, Cell, ExplorationBelief
from swarmex.missions.exploration.messages import (
    ChangeGoal,
    Goal,
    Heartbeat,
    MapMsg,
    Message,
    NeedMap,
    ScanMsg,
    ScanRecord,
)
from swarmex.missions.exploration.paths import (
    distance_steps,
    distance_toward,
    distance_until,
    field_padded,
    footprint_clear,
    footprint_offsets,
    inflate,
    labels4,
    padded,
    path_to,
    path_to_padded,
    reachable_pieces,
    steps_via_field,
)
from swarmex.missions.exploration.strategies import GoalContext, Strategy, nearest_candidate
from swarmex.sensing.frontiers import Frontiers, frontiers_of_logodds
from swarmex.sensing.occupancy import rasterise

RADIO = -1  # destination of a radio broadcast (heartbeats)
# (destination, message): a robot id, RADIO, or a Fanout (the same message to several
# neighbours, in id order: a flood relay or a GOAL; one entry whatever their number)
Out = list[tuple[int | Fanout, Message]]
UNICASTS = (NeedMap, MapMsg, ChangeGoal)  # the messages addressed to one robot
#: Why a robot plans before its goal is reached (the record's ``replan_reasons`` keys): a
#: CHANGE_GOAL received, a goal conflict lost, its path blocked, its goal reached, its goal
#: seen (no longer a frontier).
REPLAN_REASONS = ("change_goal", "conflict", "blocked", "reached", "seen")
FAR = np.iinfo(np.int32).max  # steps to a reachable cell a bounded search did not reach
FIELDS_UP_TO = 8  # candidates up to which a plan uses fields from them (shared per map state)


@dataclass(frozen=True)
class RobotConfig:
    """Everything a robot needs to know about itself and the team's conventions (ticks)."""

    shape: tuple[int, int]  # (rows, cols) of the shared grid
    angles: np.ndarray  # laser beam angles (radians)
    laser_cells: float  # laser range, cells
    radius_cells: float  # robot radius, cells
    min_region: int  # smallest frontier region kept, cells
    strategy: Strategy
    plan_period: int = 20  # 2 s of 100 ms ticks
    heartbeat_period: int = 10  # 1 s
    neighbour_timeout: int = 30  # 3 s
    goal_ttl: int = 40  # two planning periods
    aodv: bool = False  # route unicasts with AODV (the simulator and the process mesh do)
    unicast_lifetime: int = 100  # 10 s: a queued NEED_MAP / MAP waits this long for a route
    conflict_yield: bool = False  # a conflict's loser leaves the winner's zone (see plan)
    plan_pause: int = 0  # ticks the robot stands still after a plan generation
    offsets: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "offsets", footprint_offsets(self.radius_cells))


@dataclass
class RobotStats:
    plan_ticks: list[int] = field(default_factory=list)  # plan generations (Fig. 4.4)
    plans: int = 0
    replans: int = 0  # unscheduled plan generations
    reasons: dict[str, int] = field(default_factory=dict)
    scans: int = 0
    moves: int = 0
    conflicts: int = 0
    change_goals_sent: int = 0
    gap_requests: int = 0  # NEED_MAP sent to the origin of missing scans (AODV on)
    blacklisted_regions: int = 0  # unreachable frontier regions at the latest plan
    finished_at: int | None = None


class ExplorerRobot:
    def __init__(
        self,
        rid: int,
        config: RobotConfig,
        pos: Cell,
        plan_phase: int = 0,
        heartbeat_phase: int = 0,
    ) -> None:
        self.id = rid
        self.cfg = config
        self.belief = ExplorationBelief(config.shape, (int(pos[0]), int(pos[1])))
        self.mesh = MeshNode(
            rid, config.heartbeat_period, config.neighbour_timeout, phase=heartbeat_phase
        )
        self.plan_phase = plan_phase
        self.seq = 0
        self.goal: Cell | None = None
        self.path = np.empty((0, 2), dtype=np.int64)
        self.path_i = 0
        self.request: str | None = None  # reason of a pending unscheduled plan
        self.last_plan_t = -1
        self.stats = RobotStats()
        self.aodv: AodvNode | None = None
        if config.aodv:
            self.aodv = AodvNode(
                rid,
                self.mesh.relay_targets,
                AodvTiming.for_mesh(config.heartbeat_period, config.neighbour_timeout),
            )
        self.asked: dict[int, int] = {}  # origin -> tick of the last gap NEED_MAP to it
        self.beaten_by: set[int] = set()  # robots that won a conflict since the last plan
        self.hold = 0  # ticks left standing still while a plan is computed (plan_pause)
        self.start: Cell = (int(pos[0]), int(pos[1]))  # where it was deployed
        self.team_size = rid + 1  # 1 + the highest robot id it has heard
        self.last_contact = 0  # the last tick it heard a teammate
        self.rendezvous_for = -1  # the contact after which it last stood at its start
        # the cells (ys, xs) of the goal's frontier region when it was chosen
        self.goal_region: tuple[np.ndarray, np.ndarray] | None = None

    # ------------------------------------------------------------------ state
    @property
    def pos(self) -> Cell:
        return self.belief.pos

    @property
    def finished(self) -> bool:
        return self.stats.finished_at is not None

    @property
    def remaining(self) -> int:
        return int(self.path.shape[0] - self.path_i)

    def _to_neighbours(self, msg: Message, but: int | None = None) -> Out:
        """``msg`` to every neighbour (but ``but``), as one entry; nothing if there are none."""
        fan = self.mesh.fanout(but)
        return [(fan, msg)] if len(fan) else []

    def _lifetime(self, msg: object) -> int:
        """How long a unicast may wait for a route: a ``CHANGE_GOAL`` one planning period
        (after that the sender has re-planned and re-announced its goal, so the order is
        stale), the others ``unicast_lifetime``."""
        if isinstance(msg, ChangeGoal):
            return self.cfg.plan_period
        return self.cfg.unicast_lifetime

    def unicast(self, dst: int, msg: Message, t: int) -> Out:
        """The thesis's unicast queue: by AODV when routing is on, else to a neighbour."""
        if self.aodv is None:
            return [(dst, msg)]
        return cast(Out, self.aodv.send(dst, msg, t, self._lifetime(msg)))

    def link_failed(self, dst: int, msg: object, t: int) -> Out:
        """The radio could not deliver a unicast to ``dst`` (it left the range): AODV
        breaks the link, re-queues the payload and rediscovers a route."""
        if self.aodv is None:
            return []
        return cast(Out, self.aodv.send_failed(dst, msg, t, self._lifetime(msg)))

    def _request(self, reason: str) -> None:
        assert reason in REPLAN_REASONS, reason  # the record's declared replan_reasons keys
        if self.request is None:
            self.request = reason

    # ---------------------------------------------------------------- sensing
    def observe(self, ranges: np.ndarray, t: int) -> Out:
        """Own scan (ranges in cells from the robot's cell): map it and flood it."""
        x, y = self.pos
        local = rasterise(x, y, ranges, self.cfg.angles, self.cfg.laser_cells, self.cfg.shape)
        rec = ScanRecord(self.id, self.seq, x, y, local)
        self.seq += 1
        self.stats.scans += 1
        self.mesh.first_time(rec.key)
        self.belief.integrate(rec)
        return self._to_neighbours(ScanMsg(self.id, (rec,)))

    # -------------------------------------------------------------- messaging
    def housekeeping(self, t: int) -> Out:
        out: Out = []
        if self.mesh.heartbeat_due(t):
            out.append((RADIO, Heartbeat(self.id, *self.pos)))
        for gone in self.mesh.expire(t):
            self.belief.forget(gone)
            if self.aodv is not None:
                out.extend(self.aodv.link_broken(gone, t))
        if self.aodv is not None:
            out.extend(self.aodv.tick(t))
        return out

    def on_message(self, src: int, msg: Message, t: int) -> Out:
        out: Out = []
        aodv = self.aodv
        if isinstance(msg, Heartbeat):
            self.belief.hear_position(src, (msg.x, msg.y), t)
            new = self.mesh.hear(src, t)
            if aodv is not None:
                out.extend(aodv.hello(src, t))  # heartbeats are AODV's hello messages
            if new:
                out.extend(self.unicast(src, NeedMap(self.id, self.belief.archive.summary()), t))
            return out
        if src not in self.mesh.neighbours:  # reverse connection
            self.mesh.hear(src, t)
            if aodv is not None:
                out.extend(aodv.hello(src, t))
        if aodv is not None:
            if isinstance(msg, (AodvMessage, Routed)):
                sent, delivered = aodv.receive(src, msg, t)
                out.extend(sent)
                for orig, payload in delivered:  # a multi-hop unicast for this robot
                    out.extend(self._handle(orig, None, payload, t))
                return out
            if type(msg) in UNICASTS:
                aodv.delivered_direct()
        out.extend(self._handle(src, src, msg, t))
        return out

    def take_scan(self, src: int, rec: ScanRecord, t: int) -> Out:
        """:meth:`on_message` for a ``SCAN`` carrying one scan this robot has not seen, from
        a robot already in its neighbour table: the flood's common case, which a team of n
        meets n times per scan. The same effects in the same order (accept the key, map
        the scan, relay it to the other neighbours, ask for a hole in its origin's seqs)
        without the general path's dispatch; the caller checks the two conditions."""
        asks = self.accept_scan(rec, t)
        fan = self.mesh.fanout(src)
        out: Out = [(fan, ScanMsg(self.id, (rec,)))] if len(fan) else []
        out.extend(asks)
        return out

    def accept_scan(self, rec: ScanRecord, t: int) -> Out:
        """:meth:`take_scan` without the relay: accept the key, map the scan, and return the
        ``NEED_MAP`` for a hole in its origin's seqs, if any. The simulator's flood calls it
        and sends the relay (``ScanMsg`` to ``mesh.fanout(src)``) itself, before these
        messages, as :meth:`take_scan` orders them: it knows the relay's receivers as a
        bitmask already, and a relay object per robot per scan was the flood's main cost."""
        self.mesh.first_time(rec.key)
        belief = self.belief
        got = belief.archive.admit(rec)  # belief.integrate, and has_gap read on the way
        if got != HELD:
            belief.grid.apply(rec.local)
        if self.aodv is not None and rec.origin != self.id and (
                got == ADDED_GAP if got != HELD else belief.archive.has_gap(rec.origin)):
            return self._ask_for_gaps((rec,), t)
        return []

    def take_goal(self, src: int, msg: Goal, t: int) -> Out:
        """:meth:`on_message` for a ``GOAL`` from a robot already in the neighbour table (every
        plan sends one to each neighbour): note its position and goal, check for a conflict;
        the same effects as the general path without its dispatch."""
        self.belief.hear_all(src, (msg.x, msg.y), msg.goal, msg.priority, t)
        return self._check_conflict(src, msg.goal, msg.priority, t)

    def _handle(self, sender: int, via: int | None, msg: Message, t: int) -> Out:
        """An application message from ``sender``, received from neighbour ``via`` (None
        when it came over several hops: then its scans are passed on to every neighbour)."""
        out: Out = []
        if isinstance(msg, ScanMsg):  # SCAN and MAP
            seen = self.mesh.seen  # (a MAP mostly repeats scans the flood brought)
            new = tuple(r for r in msg.scans if r.key not in seen and self.mesh.first_time(r.key))
            for r in new:
                self.belief.integrate(r)
            if new:
                out.extend(self._to_neighbours(ScanMsg(self.id, new), but=via))
                if self.aodv is not None:
                    out.extend(self._ask_for_gaps(new, t))
        elif isinstance(msg, NeedMap):
            missing = self.belief.archive.missing_for(msg.have)
            if missing:
                out.extend(self.unicast(sender, MapMsg(self.id, tuple(missing)), t))
        elif isinstance(msg, Goal):
            self.belief.hear_position(sender, (msg.x, msg.y), t)
            self.belief.hear_goal(sender, msg.goal, msg.priority, t)
            out.extend(self._check_conflict(sender, msg.goal, msg.priority, t))
        elif isinstance(msg, ChangeGoal):
            self.belief.hear_goal(sender, msg.goal, msg.priority, t)
            self.beaten_by.add(sender)
            self._request("change_goal")
        return out

    def _ask_for_gaps(self, new: tuple[ScanRecord, ...], t: int) -> Out:
        """``NEED_MAP`` to the origin of scans this archive has a hole in.

        Seqs count each origin's scans from 0, so a robot holding (o, 7) but not (o, 5)
        knows it missed some of o's scans (copies lost to a neighbour that had left the
        range, or a partition) — and o is the one robot sure to hold them. It is usually
        several hops away: AODV finds the route, and o's ``MAP`` comes back along it.
        At most one request per origin per unicast lifetime.
        """
        out: Out = []
        arch = self.belief.archive
        have = None  # the archive's summary, computed once if some origin is asked
        for origin in sorted({r.origin for r in new}):
            if origin == self.id or not arch.has_gap(origin):
                continue
            last = self.asked.get(origin)
            if last is not None and t - last <= self.cfg.unicast_lifetime:
                continue
            self.asked[origin] = t
            self.stats.gap_requests += 1
            if have is None:
                have = arch.summary()
            out.extend(self.unicast(origin, NeedMap(self.id, have), t))
        return out

    def _check_conflict(self, src: int, goal: Cell | None, priority: float, t: int) -> Out:
        if not self.cfg.strategy.priorities or goal is None or self.goal is None:
            return []
        if math.dist(goal, self.goal) > self.cfg.laser_cells:
            return []
        self.stats.conflicts += 1
        mine = float(self.remaining)
        if (priority, src) < (mine, self.id):
            self.beaten_by.add(src)
            self._request("conflict")
            return []
        self.stats.change_goals_sent += 1
        return self.unicast(src, ChangeGoal(self.id, self.goal, mine), t)

    # ---------------------------------------------------------------- motion
    def next_step(self) -> Cell | None:
        """The cell the robot wants to enter this tick, or None (no plan, or path blocked)."""
        if self.path_i >= self.path.shape[0]:
            return None
        if self.hold > 0:  # still planning (plan_pause)
            self.hold -= 1
            return None
        x, y = (int(v) for v in self.path[self.path_i])
        lo = self.belief.grid.logodds
        if lo[y, x] >= 0 or not footprint_clear(lo, y, x, self.cfg.offsets):
            self.path_i = self.path.shape[0]
            self._request("blocked")
            return None
        return x, y

    def moved(self, cell: Cell) -> None:
        """The motors took the step (odometry: the robot knows where it is)."""
        self.belief.pos = (int(cell[0]), int(cell[1]))
        self.path_i += 1
        self.stats.moves += 1
        if self.path_i >= self.path.shape[0] and self.goal is not None:
            self._request("reached")

    # -------------------------------------------------------------- planning
    def _timer(self, t: int) -> bool:
        p = self.plan_phase
        return t == 0 or (t >= p and (t - p) % self.cfg.plan_period == 0)

    def plan_due(self, t: int) -> bool:
        return self.last_plan_t != t and (self._timer(t) or self.request is not None)

    def maybe_plan(self, t: int) -> Out:
        """Plan on the timer or on a pending request (at most once per tick)."""
        if self.goal_region is not None and not self._any_frontier(*self.goal_region):
            self.goal_region = None  # (only with ``replan_when_seen``)
            self._request("seen")
        if not self.plan_due(t):
            return []
        reason = None if self._timer(t) else self.request
        self.request = None
        self.last_plan_t = t
        return self.plan(t, reason)

    def plan(self, t: int, reason: str | None = None) -> Out:
        """Choose a goal and a path on the current map; announce it to the neighbours."""
        cfg = self.cfg
        grid = self.belief.grid
        trav = grid.derived(("traversable", cfg.radius_cells), self._traversable)
        x, y = self.pos
        fr = grid.derived(("frontiers", cfg.min_region), self._frontiers)
        nearest_of = cfg.strategy.candidates
        if nearest_of is None:  # the strategy may read any distance: the whole field
            dist = distance_steps(trav, x, y)
            d = dist[fr.ys, fr.xs]
            eligible = (d > 0) & trav[fr.ys, fr.xs]
        else:  # which cells are reachable from the map's pieces (shared per map state)
            lab = grid.derived(("pieces", cfg.radius_cells), lambda _lo: labels4(trav))
            pieces = reachable_pieces(trav, lab, x, y)
            eligible = trav[fr.ys, fr.xs] & np.isin(lab[fr.ys, fr.xs], pieces)
            eligible &= (fr.xs != x) | (fr.ys != y)
            d = np.empty(0, dtype=np.int32)  # set below, once the candidates are known
        reach = np.zeros(fr.n_regions, dtype=bool)
        reach[fr.region[eligible]] = True
        self.stats.blacklisted_regions = int(fr.n_regions - reach.sum())
        fields: dict[Cell, np.ndarray] = {}

        def field_from(c: Cell) -> np.ndarray:
            if c not in fields:
                fields[c] = distance_steps(trav, *c)
            return fields[c]

        ctx = GoalContext(
            me=self.id,
            pos=(x, y),
            frontiers=fr,
            eligible=eligible,
            dist=d,
            laser_cells=cfg.laser_cells,
            team_goals=self.belief.team_goals(t, cfg.goal_ttl) if cfg.strategy.exclusion else {},
            team_pos=(
                self.belief.team_positions(t, cfg.neighbour_timeout)
                if cfg.strategy.needs_rivals
                else {}
            ),
            current_goal=self.goal,
            field_from=field_from,
            winners=self._winners(t),
        )
        self._what_it_knows(ctx, t)
        self.beaten_by.clear()
        tp: np.ndarray | None = None
        if nearest_of is None:
            goal = cfg.strategy.choose(ctx) if eligible.any() else None
        else:
            goal = None
            cand = nearest_of(ctx) if eligible.any() else np.empty(0, dtype=np.int64)
            pad: np.ndarray = grid.derived(("traversable_padded", cfg.radius_cells),
                                           lambda _lo: padded(trav))
            if cand.size:
                tp = pad
            if 0 < cand.size <= min(FIELDS_UP_TO, grid.sharers):
                # few candidates (the end of a run): fields from them, shared by every
                # robot whose map is in this state, then a search along shortest paths only
                # (a field per candidate pays when at least as many robots share the map;
                # it also bounds the fields kept to about one per robot)
                d = np.full(fr.n_cells, FAR, dtype=np.int64)
                got: dict[int, np.ndarray] = {}
                for i in cand.tolist():
                    c = (int(fr.xs[i]), int(fr.ys[i]))

                    def from_c(_lo: np.ndarray, c: Cell = c) -> np.ndarray:
                        return field_padded(pad, *c)

                    got[i] = grid.derived(("field", cfg.radius_cells, c), from_c)
                    d[i] = steps_via_field(pad, got[i], x, y)
                ctx.dist = d
                goal = nearest_candidate(ctx, cand)
                if goal is not None:
                    gi = int(cand[(fr.xs[cand] == goal[0]) & (fr.ys[cand] == goal[1])][0])
                    dist = distance_toward(pad, x, y, got[gi], int(d[gi]))
            elif cand.size:
                # the goal is the nearest candidate: search only as far as the first one
                dist = distance_until(pad, x, y, fr.xs[cand], fr.ys[cand])
                d = dist[fr.ys + 1, fr.xs + 1]
                d[d < 0] = FAR  # reachable (eligible) but beyond the nearest candidate
                ctx.dist = d
                goal = nearest_candidate(ctx, cand)
        had_goal = self.goal is not None
        was_finished = self.finished
        self.goal = goal
        self.goal_region = None
        if cfg.strategy.replan_when_seen and goal is not None:
            at = np.nonzero((fr.xs == goal[0]) & (fr.ys == goal[1]))[0]
            if at.size:
                mine = fr.region == fr.region[at[0]]
                self.goal_region = (fr.ys[mine], fr.xs[mine])
        if goal is None:
            self.path = np.empty((0, 2), dtype=np.int64)
            self.path_i = 0
            if not was_finished:
                self.stats.finished_at = t
                self._record_plan(t, reason)
            if had_goal and cfg.strategy.exclusion:
                return self._to_neighbours(Goal(self.id, None, 0.0, x, y))
            return []
        self.stats.finished_at = None
        if tp is None:
            self.path = path_to(dist, trav, goal[0], goal[1], x, y)
        else:
            self.path = path_to_padded(dist, tp, goal[0], goal[1], x, y)
        self.path_i = 0
        self._record_plan(t, reason)
        self.hold = cfg.plan_pause
        if not cfg.strategy.exclusion:
            return []
        return self._to_neighbours(Goal(self.id, goal, float(self.remaining), x, y))

    def _any_frontier(self, ys: np.ndarray, xs: np.ndarray) -> bool:
        """Whether any of these (known free) cells still has an unknown 4-neighbour."""
        lo = self.belief.grid.logodds
        h, w = lo.shape
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            if (lo[np.clip(ys + dy, 0, h - 1), np.clip(xs + dx, 0, w - 1)] == 0).any():
                return True
        return False

    def _what_it_knows(self, ctx: GoalContext, t: int) -> None:
        """The context's map cache, start, team size (from the ids it has heard) and the
        ticks it has been alone (0 if it has stood at its start since its last contact)."""
        ctx.derived = self.belief.grid.derived
        ctx.start = self.start
        for rid, h in self.belief.heard.items():
            self.team_size = max(self.team_size, rid + 1)
            if h.pos[0] >= 0:
                self.last_contact = max(self.last_contact, h.t)
        if self.pos == self.start:
            self.rendezvous_for = self.last_contact
        ctx.team_size = self.team_size
        ctx.alone = t - self.last_contact if self.last_contact > self.rendezvous_for else 0

    def _traversable(self, lo: np.ndarray) -> np.ndarray:
        """Known-free cells whose footprint touches no known obstacle nor the map's edge."""
        trav = lo < 0
        trav &= ~inflate(lo, self.cfg.offsets)
        return trav

    def _frontiers(self, lo: np.ndarray) -> Frontiers:
        return frontiers_of_logodds(lo, self.cfg.min_region)

    def _winners(self, t: int) -> dict[int, Cell]:
        """Goals of the robots that beat this one since its last plan, when it yields.

        With ``conflict_yield`` a robot that lost a conflict must leave the winner's zone:
        the thesis's loser "starts the unscheduled re-planning" so that the robots
        "negotiate the rescheduling of their goals" (§3.3.4, §4.2). Without it the
        re-plan follows the "prefers" fallback like any other plan, and when every
        candidate is in some zone that is plain greedy — usually the goal it just had.
        """
        if not self.cfg.conflict_yield or not self.beaten_by:
            return {}
        goals = self.belief.team_goals(t, self.cfg.goal_ttl)
        return {r: goals[r] for r in sorted(self.beaten_by) if r in goals}

    def _record_plan(self, t: int, reason: str | None) -> None:
        s = self.stats
        s.plan_ticks.append(t)
        s.plans += 1
        if reason is not None:
            s.replans += 1
            s.reasons[reason] = s.reasons.get(reason, 0) + 1
