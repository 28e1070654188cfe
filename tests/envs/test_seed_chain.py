"""Episode seeds of the environments (``swarmex.envs.common.SeedChain``)."""

from __future__ import annotations

import pickle

import pytest

pytest.importorskip("pettingzoo")

from swarmex.envs.common import SeedChain  # noqa: E402


def _seeds(first: int, explicit: int | None, n: int) -> list[int]:
    chain = SeedChain(first)
    out = [chain.next(explicit)]
    out += [chain.next(None) for _ in range(n - 1)]
    return out


def test_copies_seeded_one_apart_never_replay_each_other():
    """SuperSuit seeds its copies s, s + 1, ...: with "the previous seed + 1" copy i replayed
    copy i + 1's episodes one reset later."""
    streams = [_seeds(0, 100 + i, 200) for i in range(4)]
    assert [s[0] for s in streams] == [100, 101, 102, 103]
    for i, a in enumerate(streams):
        for b in streams[i + 1:]:
            assert not set(a) & set(b)


def test_the_sequence_is_reproducible_and_starts_with_the_params_seed():
    assert _seeds(7, None, 5) == _seeds(7, None, 5)
    assert _seeds(7, None, 5)[0] == 7
    assert _seeds(7, 3, 5) == _seeds(9, 3, 5)  # an explicit seed restarts it, whatever the params


def test_a_pickled_chain_goes_on_where_it_was():
    chain = SeedChain(4)
    chain.next(None)
    chain.next(None)
    copy = pickle.loads(pickle.dumps(chain))
    assert [copy.next(None) for _ in range(3)] == [chain.next(None) for _ in range(3)]
