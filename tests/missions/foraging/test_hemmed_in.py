"""An idle robot hemmed in by robots that want its cell keeps it (resolve.py's last resort).

Before the rule, Alg. 1's resolution had no answer when an idle robot, bumped off its cell,
found every side cell kept: the Python rule raised and the compiled loop read past the
robot's list of options (undefined memory, a crash in ``swarmex.run``). Found by
``floor.py``'s start states and then in a plain run: food in a grid corner, few units.
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.missions.foraging import fastloop, replay, run_forage, to_record
from swarmex.missions.foraging.resolve import resolve
from swarmex.missions.foraging.sim import run_mission
from swarmex.missions.foraging.timed import timed_plan

# the round that had no answer (captured from floor.py's start state: g = 8, food (0, 0))
CUR = [(0, 1), (0, 3), (0, 0), (1, 0), (0, 2), (1, 1)]
OPTS = [
    [(0, 2), (0, 1)],
    [(0, 2), (0, 3)],
    [(0, 0), (1, 0), (0, 1)],  # idle in the corner: stay, then its two side cells
    [(0, 0), (1, 0)],
    [(0, 1), (0, 2)],
    [(0, 1), (1, 0), (1, 1)],
]
ORDER = [4, 0, 5, 3, 1, 2]
NEST = (4, 4)


def _legal(cur, opts, new, nest):
    outside = [c for c in new if c != nest]
    assert len(outside) == len(set(outside)), "two robots in one non-nest cell"
    for p, o, c in zip(cur, opts, new, strict=True):
        assert c in o or c == p, "a robot left its options"


def test_the_hemmed_in_robot_keeps_its_cell_and_the_intruder_yields():
    new = resolve(CUR, OPTS, ORDER, NEST)
    _legal(CUR, OPTS, new, NEST)
    assert new[2] == (0, 0)  # both side cells are kept (robots 3 and 5 stay)
    assert new[3] == (1, 0)  # the robot that wanted the corner stays instead
    assert (new[0], new[4]) == ((0, 2), (0, 1))  # the swap above is untouched


def test_the_compiled_resolution_gives_the_same_answer():
    n = len(CUR)
    pos = np.asarray(CUR, dtype=np.int64)
    wishes = np.zeros((n, fastloop.MAXOPT, 2), dtype=np.int64)
    for a, o in enumerate(OPTS):
        wishes[a, : len(o)] = o
    nopt = np.asarray([len(o) for o in OPTS], dtype=np.int64)
    choice = np.zeros(n, dtype=np.int64)
    cells = np.full((8, 8), -1, dtype=np.int64)
    order = np.asarray(ORDER, dtype=np.int64)
    fastloop._resolve(pos, wishes, nopt, order, NEST[0], NEST[1], choice, cells)
    got = [tuple(int(v) for v in wishes[a, choice[a]]) for a in range(n)]
    assert got == resolve(CUR, OPTS, ORDER, NEST)
    assert nopt[2] == 4  # the last resort was appended for the hemmed-in robot only
    assert nopt.tolist()[:2] + nopt.tolist()[3:] == [2, 2, 2, 2, 3]


@pytest.mark.parametrize("transport", ["relay-path", "relay-food"])
def test_a_corner_food_run_finishes_the_same_in_both_loops(transport):
    """The plain run that crashed: g = 16, 8 robots, Spiral, food in a corner, 3 units."""
    rec = to_record(run_forage("spiral", 16, 8, (15, 0), 3, transport), 0, {}).to_dict()
    assert rec["complete"] is True
    assert rec["metrics"]["food_delivered"] == 3
    assert replay(rec) == []  # every move legal, no shared non-nest cell
    plan = timed_plan("spiral", 16, 8)
    slow, fast = (run_mission(plan, (15, 0), 3, transport, fast=f) for f in (False, True))
    assert slow.makespan == fast.makespan == rec["makespan"]
    assert np.array_equal(slow.positions, fast.positions)
