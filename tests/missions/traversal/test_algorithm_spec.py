"""Algorithm specs, ``NAME@KEY=VALUE,...``: a policy's options on every surface.

What is pinned: a spec builds the policy its options describe (runs equal those of the
policy built by hand, for settings that are documented identities); every option of every
registered policy reads back from its spelled default into the same run; bad specs are one
clear ``InputError``; the record keeps one spelling, so equal settings give equal records.
The CLI, the environments, the networked runtime and ``rerun`` are pinned in their own tests
(test_cli_traversal, test_traversal_v0, test_protocol, test_warm_up, test_rerun).
"""

from __future__ import annotations

import numpy as np
import pytest

import swarmex
from swarmex.errors import InputError
from swarmex.missions.traversal import run_traversal, uniform_agents
from swarmex.missions.traversal.followed import MadgtaF
from swarmex.missions.traversal.params import TraversalParams
from swarmex.missions.traversal.partition import MadgtaK
from swarmex.missions.traversal.policies import (
    POLICIES,
    canonical_algorithm,
    make_policy,
    parse_algorithm,
    policy_options,
)
from swarmex.worlds import random_obstacles


def _team(world, m: int) -> list:
    free = np.nonzero(~world.blocked)[0]
    return uniform_agents([int(v) for v in free[:m]], 2.0, 9.0)


def test_options_are_read_with_their_types():
    name, options = parse_algorithm(" madgta-f@ils=60, keep=False ,follow=walls,max_vacant=none")
    assert name == "madgta-f"
    assert options == {"ils": 60, "keep": False, "follow": "walls", "max_vacant": None}
    assert parse_algorithm("madgta-h@rho=1")[1] == {"rho": 1.0}  # an int where a float goes
    assert isinstance(parse_algorithm("madgta-h@rho=1")[1]["rho"], float)
    assert parse_algorithm("madgta-k") == ("madgta-k", {})


def test_inherited_options_are_accepted():
    """madgta-f passes unknown keywords up to madgta-k, madgta-p and madgta-r."""
    options = policy_options(MadgtaF)
    for key in ("tip_per_agent", "rounds", "ils", "ruin", "keep", "k", "max_vacant", "horizon"):
        assert key in options
    policy = make_policy("madgta-f@rounds=20,k=3,ruin=6")
    assert (policy.sweep.rounds, policy.k, policy.ruin) == (20, 3, 6)
    assert policy_options(POLICIES["madgta"]) == {}


@pytest.mark.parametrize(("spec", "message"), [
    ("madgta-f@bogus=1", "madgta-f has no option 'bogus' (its options: tip_per_agent,"),
    ("madgta@k=1", "madgta has no option 'k' (its options: none)"),
    ("madgta-f@ils=1.5", "option 'ils' must be int, got '1.5'"),
    ("madgta-f@keep=2", "option 'keep' must be bool"),
    ("madgta-f@ils=true", "option 'ils' must be int"),
    ("madgta-f@ils", "expected KEY=VALUE after '@', got 'ils'"),
    ("madgta-f@", "expected KEY=VALUE after '@'"),
    ("madgta-f@ils=1,ils=2", "option 'ils' given twice"),
    ("madgta-f@ils=-1", "ils must be in 0..10000, got -1"),  # the class's own check
    ("madgta-f@ils=1000000000", "ils must be in 0..10000"),  # ran for ever, deaf to Ctrl-C
    ("madgta-r@samples=100000000", "samples must be in 0..1000"),  # 5 GB in 20 s, for ever
    ("madgta-r@ties=5000", "ties must be in 0..1000, got 5000"),
    # a word option names its words ("must be str, got '-1'" did not)
    ("madgta-f@idle=-1", "idle must be one of madgta, stop, got '-1'"),
    # not finite: "must be float, got 'nan'", and 1e400 was shown as inf
    ("madgta-f@tol=nan", "option 'tol' must be a finite number, got 'nan'"),
    ("madgta-r@weight=1e400", "option 'weight' must be a finite number, got '1e400'"),
    ("madgta-f@follow=sometimes", "follow must be True, False or 'walls'"),
    ("madgta-x@ils=1", "unknown traversal algorithm 'madgta-x'"),
    # the MILP is not a policy: it used to be refused while listed among the choices
    ("optimal", "'optimal' is the exact MILP plan of the whole mission, not an online policy"),
])
def test_a_bad_spec_is_one_clear_input_error(spec, message):
    with pytest.raises(InputError) as err:
        make_policy(spec)
    assert message in str(err.value)
    assert "\n" not in str(err.value)


def test_run_traversal_refuses_a_negative_seed_by_name():
    world = random_obstacles(5, 5, 0.0, seed=0)
    with pytest.raises(InputError, match="seed must be at least 0, got -1"):
        run_traversal(world, uniform_agents([0], 1.0, 1.0), seed=-1)


def test_the_spelling_is_canonical():
    assert canonical_algorithm("madgta-f@keep=False,ils=60") == "madgta-f@ils=60,keep=false"
    assert canonical_algorithm("madgta-f@ils=60,keep=false") == "madgta-f@ils=60,keep=false"
    assert canonical_algorithm("madgta-r@tol=0.5,max_vacant=None") == \
        "madgta-r@max_vacant=none,tol=0.5"
    assert TraversalParams.from_values(grid="4x4", agents=2, algorithm="madgta-f@keep=False,ils=60"
                                       ).algorithm == "madgta-f@ils=60,keep=false"


def test_options_are_applied():
    """Two documented identities: madgta-f is madgta-k with four settings, and madgta-f
    with its plan switched off is the gated madgta-k; each built by hand, compared run for
    run with the spec."""
    world = random_obstacles(14, 14, 0.2, seed=2)
    agents = _team(world, 5)
    spelled = run_traversal(world, agents, "madgta-k@tip_per_agent=60,follow=walls,ils=30,"
                                           "keep=true", seed=2)
    assert spelled.path_strings() == run_traversal(world, agents, MadgtaF(), seed=2
                                                   ).path_strings()
    off = run_traversal(world, agents, "madgta-f@ils=0,keep=false,follow=false", seed=2)
    assert off.path_strings() == run_traversal(world, agents, MadgtaK(tip_per_agent=60),
                                               seed=2).path_strings()
    assert off.algorithm == "madgta-f@follow=false,ils=0,keep=false"


@pytest.mark.parametrize("name", sorted(POLICIES))
def test_every_option_reads_back_from_its_spelled_default(name):
    """Each registered policy with every option given its default, spelled the way a
    record spells it, runs exactly like the bare name (None, bools, text and numbers all
    survive the round trip)."""
    import inspect

    defaults = {}
    for klass in POLICIES[name].__mro__:
        init = klass.__dict__.get("__init__")
        if init is not None:
            for key, p in inspect.signature(init).parameters.items():
                if p.default is not p.empty:
                    defaults.setdefault(key, p.default)
    spec = name
    if (keys := [k for k in policy_options(POLICIES[name]) if k in defaults]):
        spec = canonical_algorithm(name + "@" + ",".join(
            f"{k}={'none' if defaults[k] is None else defaults[k]}" for k in keys))
    world = random_obstacles(9, 9, 0.2, seed=4)
    agents = _team(world, 3)
    assert run_traversal(world, agents, spec, seed=4).path_strings() == \
        run_traversal(world, agents, name, seed=4).path_strings()


def test_swarmex_run_records_the_spec():
    record = swarmex.run("traversal", grid="6x6", obstacles="2,2;3,3", agents=3, seed=1,
                         algorithm="madgta-f@keep=False,ils=4")
    assert record.params["algorithm"] == "madgta-f@ils=4,keep=false"
    assert record.algorithm == "madgta-f@ils=4,keep=false"
    with pytest.raises(InputError, match="^algorithm: options .* are for a policy"):
        swarmex.run("traversal", grid="4x4", agents=2, algorithm="optimal@objective=sum")
