"""Golden scenarios: fixed-seed runs of every mission and algorithm whose records must not
change when code moves (issue 12). Each entry is (name, mission, CLI command, argv); argv
paths are relative to the repository root, where the runs are made."""

from __future__ import annotations

SCENARIOS: list[tuple[str, str, str, list[str]]] = []


def _add(name: str, mission: str, command: str, *argv: str) -> None:
    SCENARIOS.append((name, mission, command, list(argv)))


# traversal: every algorithm, objective, channel option and timing option
for alg in ("madgta", "madgta+", "nearest"):
    _add(f"trav-{alg}", "traversal", "traverse", "--grid", "8x8", "--agents", "3",
         "--algorithm", alg, "--obstacles", "3,2;3,3;3,4;5,5", "--nests", "0,0;7,7", "--seed", "3")
for obj in ("sum", "makespan"):
    _add(f"trav-optimal-{obj}", "traversal", "traverse", "--grid", "3x3", "--agents", "2",
         "--algorithm", "optimal", "--objective", obj, "--seed", "1")
_add("trav-lossy", "traversal", "traverse", "--grid", "10x10", "--agents", "4", "--loss", "0.3",
     "--delay", "0.5", "--comm-range", "4", "--seed", "5")
_add("trav-failure-alt8", "traversal", "traverse", "--map", "tests/golden/tiny.map",
     "--agents", "3", "--connectivity", "8", "--job-failure", "0.2", "--altitude", "5",
     "--travel-time", "1.5", "--job-time", "3", "--start-interval", "1", "--seed", "2")
# foraging: every pattern, every transport, every food option
for alg in ("strips", "zigzag", "hilbert", "sectors", "spiral", "rings", "loop-strips"):
    _add(f"forage-{alg}", "foraging", "forage", "--grid", "32", "--agents", "4", "--algorithm",
         alg, "--food-distance", "40-60", "--food-units", "12", "--seed", "4")
_add("forage-modified-zigzag", "foraging", "forage", "--grid", "32", "--agents", "8",
     "--algorithm", "modified-zigzag", "--food-distance", "60-80", "--seed", "4")
for tr in ("end-to-end", "relay-food", "relay-path"):
    _add(f"forage-{tr}", "foraging", "forage", "--grid", "20", "--agents", "8", "--algorithm",
         "sectors", "--transport", tr, "--food", "15,3", "--food-units", "20", "--seed", "1")
_add("forage-random", "foraging", "forage", "--grid", "16", "--agents", "2", "--algorithm",
     "spiral", "--seed", "9")
# exploration: every strategy, and the protocol options
for st in ("greedy", "greedy-exclusion", "utility", "minpos", "hungarian"):
    _add(f"explore-{st}", "exploration", "explore", "--empty", "4x4", "--cell", "0.1",
         "--robots", "3", "--laser-range", "1.0", "--comm-range", "2.0", "--strategy", st,
         "--seed", "1")
_add("explore-map-options", "exploration", "explore", "--map", "tests/golden/tiny.map",
     "--cell", "0.25", "--robots", "3", "--comm-range", "1.5", "--no-aodv", "--conflict-yield",
     "--plan-pause", "2", "--starts", "1,1;2,1;1,2", "--beams", "180", "--seed", "2")
_add("explore-maxticks", "exploration", "explore", "--empty", "5x5", "--cell", "0.1",
     "--robots", "2", "--max-ticks", "30", "--robot-radius", "0.15", "--seed", "0")
# roadmap: every planner and task
for pl in ("wma-rrt", "prm", "wma-rrt-takeover"):
    _add(f"roadmap-cover-{pl}", "roadmap", "roadmap", "--env", "examples/roadmap_fig8.json",
         "--planner", pl, "--agents", "3", "--nodes", "150", "--step", "30",
         "--sensor-range", "1eps", "--seed", "1")
    _add(f"roadmap-search-{pl}", "roadmap", "roadmap", "--env", "examples/roadmap_fig14.json",
         "--task", "search", "--planner", pl, "--agents", "2", "--nodes", "150", "--step",
         "30", "--sensor-range", "inf", "--seed", "2")
_add("roadmap-budget", "roadmap", "roadmap", "--env", "examples/roadmap_fig8.json",
     "--agents", "2", "--nodes", "80", "--step", "40", "--sensor-range", "60",
     "--step-budget", "50", "--raster", "128", "--starts", "40,40;60,40", "--seed", "0")
