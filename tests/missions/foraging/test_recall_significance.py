"""Recall's choice rules on made-up replay totals (module docstring). The significance rule:
with two or more remembered distances the team leaves the pattern best for uniform food only
for a candidate whose gain over it, paired over the remembered distances, *exceeds*
``SIGNIFICANT`` (2) standard errors: mean gain + 2 · sd / sqrt(m) < 0. And the filter of
candidates another one beats by 10 % in every distance band."""

from __future__ import annotations

import pytest

from swarmex.missions.foraging import recall
from swarmex.missions.foraging.grid import manhattan, nest_of

G, N = 16, 4
A, B = "strips", "spiral"  # A: best for uniform food; B: best where food was found


def _choose(monkeypatch, ring_totals):
    """``choose`` with B's replay total ``ring_totals[d]`` on the ring of remembered distance
    ``d``, 101 rounds on the prior's cells, and A's 100 everywhere."""
    nest = nest_of(G)
    total_at = {c: v for d, v in ring_totals.items() for c in recall.ring_cells(G, d)}
    far = ((0, 0),), ((G - 1, G - 1),)  # the prior: two far cells, not on the rings
    assert not {c for cells in far for c in cells} & set(total_at)
    monkeypatch.setattr(recall, "prior_of", lambda g: recall.Prior(far, (0.5, 0.5)))

    def replay(cand, g, n, food, units, transport, comm):
        assert manhattan(food, nest) > 0
        return 100 if cand == A else total_at.get(food, 101)

    monkeypatch.setattr(recall, "replay", replay)
    monkeypatch.setattr(recall, "candidates", lambda g, n, distances: [A, B])
    found = [(nest[0] + d, nest[1]) for d in ring_totals]
    return recall.choose(G, N, found, 3, "relay-food", "seed")


@pytest.mark.parametrize(
    ("b_rings", "chosen"),
    [
        ({4: 96.5, 6: 98.5}, B),  # gains -3.5, -1.5: mean -2.5, 1 s.e.: -2.5 + 2 < 0
        ({4: 97.0, 6: 99.0}, A),  # gains -3, -1: mean -2, 1 s.e.: exactly 2 s.e., not beyond
        ({4: 97.5, 6: 99.5}, A),  # gains -2.5, -0.5: mean -1.5, 1 s.e.: within 2 s.e.
    ],
)
def test_the_team_leaves_the_uniform_best_pattern_only_beyond_two_standard_errors(
    monkeypatch, b_rings, chosen
):
    choice = _choose(monkeypatch, b_rings)
    # B has the least score every time: (2 · ring mean + uniform mean) / 3 < A's 100
    assert min(choice.predicted, key=choice.predicted.__getitem__) == B
    assert choice.predicted[A] == pytest.approx(100.0)
    assert choice.pattern == chosen


def test_a_candidate_beaten_by_exactly_ten_percent_in_every_band_is_dropped(monkeypatch):
    """Module docstring: "A candidate that another beats by 10 % in every distance band of
    the prior ... is dropped" (``DOMINATED`` = 0.9): A takes 90 rounds wherever the food
    lies, B 100, so B is not a candidate any more; at 91 it would be kept."""
    far = ((0, 0),), ((G - 1, G - 1),)
    monkeypatch.setattr(recall, "prior_of", lambda g: recall.Prior(far, (0.5, 0.5)))
    monkeypatch.setattr(recall, "candidates", lambda g, n, distances: [A, B])
    for a_total, kept in ((90, [A]), (91, [A, B])):
        totals = {A: a_total, B: 100}
        monkeypatch.setattr(recall, "replay", lambda cand, *rest, t=totals: t[cand])
        choice = recall.choose(G, N, [], 3, "relay-food", "seed")
        assert sorted(choice.predicted) == sorted(kept) and choice.pattern == A
