"""Numbers from the command line: a bound that is broken, and a value that is no number at all
(inf, nan), each say what they are in one line."""

from __future__ import annotations

import math

import pytest

from swarmex.cli import main
from swarmex.errors import InputError, check_number


@pytest.mark.parametrize(("value", "kw", "says"), [
    (math.inf, {"above": 0}, "--x must be a finite number > 0, got inf"),
    (math.nan, {"at_least": 0}, "--x must be a finite number >= 0, got nan"),
    (0.0, {"above": 0}, "--x must be > 0, got 0.0"),
    (-1, {"at_least": 0}, "--x must be >= 0, got -1"),
    (True, {"above": 0}, "--x must be a finite number > 0, got True"),
])
def test_refusals_name_the_option_and_the_reason(value, kw, says):
    with pytest.raises(InputError) as err:
        check_number(value, "--x", **kw)
    assert str(err.value) == says


@pytest.mark.parametrize(("value", "kw"), [(0, {"at_least": 0}), (1e-9, {"above": 0}), (5, {})])
def test_good_values_pass(value, kw):
    check_number(value, "--x", **kw)


def test_the_command_line_says_finite(capsys):
    assert main(["serve", "--grid", "4x4", "--agents", "2", "--port", "0", "--timeout", "inf"]) == 2
    assert capsys.readouterr().err.strip() == (
        "swarmex: error: --timeout must be a finite number > 0, got inf")
