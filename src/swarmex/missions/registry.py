"""The explicit registry of missions: name -> the object implementing the contract.

Why explicit: registration by import side effect makes the set of missions depend on what
happened to be imported. Here the four built-in missions are listed by module path and
imported only when first asked for (so ``swarmex --help`` stays light), and third-party
packages add missions through the ``swarmex.missions`` entry-point group, whose entries name
a :class:`~swarmex.missions.base.Mission` subclass or instance::

    [project.entry-points."swarmex.missions"]
    patrol = "my_package.patrol:PatrolMission"
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Iterator
from contextlib import contextmanager
from functools import cache
from importlib.metadata import entry_points
from typing import Any

from swarmex.errors import InputError
from swarmex.missions.base import Mission, Params, rename_flags

BUILTIN: dict[str, str] = {
    "exploration": "swarmex.missions.exploration.mission:ExplorationMission",
    "foraging": "swarmex.missions.foraging.mission:ForagingMission",
    "roadmap": "swarmex.missions.roadmap.mission:RoadmapMission",
    "traversal": "swarmex.missions.traversal.mission:TraversalMission",
}
ENTRY_POINT_GROUP = "swarmex.missions"


def _load(target: str) -> Mission[Any, Any]:
    module, _, attr = target.partition(":")
    obj = getattr(importlib.import_module(module), attr)
    return obj() if isinstance(obj, type) else obj


@cache
def _plugins() -> dict[str, Any]:
    return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP) if ep.name not in BUILTIN}


def names() -> list[str]:
    """Registered mission names, sorted."""
    return sorted({*BUILTIN, *_plugins()})


def get(name: str) -> Mission[Any, Any]:
    """The mission called ``name``; an unknown name is an InputError naming the nearest."""
    if not isinstance(name, str):  # a list raised "unhashable type" from the cache
        raise InputError(f"a mission is a name such as 'traversal', got {name!r}")
    return _get(name)


@cache
def _get(name: str) -> Mission[Any, Any]:
    if name in BUILTIN:
        return _load(BUILTIN[name])
    plugin = _plugins().get(name)
    if plugin is not None:
        obj = plugin.load()
        mission = obj() if isinstance(obj, type) else obj
        if not isinstance(mission, Mission):
            raise InputError(f"entry point {name!r} does not name a swarmex Mission")
        return mission
    close = difflib.get_close_matches(str(name), names(), n=1, cutoff=0.5)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    raise InputError(f"unknown mission {name!r} (choose from {', '.join(names())}){hint}")


def by_command(command: str) -> Mission[Any, Any]:
    """The mission whose CLI command is ``command`` (``"traverse"`` -> traversal)."""
    for name in names():
        mission = get(name)
        if mission.command == command:
            return mission
    raise InputError(f"no mission has the command {command!r}")


def same_value(mission: str | None, name: str, a: Any, b: Any) -> bool:
    """Whether ``a`` and ``b`` are one value of ``mission``'s option ``name`` once its parser
    has read both: a sweep table spells ``grid=(5, 5)`` "5,5", a user writes "5x5" (as the
    command line and the records do). False when either does not parse or the option is
    unknown."""
    if mission is None:
        return False
    try:
        info = get(mission).params_type.options().get(name.replace("-", "_"))
    except InputError:
        return False
    if info is None:
        return False

    def parsed(value: Any) -> Any:
        try:
            return info.parse(value, info.flag)
        except (InputError, TypeError, ValueError):
            pass
        if isinstance(value, str) and "," in value and ";" not in value:
            try:  # a table's text of a pair, "5,5": the pair itself
                return info.parse([float(p) if "." in p else int(p) for p in value.split(",")],
                                  info.flag)
            except (InputError, TypeError, ValueError):
                pass
        return _UNPARSED

    first = parsed(a)
    return first is not _UNPARSED and first == parsed(b)


_UNPARSED = object()


@contextmanager
def any_python_spelling() -> Iterator[None]:
    """:func:`~swarmex.missions.base.python_spelling` for the options of every registered
    mission: for surfaces that learn the mission from a record (``swarmex.rerun``,
    ``render``). The missions are looked up only when an error is raised."""
    try:
        yield
    except InputError as exc:
        rename_flags(exc, _registered_params_types())
        raise


def _registered_params_types() -> list[type[Params]]:
    found = []
    for name in names():
        try:
            found.append(get(name).params_type)
        except Exception:  # noqa: BLE001 - a broken plugin must not hide the user's error
            continue
    return found
