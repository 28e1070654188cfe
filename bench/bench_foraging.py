"""Foraging speed: one full 128×128 run per pattern with n = 16 (8 for Modified ZigZag).

Prints, per pattern: the one-off timetable build (shared by every run of the pattern), the wall
time of a run without and with the full trajectory record, the rounds played and rounds/s, and
the ratio against the reference — the same run with the compiled transport tail switched off
(the pure-Python loop, which gives the identical result). It ends with the projected wall time
of the full ``swarmex reproduce foraging`` sweep on two cores.

    .venv/bin/python bench/bench_foraging.py
"""

from __future__ import annotations

import time

import _cli
from swarmex.missions.foraging.sim import run_mission
from swarmex.missions.foraging.timed import timed_plan
from swarmex.studies.foraging.design import TABLE_CONFIGS, TRANSPORT_CONFIGS, food_cells

G, UNITS = 128, 100
PATTERNS = TRANSPORT_CONFIGS  # the reproduction's eight n = 16 (or 8) configurations


def timed_run(T, food, record, fast):
    t0 = time.perf_counter()
    o = run_mission(T, food, UNITS, "relay-food", record=record, fast=fast)
    return time.perf_counter() - t0, o.makespan


def main() -> None:
    # no options; parsed so that --help works and a stray argument is refused, not ignored
    _cli.Parser(description=__doc__.split("\n\n")[0]).parse_args()
    foods = food_cells(2015, 4)["random"]
    warm = timed_plan("strips", G, 4)
    run_mission(warm, (3, 3), 2, "relay-food", record=False)  # compile (or load) the tail
    print(f"{'pattern':16s} {'n':>3s} {'plan s':>7s} {'run s':>7s} {'rec s':>7s} "
          f"{'rounds':>7s} {'rounds/s':>9s} {'python s':>9s} {'speed-up':>8s}")  # fmt: skip
    for name, n in PATTERNS:
        t0 = time.perf_counter()
        T = timed_plan(name, G, n)
        plan_s = time.perf_counter() - t0
        fast = [timed_run(T, f, False, True) for f in foods]
        rec = [timed_run(T, f, True, True) for f in foods]
        slow = [timed_run(T, f, False, False) for f in foods]
        w = sum(x for x, _ in fast) / len(foods)
        rounds = sum(r for _, r in fast) / len(foods)
        wr = sum(x for x, _ in rec) / len(foods)
        ws = sum(x for x, _ in slow) / len(foods)
        print(
            f"{name:16s} {n:3d} {plan_s:7.2f} {w:7.3f} {wr:7.3f} {rounds:7.0f} "
            f"{rounds / w:9.0f} {ws:9.3f} {ws / w:7.1f}x"
        )
    # projection: one run per table configuration on each of the sample cells
    sample = []
    for name, n in TABLE_CONFIGS:
        T = timed_plan(name, G, n)
        sample += [timed_run(T, f, False, True)[0] for f in foods[:2]]
    runs = len(TABLE_CONFIGS) * 6 * 40 + len(TRANSPORT_CONFIGS) * 2 * 40
    mean = sum(sample) / len(sample)
    print(
        f"full reproduction: {runs} runs × {mean:.3f} s mean over all configurations "
        f"≈ {runs * mean / 2 / 60:.1f} min on 2 cores (plus timetables and figures, < 1 min)"
    )


if __name__ == "__main__":
    _cli.run(main)
