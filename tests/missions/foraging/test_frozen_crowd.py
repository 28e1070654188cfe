"""End-to-End robots that freeze in a crowd near the food get going again (docs/foraging.md).

The frozen state is detected by an exact repeat of the transport state after Look; the rule
then lets robots that want to move take a free side cell for that round. Before the rule
these runs never finished (NoProgress).
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmex.cli import main
from swarmex.missions.foraging.sim import TRANSPORT, Mission, run_mission
from swarmex.missions.foraging.timed import timed_plan

# a run that froze before the rule: (pattern, g, n, food, k)
FROZE = [("strips", 12, 6, (7, 4), 48)]


@pytest.mark.parametrize("pattern, g, n, food, k", FROZE)
def test_a_run_that_froze_now_finishes_and_the_compiled_loop_agrees(pattern, g, n, food, k):
    plan = timed_plan(pattern, g, n)
    slow = run_mission(plan, food, k, "end-to-end", fast=False)
    fast = run_mission(plan, food, k, "end-to-end", fast=True)
    assert slow.complete and slow.delivered == k
    assert slow.makespan == fast.makespan
    assert np.array_equal(slow.positions, fast.positions)
    assert slow.jobs == fast.jobs
    # replay: every move is one step or a stay, and no two robots share a non-nest cell
    steps = np.abs(np.diff(slow.positions, axis=0)).sum(axis=2)
    assert steps.max() <= 1
    nest = tuple(plan.plan.nest)
    for row in slow.positions:
        cells = [tuple(c) for c in row.tolist() if tuple(c) != nest]
        assert len(cells) == len(set(cells))


# runs that froze in the mixed phase (someone still explores or communicates) before the rule
# covered it (30 Nov 2026): (pattern, g, n, comm, food, k). The first two stood still for
# good; in the third two seed-rule messengers chase each other (period 2) while the
# End-to-End crowd stands still; the last is the g = 100 example of docs/foraging.md.
MIXED = [
    ("sectors", 14, 48, "seed", (8, 4), 20),
    ("sectors", 14, 48, "omniscient", (8, 5), 20),
    ("rings", 10, 24, "seed", (7, 9), 20),
    ("sectors", 100, 64, "omniscient", (51, 48), 100),
]


def _mixed_snapshot(m: Mission):
    """The whole state a mixed round depends on, from the mission's own fields and with the
    full lists and word (``Mission.mixed_key`` keeps counts of those); None outside it."""
    if not any(m.informed) or all(mode == TRANSPORT for mode in m.mode):
        return None
    t_end = m.timed.t_end
    return (
        [tuple(p) for p in m.pos], list(m.carrying), list(m.mode), list(m.tmode),
        list(m.pidx), [m.join_at.get(a) if m.mode[a] == TRANSPORT else None for a in range(m.n)],
        list(m.displaced), list(m.informed), [min(max(0, m.t - d), t_end) for d in m.delay],
        [list(x) for x in m.targets], list(m.word.know) if m.word is not None else None,
        m.units, m.delivered,
    )  # fmt: skip


def _count_frozen(monkeypatch):
    """Patch Mission.step to check every round's frozen flag against the rule as stated:
    it fires exactly when (a) every robot transports and the transport state after Look
    (positions, loads, transport modes, path indices, units, delivered) equals the previous
    round's, every robot transporting then too, or (b) in the mixed phase (someone informed,
    not everyone transporting) the whole state equals that of the previous round or of the
    round before it, both in the mixed phase. Returns the list of (flag, mixed) per round."""
    fired: list[tuple[bool, bool]] = []
    original = Mission.step
    previous: list = [None]
    mixed_before: list = [None, None]

    def step(self):
        snap = (
            [tuple(p) for p in self.pos],
            list(self.carrying),
            list(self.tmode),
            list(self.pidx),
            self.units,
            self.delivered,
        )
        transporting = all(m == TRANSPORT for m in self.mode)
        mixed = _mixed_snapshot(self)
        if transporting:
            repeated = snap == previous[0]
        else:
            repeated = mixed is not None and mixed in mixed_before
        previous[0] = snap if transporting else None
        mixed_before[:] = [mixed, mixed_before[0]] if mixed is not None else [None, None]
        original(self)
        assert self._frozen == repeated
        fired.append((self._frozen, mixed is not None))

    monkeypatch.setattr(Mission, "step", step)
    return fired


def test_the_rule_fires_only_on_an_exact_repeat(monkeypatch):
    """Count frozen rounds: a run that never repeats its state never uses the rule, and the
    rule fires exactly on the rounds whose state after Look (snapshotted here, from the
    mission's own fields) repeats the previous round's with every robot transporting, or in
    the mixed phase repeats that of one of the two rounds before (_count_frozen)."""
    fired = _count_frozen(monkeypatch)
    plan = timed_plan("strips", 12, 6)
    run_mission(plan, (7, 4), 48, "end-to-end", fast=False)
    assert any(f for f, _ in fired)  # the crowd froze and was broken
    assert any(mixed for _, mixed in fired)  # the mixed phase was checked too
    fired.clear()
    run_mission(plan, (2, 9), 12, "end-to-end", fast=False)
    assert not any(f for f, _ in fired)


@pytest.mark.parametrize("pattern, g, n, comm, food, k", MIXED[:3])
def test_the_mixed_rule_fires_exactly_on_a_repeat(monkeypatch, pattern, g, n, comm, food, k):
    fired = _count_frozen(monkeypatch)
    run_mission(timed_plan(pattern, g, n), food, k, "end-to-end", fast=False, comm=comm)
    assert any(f and mixed for f, mixed in fired)  # it fired in the mixed phase


@pytest.mark.parametrize("pattern, g, n, comm, food, k", MIXED)
def test_a_mixed_phase_freeze_now_finishes_and_every_loop_agrees(pattern, g, n, comm, food, k):
    """Before the mixed-phase rule these runs went to the round limit with units left. Now
    they finish, legally (replay), the same in the Python loop, the compiled one (its
    communication phase) and a hooked run that plays the seed's moves."""
    from swarmex.missions.foraging.replay import replay
    from swarmex.missions.foraging.run import run_forage, to_record

    plan = timed_plan(pattern, g, n)
    slow = run_mission(plan, food, k, "end-to-end", fast=False, comm=comm)
    fast = run_mission(plan, food, k, "end-to-end", fast=True, comm=comm)
    hooked = run_mission(plan, food, k, "end-to-end", comm=comm, decide=lambda c: c.builtin)
    assert slow.complete and slow.delivered == k
    for other in (fast, hooked):
        assert other.makespan == slow.makespan
        assert np.array_equal(other.positions, slow.positions)
        assert other.jobs == slow.jobs and other.handovers == slow.handovers
        assert other.comm_done == slow.comm_done
    rec = to_record(run_forage(pattern, g, n, food, k, "end-to-end", comm=comm), 0, {})
    record = rec.to_dict()
    assert record["complete"] and record["makespan"] == slow.makespan
    assert replay(record) == []


@pytest.mark.parametrize("pattern, g, n", [("strips", 12, 6), ("sectors", 16, 8)])
def test_every_food_cell_finishes_end_to_end(pattern, g, n):
    plan = timed_plan(pattern, g, n)
    for fx in range(g):
        for fy in range(g):
            if (fx, fy) == tuple(plan.plan.nest):
                continue
            for k in (n, 4 * n):
                out = run_mission(plan, (fx, fy), k, "end-to-end", record=False)
                assert out.complete, (fx, fy, k)


def test_the_cli_example_that_used_to_hang(capsys):
    argv = ["forage", "--grid", "12", "--agents", "6", "--algorithm", "strips"]
    extra = ["--food", "7,4", "--transport", "end-to-end", "--food-units", "48"]
    assert main([*argv, *extra]) == 0
    assert "48/48" in capsys.readouterr().out


def test_a_locked_team_ends_as_an_incomplete_run_and_both_loops_agree(tmp_path, capsys):
    """A crowd the side-step rule cannot free (24 robots on 7 x 7, End-to-End) cycles through
    the same 60 states for ever. It used to raise NoProgress, a traceback that lost the run;
    it now ends at the round limit as an incomplete run whose record says ``stalled``, the
    same in the compiled loop and in the Python one."""
    from swarmex.missions.foraging.sim import round_limit

    plan = timed_plan("sectors", 7, 24)
    fast = run_mission(plan, (6, 0), 13, "end-to-end", fast=True)
    slow = run_mission(plan, (6, 0), 13, "end-to-end", fast=False)
    limit = round_limit(fast.discovery, 7, 13)
    for o in (fast, slow):
        assert not o.complete and o.delivered == 5
        assert o.makespan == limit and o.extra == {"stalled": limit}
        assert len(o.positions) == limit + 1  # rows 0..makespan, as a finished run's
    assert np.array_equal(fast.positions, slow.positions)
    assert fast.jobs == slow.jobs and fast.handovers == slow.handovers

    argv = ["forage", "--grid", "7", "--agents", "24", "--algorithm", "sectors",
            "--transport", "end-to-end", "--food", "6,0", "--food-units", "13",
            "--json", str(tmp_path / "r.json")]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f"stalled: the team locked with 5 of 13 units home; the run stopped at its round " \
        f"limit, {limit}" in out
    import json

    record = json.loads((tmp_path / "r.json").read_text())
    assert record["complete"] is False and record["stalled"] == limit
