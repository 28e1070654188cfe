"""How each mission's cost grows with the swarm and the map (issue 14 item 5).

For every mission, 4 sizes; each case runs in its own process (so its peak memory is its
own: ``ru_maxrss`` of the child) after a small warm-up run in that process (so numba's
compile or cache load is not counted). Printed per case: wall and CPU seconds, peak memory,
agent-steps and CPU per agent-step; per mission the fitted exponent of CPU time against size
(slope of the log-log line) and of the per-agent-step cost. An exponent near 1 for the
total means near-linear growth; a per-agent-step exponent near 0 means each agent-step costs
the same whatever the size.

Sizes (``size`` column):

* traversal — MADGTA, 8 agents, empty grids of 32² … 256² cells: size = cells;
* exploration — 20 × 20 m at 5 cm, laser 2 m, radio 10 m, 5 … 40 robots: size = robots;
  ``--large`` adds issue 14's 100 robots on 40 × 40 m at 5 cm (size ``100x40``: robots x
  side in metres), a row of its own, left out of the fitted exponents (another map);
* foraging — Strips, Relay-Food, 100 units, g × g grid with N robots, (128, 16) …
  (1024, 1024): size = robots (the grid grows with them, g² / N = 1024 … 1024 cells each);
* roadmap — WMA-RRT coverage, 32 agents, a 2000 × 2000 world with 9 square obstacles,
  ε = 10, range 15, 2,500 … 20,000 nodes: size = nodes.

``--quick`` runs the three smallest sizes of each (a minute or two); the full table takes
several minutes (the machine is shared: CPU time is the measure, wall time is shown too).
``--write`` puts the table into bench/README.md (between the ``bench_scale`` markers) and the
log-log plot into bench/scale.png.

    .venv/bin/python bench/bench_scale.py            # the full table
    .venv/bin/python bench/bench_scale.py --quick --missions traversal,roadmap
    .venv/bin/python bench/bench_scale.py --missions foraging --sizes 256x64,1024x1024
    .venv/bin/python bench/bench_scale.py --missions exploration --large --timeout 3600
    .venv/bin/python bench/bench_scale.py --write
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

import _cli

HERE = Path(__file__).resolve().parent
MISSIONS = ("traversal", "exploration", "foraging", "roadmap")
SIZES: dict[str, list[Any]] = {
    "traversal": [32, 64, 128, 256],
    "exploration": [5, 10, 20, 40],
    "foraging": [(128, 16), (256, 64), (512, 256), (1024, 1024)],
    "roadmap": [2500, 5000, 10000, 20000],
}
# rows on a map of their own (``--large``): shown, not fitted
LARGE: dict[str, list[Any]] = {"exploration": [(100, 40)]}
MARK_BEGIN, MARK_END = "<!-- bench_scale:begin -->", "<!-- bench_scale:end -->"
# issue 14's goals on rows of this table: (mission, size label) -> (CPU s, peak MB or None)
TARGETS: dict[tuple[str, str], tuple[float, float | None]] = {
    ("traversal", "256"): (4.0, None),
    ("exploration", "10"): (3.0, None),
    ("exploration", "40"): (12.0, None),
    ("exploration", "100 on 40x40 m"): (90.0, 4096.0),
}


def roadmap_env(path: Path) -> Path:
    """An open 2000 × 2000 world with a 3 × 3 lattice of 100-unit square obstacles (the
    lower-left corner, where the team starts, left clear)."""
    obstacles = [[[x, y], [x + 100, y], [x + 100, y + 100], [x, y + 100]]
                 for x in range(700, 2000, 450) for y in range(700, 2000, 450)]
    path.write_text(json.dumps({"bounds": [0, 0, 2000, 2000], "obstacles": obstacles}))
    return path


def case_params(mission: str, size: Any, tmp: Path) -> tuple[dict[str, Any], float]:
    """(the swarmex.run keywords of one case, its size on the x axis)."""
    if mission == "traversal":
        return {"grid": f"{size}x{size}", "agents": 8}, float(size * size)
    if mission == "exploration":
        n, side = size if isinstance(size, tuple) else (size, 20)
        return {"empty": f"{side}x{side}", "cell": 0.05, "robots": n, "laser_range": 2.0,
                "comm_range": 10.0}, float(n)
    if mission == "foraging":
        g, n = size
        return {"grid": g, "agents": n, "algorithm": "strips"}, float(n)
    return {"env": str(roadmap_env(tmp / "scale_env.json")), "agents": 32, "nodes": size,
            "step": 10.0, "sensor_range": 15.0}, float(size)


WARMUP = {
    "traversal": {"grid": "16x16", "agents": 2},
    "exploration": {"empty": "3x3", "robots": 2, "laser_range": 0.8},
    "foraging": {"grid": 16, "agents": 4, "algorithm": "strips"},
    "roadmap": None,  # filled with the case's own env, few nodes
}


def agent_steps(mission: str, record: Any) -> int:
    """The run's agent-steps: what one agent does in one unit of the mission's clock."""
    m = record.metrics
    if mission == "traversal":  # an agent-step is a move or a job
        return int(sum((a.metrics.get("nodes_traveled") or 0) + (a.metrics.get("nodes_done") or 0)
                       for a in record.agents))
    if mission == "exploration":
        return int(sum(m["steps"])) if isinstance(m.get("steps"), list) else int(
            m["mean_steps"] * len(record.agents))
    return int(len(record.agents) * float(record.makespan))


def label(mission: str, size: Any) -> str:
    """The size column: a large exploration case names its map."""
    if mission == "exploration" and isinstance(size, tuple):
        return f"{size[0]} on {size[1]}x{size[1]} m"
    return str(size)


def child(mission: str, size_json: str, tmp: str) -> None:
    """One case in this process: warm up, run, print a JSON line."""
    import resource

    import swarmex

    size = json.loads(size_json)
    size = tuple(size) if isinstance(size, list) else size
    kw, x = case_params(mission, size, Path(tmp))
    warm = WARMUP[mission] or {**kw, "nodes": 50}
    swarmex.run(mission, trace=False, **warm)
    w0, c0 = time.perf_counter(), time.process_time()
    rec = swarmex.run(mission, trace=False, **kw)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    print(json.dumps({
        "mission": mission, "size": x, "label": label(mission, size), "wall": wall, "cpu": cpu,
        "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "agent_steps": agent_steps(mission, rec), "complete": bool(rec.complete),
        "large": isinstance(size, tuple) and mission == "exploration",
    }))


def run_case(mission: str, size: Any, tmp: Path, timeout: float) -> dict[str, Any] | None:
    size_json = json.dumps(list(size) if isinstance(size, tuple) else size)
    try:
        proc = subprocess.run(
            [sys.executable, __file__, "--child", mission, size_json, str(tmp)],
            capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        print(f"  {mission} {size}: over {timeout:.0f} s, skipped", file=sys.stderr)
        return None
    if proc.returncode != 0:
        print(f"  {mission} {size}: failed\n{proc.stderr[-800:]}", file=sys.stderr)
        return None
    return json.loads(proc.stdout.strip().splitlines()[-1])


def parse_sizes(mission: str, text: str) -> list[Any]:
    """``--sizes`` as the case sizes of ``mission``: integers, or ``GxN`` pairs for foraging
    (whose size is a grid side and a robot count)."""
    out: list[Any] = []
    for part in (p.strip() for p in text.split(",") if p.strip()):
        if mission == "foraging":
            g, sep, n = part.partition("x")
            if not sep:
                raise ValueError(f"foraging sizes are GRIDxROBOTS, got {part!r}")
            out.append((int(g), int(n)))
        elif mission == "exploration" and "x" in part:  # ROBOTSxSIDE (metres)
            n, _, side = part.partition("x")
            out.append((int(n), int(side)))
        else:
            out.append(int(part))
    if not out or any(v <= 0 for s in out for v in (s if isinstance(s, tuple) else (s,))):
        raise ValueError("give positive sizes, e.g. 64,128")
    return out


def exponent(xs: list[float], ys: list[float]) -> float:
    """Slope of log(y) against log(x): the power of the growth."""
    if len(xs) < 2:
        return float("nan")
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0])


def table(rows: list[dict[str, Any]]) -> list[str]:
    out = ["| mission | size | x | wall s | CPU s | peak MB | agent-steps | µs CPU / agent-step |",
           "|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        per = 1e6 * r["cpu"] / max(r["agent_steps"], 1)
        out.append(f"| {r['mission']} | {r['label']} | {r['size']:g} | {r['wall']:.2f} | "
                   f"{r['cpu']:.2f} | {r['rss_mb']:.0f} | {r['agent_steps']:,} | {per:.1f} |")
    out += ["", "| mission | exponent of CPU vs size | exponent of CPU per agent-step |",
            "|---|---:|---:|"]
    for mission in MISSIONS:
        rs = [r for r in rows if r["mission"] == mission and not r.get("large")]
        if len(rs) < 2:
            continue
        xs = [r["size"] for r in rs]
        total = exponent(xs, [max(r["cpu"], 1e-6) for r in rs])
        per = exponent(xs, [max(r["cpu"], 1e-6) / max(r["agent_steps"], 1) for r in rs])
        out.append(f"| {mission} | {total:.2f} | {per:+.2f} |")
    return out


def target_lines(rows: list[dict[str, Any]]) -> list[str]:
    """Each goal a row of this run meets or misses, with the ratio measured / goal (below 1:
    met), so the figure is judged in the same run that measured it."""
    out = []
    for r in rows:
        goal = TARGETS.get((r["mission"], r["label"]))
        if goal is None:
            continue
        seconds, mb = goal
        ratio = r["cpu"] / seconds
        line = (f"ratio {r['mission']} {r['label']}: {r['cpu']:.2f} s CPU / {seconds:g} s goal"
                f" = {ratio:.2f}")
        if mb is not None:
            line += f"; {r['rss_mb']:.0f} MB / {mb:g} MB goal = {r['rss_mb'] / mb:.2f}"
            ratio = max(ratio, r["rss_mb"] / mb)
        out.append(line + (" (met)" if ratio <= 1 else " (MISSED)"))
    return out


def plot(rows: list[dict[str, Any]], path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.5), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(111)
    for mission in MISSIONS:
        rs = [r for r in rows if r["mission"] == mission and not r.get("large")]
        if rs:
            xs = np.array([r["size"] for r in rs]) / rs[0]["size"]
            ax.loglog(xs, [1e6 * r["cpu"] / max(r["agent_steps"], 1) for r in rs], "o-",
                      label=mission)
    ax.set_xlabel("size / smallest size (cells, robots or nodes: see bench_scale.py)")
    ax.set_ylabel("µs CPU per agent-step")
    ax.set_title("Cost per agent-step as the swarm and the map grow")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.savefig(path)


def write_readme(lines: list[str]) -> None:
    readme = HERE / "README.md"
    text = readme.read_text()
    block = "\n".join([MARK_BEGIN, *lines, "", "![scale](scale.png)", MARK_END])
    if MARK_BEGIN in text:
        head, rest = text.split(MARK_BEGIN, 1)
        text = head + block + rest.split(MARK_END, 1)[1]
    else:
        text = text.rstrip() + "\n\n## Scale (`bench_scale.py`)\n\n" + block + "\n"
    readme.write_text(text)


def main(argv: list[str] | None = None) -> int:
    ap = _cli.Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the three smallest sizes")
    ap.add_argument("--missions", default=",".join(MISSIONS))
    ap.add_argument("--timeout", type=_cli.positive_float, default=900.0, help="seconds per case")
    ap.add_argument("--write", action="store_true", help="update bench/README.md and scale.png")
    ap.add_argument("--sizes", help="sizes of the one mission of --missions, e.g. 64,128 "
                    "(traversal side, robots, nodes) or 256x64,512x256 (foraging grid x robots)")
    ap.add_argument("--large", action="store_true",
                    help="add the large-map rows (exploration: 100 robots on 40 x 40 m)")
    ap.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        child(*args.child)
        return 0
    missions = args.missions.split(",")
    if unknown := [m for m in missions if m not in SIZES]:
        ap.error(f"unknown mission(s) {', '.join(unknown)}; choose from {', '.join(MISSIONS)}")
    sizes = {m: SIZES[m][: 3 if args.quick else None] for m in missions}
    if args.large:
        for m in missions:
            sizes[m] = sizes[m] + LARGE.get(m, [])
    if args.sizes:
        if len(missions) != 1:
            ap.error("--sizes needs exactly one mission in --missions")
        try:
            sizes[missions[0]] = parse_sizes(missions[0], args.sizes)
        except ValueError as e:
            ap.error(f"--sizes: {e}")
    import tempfile

    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp:
        for mission in missions:
            for size in sizes[mission]:
                r = run_case(mission, size, Path(tmp), args.timeout)
                if r is not None:
                    rows.append(r)
                    print(f"  {mission} {r['label']}: {r['cpu']:.2f} s CPU", file=sys.stderr,
                          flush=True)
    lines = table(rows)
    print("\n".join(lines))
    if goals := target_lines(rows):
        print("\n" + "\n".join(goals))
    if args.write:
        plot(rows, HERE / "scale.png")
        write_readme(lines)
    return 0


if __name__ == "__main__":
    _cli.run(main)
