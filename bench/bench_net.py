"""Networked traversal: message rate, bytes per agent per second, makespan against the simulator.

Runs ``swarmex serve`` and agent processes (``--count`` agents per process) on 127.0.0.1 for
each team size, and the simulator on the same mission and seed, then prints one row per team
size:

* the makespan of both and whether they are equal (the protocol of
  :mod:`swarmex.net.traversal` computes mission times, so the expected timing noise is 0 s;
  the real-time execution's lag — how late events ran against the scaled clock — is printed
  beside it, in mission seconds);
* MADGTA broadcasts per mission second, and the frames and bytes per agent per second that
  cross the network: agent → server (what one UAV transmits) and server → agent (what it
  receives: every relayed broadcast), per *mission* second (the protocol's own load, what a
  real UAV's Wi-Fi would carry) and per *wall* second at the chosen time scale.

Usage: ``python bench/bench_net.py [--agents 10,50] [--grid 20x20] [--time-scale 0.02]
[--per-process 10] [--seed 1] [--no-done-lists]``. Every process is killed if it outlives its run.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import _cli


def run_network(grid: str, agents: int, scale: float, per_process: int, seed: int,
                out: Path, timeout: float, done_lists: bool = True) -> tuple[dict, float]:
    py = [sys.executable, "-m", "swarmex"]
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    procs: list[subprocess.Popen] = []
    try:
        server = subprocess.Popen(
            [*py, "serve", "--grid", grid, "--agents", str(agents), "--seed", str(seed),
             "--port", "0", "--time-scale", str(scale), "--timeout", str(timeout),
             "--dead-after", "10", "--json", str(out),
             "--done-lists" if done_lists else "--no-done-lists"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
        procs.append(server)
        assert server.stdout is not None
        address = None
        for line in server.stdout:
            m = re.search(r"listening on (tcp://\S+)", line)
            if m:
                address = m[1]
                break
        if address is None:
            raise RuntimeError("the server did not start")
        left = agents
        while left > 0:
            k = min(per_process, left)
            procs.append(subprocess.Popen(
                [*py, "agent", "--connect", address, "--count", str(k),
                 "--server-timeout", "30"],
                stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT, env=env))
            left -= k
        t0 = time.monotonic()
        for _ in server.stdout:
            pass
        code = server.wait(timeout)
        wall = time.monotonic() - t0
        for p in procs[1:]:
            p.wait(30)
        if code != 0:
            raise RuntimeError(f"server exit {code}")
        return json.loads(out.read_text()), wall
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait(5)


def simulate(grid: str, agents: int, seed: int) -> dict:
    import swarmex

    return swarmex.run("traversal", grid=grid, agents=agents, seed=seed).to_dict()


def mesh_rows(size: str, robots: int, scale: float, seed: int) -> list[dict]:
    """Exploration as processes against the simulator on the same scenario (one run each:
    the process run is asynchronous, so its steps differ run to run)."""
    from swarmex.missions.exploration import ExplorationParams, run_exploration
    from swarmex.missions.exploration.record import exploration_record
    from swarmex.net.mesh import run_processes
    from swarmex.net.mesh_scenario import MeshOptions
    from swarmex.worlds.metric import empty_metric, parse_size

    grid = empty_metric(*parse_size(size))
    params = ExplorationParams(robots=robots, laser_range=1.5, comm_range=10.0, seed=seed)
    sim = exploration_record(run_exploration(grid, params)).to_dict()
    net = run_processes(grid, params, MeshOptions(time_scale=scale, timeout=600),
                        say=lambda _s: None)
    rows = []
    for name, rec in (("simulated", sim), ("processes", net)):
        m = rec["metrics"]
        mission_s = max(1.0, rec["makespan"]) * 0.1
        rows.append({
            "run": name, "complete": rec["complete"], "steps": rec["makespan"],
            "mean_steps": m["mean_steps"], "explored": m["explored_fraction"],
            "messages_per_robot_per_s": m["messages_sent"] / robots / mission_s,
            "bytes_per_robot_per_s": m["bytes_sent"] / robots / mission_s,
            "wall_s": rec["wall_seconds"],
        })
    return rows


def main() -> None:
    ap = _cli.Parser(description=__doc__.split("\n")[0])
    ap.add_argument("--agents", type=_cli.int_list, default=[10, 50])
    ap.add_argument("--grid", type=_cli.sizes(2, "WxH"), default=(20, 20))
    ap.add_argument("--time-scale", type=_cli.positive_float, default=0.02)
    ap.add_argument("--per-process", type=_cli.positive_int, default=10)
    ap.add_argument("--seed", type=_cli.nonneg_int, default=1)
    ap.add_argument("--timeout", type=_cli.positive_float, default=900.0)
    ap.add_argument("--mesh", type=_cli.sizes(3, "WxHxROBOTS"), default=None,
                    help="Also run exploration as processes: WxHxROBOTS, e.g. 5x5x5.")
    ap.add_argument("--no-done-lists", action="store_true",
                    help="Leave Fig. 4.17's done-nodes list out of the broadcasts.")
    args = ap.parse_args()
    grid = "x".join(map(str, args.grid))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.agents:
            sim = simulate(grid, n, args.seed)
            rec, wall = run_network(grid, n, args.time_scale, args.per_process,
                                    args.seed, Path(tmp) / f"net{n}.json", args.timeout,
                                    not args.no_done_lists)
            net = rec["network"]
            mission_s = rec["metrics"]["mission_end"] or rec["makespan"]
            mission_wall = net["mission_wall_seconds"]
            peers = net["peers"]
            up = np.mean([p["bytes_in"] for p in peers])  # agent → server, per agent
            down = np.mean([p["bytes_out"] for p in peers])  # server → agent
            up_f = np.mean([p["frames_in"] for p in peers])
            down_f = np.mean([p["frames_out"] for p in peers])
            same_paths = all(a["trajectory"] == b["trajectory"]
                             for a, b in zip(rec["agents"], sim["agents"], strict=True))
            rows.append({
                "agents": n, "makespan_sim": sim["makespan"], "makespan_net": rec["makespan"],
                "equal": rec["makespan"] == sim["makespan"] and same_paths,
                "lag_max": net["lag_max"], "lag_mean": net["lag_mean"],
                "broadcasts": net["broadcasts_relayed"],
                "broadcasts_per_mission_s": net["broadcasts_relayed"] / mission_s,
                "up_B_per_agent_mission_s": up / mission_s,
                "down_B_per_agent_mission_s": down / mission_s,
                "up_frames_per_agent_mission_s": up_f / mission_s,
                "down_frames_per_agent_mission_s": down_f / mission_s,
                "up_B_per_agent_wall_s": up / mission_wall,
                "down_B_per_agent_wall_s": down / mission_wall,
                "frames_per_wall_s_server": (net["frames_in"] + net["frames_out"]) / mission_wall,
                "mission_wall_s": mission_wall, "total_wall_s": wall,
                "dropped": net["dropped_checksum"] + net["dropped_encoding"],
            })
    print(f"done-nodes lists {'off' if args.no_done_lists else 'on'}; "
          f"grid {grid}, time scale {args.time_scale} wall s per mission s, seed "
          f"{args.seed}, {args.per_process} agents per process, load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    head = ("agents", "makespan sim/net (s)", "equal", "lag max/mean (mission s)",
            "bcast/mission-s", "B/agent/mission-s up/down", "frames/agent/mission-s up/down",
            "B/agent/wall-s up/down", "server frames/wall-s", "mission wall s")
    print(" | ".join(head))
    for r in rows:
        lag = ("n/a" if r["lag_max"] is None
               else f"{r['lag_max']:.2f}/{r['lag_mean']:.3f}")
        print(" | ".join([
            str(r["agents"]),
            f"{r['makespan_sim']:.2f}/{r['makespan_net']:.2f}",
            "yes" if r["equal"] else "NO",
            lag,
            f"{r['broadcasts_per_mission_s']:.2f}",
            f"{r['up_B_per_agent_mission_s']:.0f}/{r['down_B_per_agent_mission_s']:.0f}",
            f"{r['up_frames_per_agent_mission_s']:.2f}/"
            f"{r['down_frames_per_agent_mission_s']:.2f}",
            f"{r['up_B_per_agent_wall_s']:.0f}/{r['down_B_per_agent_wall_s']:.0f}",
            f"{r['frames_per_wall_s_server']:.0f}",
            f"{r['mission_wall_s']:.1f}",
        ]))
    for r in rows:
        print(f"ratio makespan net/sim at {r['agents']} agents: "
              f"{r['makespan_net'] / r['makespan_sim']:.6f} (reference 1.000000)")
    print(json.dumps(rows))
    if args.mesh:
        w, h, k = args.mesh
        scale = 0.3
        mrows = mesh_rows(f"{w}x{h}", int(k), scale, args.seed)
        print(f"exploration {w}x{h} m, {k} robots, laser 1.5 m, radio 10 m, time scale {scale}")
        print("run | complete | steps | mean robot steps | explored | messages/robot/s | "
              "bytes/robot/s | wall s")
        for r in mrows:
            print(f"{r['run']} | {r['complete']} | {r['steps']:.0f} | {r['mean_steps']:.1f} | "
                  f"{r['explored']:.4f} | {r['messages_per_robot_per_s']:.1f} | "
                  f"{r['bytes_per_robot_per_s']:.0f} | {r['wall_s']:.1f}")
        print(f"ratio steps processes/simulated: {mrows[1]['steps'] / mrows[0]['steps']:.3f}"
              " (reference 1; asynchronous processes differ run to run)")


if __name__ == "__main__":
    _cli.run(main)
