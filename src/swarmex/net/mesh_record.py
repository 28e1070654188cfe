"""The mesh run's result record: the display's view and the robots' reports, assembled.

The record has the schema of ``swarmex explore`` (so the same tools read both), plus what
only a process run measures (traffic by node, send timeouts, robots lost). Assembly is a pure
function of the display's state (:class:`RecordSource`), apart from the sockets and the
clock of :mod:`swarmex.net.mesh_display`, so it can be read and changed on its own.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from swarmex.comm.aodv import CONTROL_KINDS
from swarmex.net.routing import unicast_counts

if TYPE_CHECKING:
    from swarmex.comm.aodv import AodvNode
    from swarmex.missions.exploration.belief import ExplorationBelief
    from swarmex.missions.exploration.params import Cell, ExplorationParams
    from swarmex.net.mesh_node import Traffic
    from swarmex.net.mesh_scenario import MeshOptions
    from swarmex.worlds.metric import MetricGrid


def _by_origin(scans: dict) -> dict[str, int]:
    """How many archived scans came from each robot (who heard whom, through any hops)."""
    out: dict[str, int] = {}
    for origin, _seq in scans:
        out[str(origin)] = out.get(str(origin), 0) + 1
    return dict(sorted(out.items()))


class RecordSource(Protocol):
    """What the record is assembled from: the display process's state at the end of a run
    (a protocol, so that this module does not import the display's sockets)."""

    @property
    def params(self) -> ExplorationParams: ...
    @property
    def grid(self) -> MetricGrid: ...
    @property
    def options(self) -> MeshOptions: ...
    @property
    def starts(self) -> tuple[Cell, ...]: ...
    @property
    def reachable(self) -> np.ndarray: ...
    @property
    def robots(self) -> dict[int, dict[str, Any]]: ...
    @property
    def reports(self) -> dict[int, dict]: ...
    @property
    def multihop_in(self) -> dict[str, int]: ...
    @property
    def aodv(self) -> AodvNode | None: ...
    @property
    def belief(self) -> ExplorationBelief: ...
    @property
    def traffic(self) -> Traffic: ...


def build_record(display: RecordSource, wall: float, ended: bool) -> dict[str, Any]:
    """The mesh run's record (the schema of ``swarmex explore``) from the display's
    state and the robots' REPORTs; a robot whose report is malformed counts as not
    reported."""
    from swarmex import __version__
    from swarmex.engine.record import plain
    from swarmex.missions.exploration.params import TICK_SECONDS
    from swarmex.missions.exploration.record import average_robot, intervals

    params = display.params
    reach = display.reachable
    n_reach = max(1, int(reach.sum()))
    team_free = np.zeros(display.grid.shape, dtype=bool)
    agents = []
    totals: dict[str, Any] = {"moves": 0, "plans": 0, "replans": 0, "conflicts": 0,
                              "change_goals_sent": 0, "blacklisted_regions": 0}
    reasons: dict[str, int] = {}
    by_kind: dict[str, list[int]] = {}
    harness_by_kind: dict[str, list[int]] = {}
    unicasts = unicast_counts(None, 0)
    multihop_in = dict(display.multihop_in)
    sent = sent_bytes = lost = harness = harness_bytes = frames = frame_bytes = 0
    steps = []
    plan_series = []
    for rid in range(params.robots):
        info = display.robots.get(rid, {"trajectory": [], "alive": False, "t": 0})
        rep = display.reports.get(rid)
        metrics: dict[str, Any] = {"alive": bool(info.get("alive")),
                                   "reported": rep is not None}
        traj = info["trajectory"] or [[0, *display.starts[rid]]]
        if rep is not None:
            try:
                free = np.unpackbits(np.frombuffer(rep["free"], np.uint8),
                                     count=reach.size).astype(bool).reshape(reach.shape)
                team_free |= free
                tr = rep["traffic"]
                metrics.update({k: rep[k] for k in (
                    "steps", "moves", "plans", "replans", "replan_reasons", "scans",
                    "archive", "conflicts", "change_goals_sent", "blacklisted_regions")})
                metrics["plan_intervals"] = intervals(rep["plan_ticks"])
                metrics["scans_by_origin"] = rep.get("scans_by_origin", {})
                # the simulator's count (mesh_node.Traffic): the radio's messages only
                metrics["messages_sent"] = tr["messages_out"]
                metrics["bytes_sent"] = tr["message_bytes_out"]
                metrics["explored_fraction_own"] = float((free & reach).sum()) / n_reach
                metrics["traffic"] = tr
                metrics["unicasts"] = rep["unicasts"]
                metrics["multihop_in"] = rep["multihop_in"]
                metrics["link_refusals"] = int(rep["link_refusals"])
                for k, v in rep["unicasts"].items():
                    unicasts[k] += int(v)
                for k, v in rep["multihop_in"].items():
                    multihop_in[k] = multihop_in.get(k, 0) + int(v)
                traj = rep["trajectory"]
                steps.append(int(rep["steps"]))
                plan_series.append(metrics["plan_intervals"])
                for k in totals:
                    totals[k] += int(rep[k])
                for k, v in rep["replan_reasons"].items():
                    reasons[k] = reasons.get(k, 0) + int(v)
                sent += tr["messages_out"]
                sent_bytes += tr["message_bytes_out"]
                harness += tr["harness_out"]
                harness_bytes += tr["harness_bytes_out"]
                frames += tr["frames_out"]
                frame_bytes += tr["bytes_out"]
                lost += tr["send_timeouts"] + tr["out_of_range"] + tr["lost_injected"]
                for table, acc_table in ((tr["by_kind"], by_kind),
                                         (tr["harness_by_kind"], harness_by_kind)):
                    for k, row in table.items():
                        acc = acc_table.setdefault(k, [0, 0])
                        acc[0] += row["messages"]
                        acc[1] += row["bytes"]
            except (KeyError, TypeError, ValueError, OverflowError, IndexError):
                # (the display keeps only reports that passed report_fields: a last guard)
                metrics["reported"] = False
        agents.append({"id": rid, "metrics": metrics,
                       "trajectory": [[int(t), int(x), int(y)] for t, x, y in traj],
                       "jobs": []})
    explored = float((team_free & reach).sum()) / n_reach
    live = [i for i in display.robots.values() if i.get("alive")]
    complete = ended and bool(live) and all(i["finished"] for i in live)
    makespan = max(steps) if steps else 0
    p = params.as_dict()
    p["starts"] = [list(s) for s in display.starts]
    p["cell"] = display.grid.cell
    p["processes"] = display.options.to_wire()
    record = {
        "swarmex_version": __version__,
        "mission": "exploration",
        "algorithm": params.strategy,
        "params": p,
        "seed": params.seed,
        "world": display.grid.describe(),
        "complete": complete,
        "makespan": float(makespan),
        "time_unit": "step",
        "metrics": {
            "explored_fraction": explored,
            "reachable_free_cells": int(reach.sum()),
            "steps": steps,
            "mean_steps": float(np.mean(steps)) if steps else None,
            "makespan_seconds": makespan * TICK_SECONDS,
            **totals,
            "replan_reasons": dict(sorted(reasons.items())),
            # the radio's messages as the simulator counts them (a broadcast once, a
            # unicast or relay per copy, each message's own size: mesh_node.Traffic)
            "messages_sent": sent,
            "bytes_sent": sent_bytes,
            "messages_lost": lost,
            "messages_by_kind": {k: {"messages": m, "bytes": b}
                                 for k, (m, b) in sorted(by_kind.items())},
            # what the simulator does not have: the robots' control link (HELLO, STATUS)
            # and NACKs, and every frame their sockets carried (radio copies included)
            "harness_messages": harness,
            "harness_bytes": harness_bytes,
            "harness_by_kind": {k: {"messages": m, "bytes": b}
                                for k, (m, b) in sorted(harness_by_kind.items())},
            "frames_sent": frames,
            "frame_bytes_sent": frame_bytes,
            "aodv_messages": sum(by_kind[k][0] for k in CONTROL_KINDS if k in by_kind),
            "aodv_bytes": sum(by_kind[k][1] for k in CONTROL_KINDS if k in by_kind),
            # the robots' AODV statistics, summed (as the simulator's record), and what
            # the receivers saw arrive in routed envelopes (robots and display, by kind)
            "unicasts": unicasts,
            "multihop_in_by_kind": dict(sorted(multihop_in.items())),
            "display_unicasts": unicast_counts(display.aodv, 0),
            "plan_intervals_avg": average_robot(plan_series),
            "finished_robots": int(sum(1 for i in live if i["finished"])),
            "robots_lost": int(sum(1 for i in display.robots.values() if not i["alive"])),
            "display_scans_by_origin": _by_origin(display.belief.archive.scans),
            "display_map_fraction": float(
                ((display.belief.grid.logodds < 0) & reach).sum()) / n_reach,
            "display_traffic": display.traffic.to_dict(),
        },
        "agents": agents,
        "wall_seconds": wall,
        "tick_seconds": TICK_SECONDS,
    }
    return plain(record)
