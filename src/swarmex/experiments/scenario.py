"""Scenario files: one mission run written down as TOML, for ``swarmex run``.

A scenario is the command line of a mission command in file form, so it can never drift from
the command's options::

    mission = "traversal"        # traversal | foraging | exploration | roadmap
    grid = "10x10"
    agents = 3
    nests = ["0,9", "9,0"]       # or "0,9;9,0", or [[0, 9], [9, 0]]
    travel-time = 2.22           # travel_time works too

    [[agents]]                   # a fleet: per-agent values by id (traversal; the
    id = 1                       # tables come after the plain keys, as TOML requires)
    job_time = 12.0

Every key but ``mission`` is an option of the mission's command (``traverse``, ``forage``,
``explore``, ``roadmap``), dashes or underscores alike. Its value goes as it is to the
mission's Params parsers (:func:`scenario_values`), the ones ``swarmex.run`` and the command
line use, so a file value means what the Python value means (``grid = [6, 5]`` is
``grid=(6, 5)``, ``nests = ["0,9", "9,0"]`` two cells, ``true``/``false`` a flag on or off).
A relative path (any option the Params declare as a path) is resolved against the scenario
file's folder, so a scenario and its map travel together.

Which options are paths or flags comes from the *shapes* :func:`mission_shapes` reads off the
Params; this module stays free of the CLI framework.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from swarmex.errors import InputError

MISSIONS: dict[str, str] = {
    "traversal": "traverse",
    "foraging": "forage",
    "exploration": "explore",
    "roadmap": "roadmap",
}


@dataclass(frozen=True)
class OptionShape:
    """What ``swarmex run`` must know about one option of a mission command."""

    flag: str  # "--nests"
    is_path: bool = False
    is_flag: bool = False  # a boolean flag: takes no value
    negation: str | None = None  # "--no-quick" when the flag has an off switch
    required: bool = False  # the command refuses to run without it


@dataclass(frozen=True)
class Scenario:
    path: Path
    mission: str
    options: dict[str, Any]  # keys in option form ("travel-time"), in file order

    @property
    def command(self) -> str:
        return MISSIONS[self.mission]


def read_toml(path: Path, what: str) -> dict[str, Any]:
    """A TOML file's table; a missing, unreadable or malformed file is one InputError line
    (``what`` names the file's role: "scenario file", "sweep spec")."""
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"{what} not found: {path}") from None
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise InputError(f"cannot read {what} {path}: {reason}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not valid TOML: {exc}") from None


def check_mission(mission: Any, path: Path) -> str:
    """A scenario's or a sweep spec's ``mission`` key, checked: one of :data:`MISSIONS`."""
    if mission is None:
        raise InputError(f'{path}: no mission key (e.g. mission = "traversal")')
    if not isinstance(mission, str) or mission not in MISSIONS:  # a TOML list is unhashable
        raise InputError(f"{path}: unknown mission {mission!r} (choose from"
                         f" {', '.join(MISSIONS)})")
    return mission


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file; every problem is an InputError naming the file."""
    path = Path(path)
    data = read_toml(path, "scenario file")
    mission = check_mission(data.pop("mission", None), path)
    options: dict[str, Any] = {}
    for key, value in data.items():
        name = key.replace("_", "-")
        if name in options:
            raise InputError(f"{path}: option {name!r} is given twice")
        _check_value(path, name, value)
        options[name] = value
    return Scenario(path, mission, options)


def _check_value(path: Path, name: str, value: Any) -> None:
    scalar = (str, int, float, bool)
    if isinstance(value, scalar):
        return
    if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        return  # an array of tables ([[agents]]: a traversal fleet); the mission parses it
    if isinstance(value, list) and all(
        isinstance(v, scalar)
        or (isinstance(v, list) and all(isinstance(c, int | float) for c in v))
        for v in value
    ):
        return
    raise InputError(
        f"{path}: option {name!r} has an unsupported value {value!r}"
        " (use a string, number, boolean or list)"
    )


def as_text(value: Any) -> str:
    """One value as the command line spells it (lists of pairs → "x,y;x,y"): a sweep's text
    column for a list-valued parameter."""
    if isinstance(value, list):
        if all(isinstance(v, list) for v in value):
            return ";".join(",".join(as_text(c) for c in v) for v in value)
        sep = ";" if any(isinstance(v, str) for v in value) else ","
        return sep.join(as_text(v) for v in value)
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _unknown_option(scenario: Scenario, name: str, shapes: dict[str, OptionShape]) -> InputError:
    """The error for a scenario key its mission command does not have (lists the known ones)."""
    known = ", ".join(sorted(shapes))
    return InputError(
        f"{scenario.path}: swarmex {scenario.command} has no option --{name} (it has: {known})"
    )


def mission_shapes(mission: str) -> dict[str, OptionShape]:
    """Option shapes of a mission's parameters, read off its Params (option name with dashes
    -> shape): what a spec or scenario may set, and which values are paths or flags."""
    from swarmex.missions.registry import get

    shapes = {}
    for info in get(mission).params_type.options().values():
        shapes[info.flag[2:]] = OptionShape(
            flag=info.flag,
            is_path=info.kind is Path,
            is_flag=info.kind is bool,
            negation=info.negation,
            required=info.required,
        )
    return shapes


def scenario_values(scenario: Scenario, shapes: dict[str, OptionShape]) -> dict[str, Any]:
    """The mission parameters of ``scenario`` as Python values for ``Mission.params``:
    file values as they are (the mission's parsers accept TOML's strings, numbers, booleans
    and lists), relative paths taken from the file's folder. An unknown key is an InputError
    listing the known ones."""
    values: dict[str, Any] = {}
    for name, value in scenario.options.items():
        shape = shapes.get(name)
        if shape is None:
            raise _unknown_option(scenario, name, shapes)
        if shape.is_path and isinstance(value, str):
            value = resolve_path(scenario.path.parent, value)
        values[name.replace("-", "_")] = value
    return values


def in_file(path: Path, exc: InputError) -> InputError:
    """``exc`` as one line that names the scenario file once: errors of the mission's parsers
    do not know the file, but the ones raised here (an unknown key) already start with it,
    and naming it twice ("s.toml: s.toml: ...") reads as a bug."""
    text = str(exc)
    return exc if text.startswith(f"{path}:") else InputError(f"{path}: {text}")


def resolve_path(folder: Path, text: str) -> Path:
    """A path from a scenario: ``~`` expanded, relative ones taken from the file's folder."""
    p = Path(text).expanduser()
    return p if p.is_absolute() else folder / p
