"""The Mission contract: what every mission implements once, and every surface relies on.

A mission is three things:

* a **Params** dataclass (a subclass of :class:`Params`) that owns every parameter's default,
  unit, parser and validation rule. Each field is declared with :func:`option`, which names
  its command-line flag and says how a value given as the CLI's string *or* as a plain Python
  value (``grid="12x12"`` or ``grid=(12, 12)``) becomes the typed value. Nothing else in
  swarmex knows a mission's defaults: the CLI's options, scenario files, sweeps and
  ``swarmex.run`` all read them from here;
* a :class:`Mission` object that turns valid Params into a prepared world (every check that
  needs the world happens there, before any work starts), runs it and builds the
  :class:`~swarmex.engine.record.ResultRecord`;
* an entry in the explicit registry (:mod:`swarmex.missions.registry`).

Why a dataclass of options rather than the CLI's signature: the Python API, TOML files and
sweeps need the same names, defaults and checks as the command line, and a plain dataclass
is what a library user can read, compare, pickle and copy with changes (``params.replace(...)``,
which parses and checks the changes; a Params built by its constructor or by
``dataclasses.replace`` skips the parsers until :meth:`Mission.run` reruns them, see
:meth:`Params.validated`). The CLI generates
its options from these declarations (cli/missions.py), so the two cannot drift.

Parsing is strict and names the parameter: ``agents="three"`` is an
:class:`~swarmex.errors.InputError` "--agents: expected an integer, got 'three'", raised
before any work starts, and an unknown keyword names the nearest valid one. The parsers
name flags, as the command line needs; the Python surfaces (``swarmex.run`` and the others,
``Params.replace``, the environments) rename them to keywords with :func:`python_spelling`.
"""

from __future__ import annotations

import difflib
import math
import numbers
import re
from abc import ABC, abstractmethod
from collections.abc import Callable, Collection, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import MISSING, dataclass, field, fields, replace
from pathlib import Path
from typing import Any, ClassVar, Generic, Self, TypeVar

from swarmex.engine.record import MetricInfo, ResultRecord
from swarmex.errors import InputError

Parser = Callable[[Any, str], Any]  # (raw value, "--flag") -> typed value, or InputError
Cell = tuple[int, int]

REQUIRED: Any = MISSING  # the default of an option the user must give


class StopRun(Exception):  # noqa: N818 - a control-flow signal, not an error
    """Raised by an ``on_frame`` callback to end a run early (the record is then incomplete)."""


# ---------------------------------------------------------------------------- parsers


def integer(lo: int | None = None, hi: int | None = None) -> Parser:
    """Whole numbers: ``3``, ``"3"``; not ``3.5``, ``True`` or ``"three"``."""

    def parse(value: Any, flag: str) -> int:
        if isinstance(value, bool):
            raise InputError(f"{flag}: expected an integer, got {value!r}")
        whole_float = isinstance(value, float) and value.is_integer()
        digits = isinstance(value, str) and re.fullmatch(r"\s*[-+]?\d+\s*", value)
        if isinstance(value, numbers.Integral) or whole_float or digits:
            out = int(value)
        else:
            raise InputError(f"{flag}: expected an integer, got {value!r}")
        if lo is not None and out < lo:
            raise InputError(f"{flag} must be at least {lo}, got {out}")
        if hi is not None and out > hi:
            raise InputError(f"{flag} must be at most {hi}, got {out}")
        return out

    parse.kind = int  # type: ignore[attr-defined]
    return parse


def real(
    lo: float | None = None,
    *,
    above: float | None = None,
    hi: float | None = None,
    below: float | None = None,
    finite: bool = True,
) -> Parser:
    """Numbers: ``2.5``, ``"2.5"``; bounds ``lo <= x``, ``above < x``, ``x <= hi``, ``x < below``.

    NaN is always refused; infinity only with ``finite=False``.
    """

    def parse(value: Any, flag: str) -> float:
        if isinstance(value, bool):
            raise InputError(f"{flag}: expected a number, got {value!r}")
        try:
            out = float(value)
        except (TypeError, ValueError):
            raise InputError(f"{flag}: expected a number, got {value!r}") from None
        if math.isnan(out) or (finite and math.isinf(out)):
            what = "a finite number" if finite else "a number or inf"  # e.g. --comm-range
            raise InputError(f"{flag} must be {what}, got {value!r}")
        if lo is not None and out < lo:
            raise InputError(f"{flag} must be at least {lo:g}, got {out:g}")
        if above is not None and not out > above:
            raise InputError(f"{flag} must be greater than {above:g}, got {out:g}")
        if hi is not None and out > hi:
            raise InputError(f"{flag} must be at most {hi:g}, got {out:g}")
        if below is not None and not out < below:
            raise InputError(f"{flag} must be less than {below:g}, got {out:g}")
        return out

    parse.kind = float  # type: ignore[attr-defined]
    return parse


def text(choices: Sequence[str] | None = None, *, lower: bool = False) -> Parser:
    """Strings, optionally one of ``choices`` (the error lists them)."""

    def parse(value: Any, flag: str) -> str:
        if not isinstance(value, str):
            raise InputError(f"{flag}: expected text, got {value!r}")
        out = value.strip().lower() if lower else value
        if choices is not None and out not in choices:
            raise InputError(f"{flag} must be one of {', '.join(choices)}, got {value!r}")
        return out

    parse.kind = str  # type: ignore[attr-defined]
    parse.choices = tuple(choices) if choices else None  # type: ignore[attr-defined]
    return parse


def boolean() -> Parser:
    def parse(value: Any, flag: str) -> bool:
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.strip().lower() in ("true", "1", "yes", "on"):
            return True
        if isinstance(value, str) and value.strip().lower() in ("false", "0", "no", "off"):
            return False
        raise InputError(f"{flag}: expected true or false, got {value!r}")

    parse.kind = bool  # type: ignore[attr-defined]
    return parse


def path() -> Parser:
    def parse(value: Any, flag: str) -> Path:
        if isinstance(value, Path):
            return value
        if isinstance(value, str) and value.strip():
            return Path(value)
        raise InputError(f"{flag}: expected a file path, got {value!r}")

    parse.kind = Path  # type: ignore[attr-defined]
    return parse


def path_or(world_type: Callable[[], type | tuple[type, ...]], what: str) -> Parser:
    """A file path (str or Path), or an object of ``world_type()`` passed through as it is
    (a world built in Python). ``world_type`` imports its class only for a value that is not a
    path, so the CLI's options import no numpy; ``what`` names both forms in the error."""
    as_path = path()

    def parse(value: Any, flag: str) -> Any:
        if isinstance(value, str | Path):
            return as_path(value, flag)
        if isinstance(value, world_type()):
            return value
        raise InputError(f"{flag}: expected {what}, got {value!r}")

    parse.kind = Path  # type: ignore[attr-defined]
    return parse


def plain_sequence(value: Any) -> Any:
    """A numpy array as the nested list it holds (users pass arrays of cells); else as is."""
    tolist = getattr(value, "tolist", None)
    return tolist() if callable(tolist) and not isinstance(value, str) else value


_CELL = re.compile(r"^\s*(-?\d+)\s*,\s*(-?\d+)\s*$")


def _pair(value: Any, flag: str, what: str = "cell") -> Cell:
    value = plain_sequence(value)
    if isinstance(value, str):
        m = _CELL.match(value)
        if m:
            return int(m[1]), int(m[2])
    elif _is_int_pair(value):
        return int(value[0]), int(value[1])
    raise InputError(f'{flag}: malformed {what} {value!r} (expected "x,y" or (x, y))')


def cell() -> Parser:
    """One cell: ``"3,4"`` or ``(3, 4)``."""

    def parse(value: Any, flag: str) -> Cell:
        return _pair(value, flag)

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def _is_int_pair(value: Any) -> bool:
    return (isinstance(value, Sequence) and not isinstance(value, str) and len(value) == 2
            and all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in value))


def cells() -> Parser:
    """Cells: ``"1,2;3,4"``, ``["1,2", "3,4"]`` or ``[(1, 2), (3, 4)]`` -> a tuple of cells;
    one cell alone as ``(1, 2)`` too (a sweep axis of cells, ``nests = [[0, 0], [5, 5]]``,
    gives each run one such pair: "malformed cell 0" said nothing useful).

    Empty parts of a string (a trailing ``;``) are skipped.
    """

    def parse(value: Any, flag: str) -> tuple[Cell, ...]:
        value = plain_sequence(value)
        if isinstance(value, str):
            parts: Iterable[Any] = [p for p in value.split(";") if p.strip()]
        elif _is_int_pair(value):
            parts = [value]
        elif isinstance(value, Sequence):
            parts = value
        else:
            raise InputError(f'{flag}: expected cells "x,y;x,y;…", got {value!r}')
        out = []
        for p in parts:
            if isinstance(p, str):
                m = _CELL.match(p)
                if not m:
                    raise InputError(
                        f'{flag}: malformed cell {p.strip()!r} (expected "x,y;x,y;…")'
                    )
                out.append((int(m[1]), int(m[2])))
            else:
                out.append(_pair(p, flag))
        return tuple(out)

    parse.kind = str  # type: ignore[attr-defined]
    parse.many = True  # type: ignore[attr-defined]  # a list of values is one value
    return parse


Point = tuple[float, float]


def _coordinate(value: Any) -> float | None:
    """A finite coordinate from a number (not a bool) or its text, else None."""
    if isinstance(value, bool):
        return None
    try:
        out = float(value)
    except (TypeError, ValueError):
        return None
    return out if math.isfinite(out) else None


def _listed(value: Any) -> Any:
    """A numpy array as the plain list it holds (so arrays pass where sequences do)."""
    return value.tolist() if hasattr(value, "tolist") and hasattr(value, "ndim") else value


def _point(value: Any, flag: str) -> Point:
    """``"x,y"`` or ``(x, y)``, finite real coordinates, or an InputError naming ``flag``."""
    parts = value.split(",") if isinstance(value, str) else _listed(value)
    if isinstance(parts, Sequence) and len(parts) == 2:
        x, y = _coordinate(parts[0]), _coordinate(parts[1])
        if x is not None and y is not None:
            return x, y
    raise InputError(f"{flag}: malformed point {value!r} (expected finite 'x,y' or (x, y))")


def point() -> Parser:
    """One point of a continuous world: ``"1.5,2"`` or ``(1.5, 2)`` -> ``(1.5, 2.0)``."""

    def parse(value: Any, flag: str) -> Point:
        if isinstance(value, str) and ";" in value.strip().strip(";"):
            raise InputError(f"{flag} takes one 'x,y' point, got {value!r}")
        return _point(value.strip().strip(";") if isinstance(value, str) else value, flag)

    parse.kind = str  # type: ignore[attr-defined]
    return parse


def points() -> Parser:
    """Points: ``"1,2;3.5,4"`` or ``[(1, 2), (3.5, 4)]`` -> a non-empty tuple of points.

    Empty parts of a string (a trailing ``;``) are skipped.
    """

    def parse(value: Any, flag: str) -> tuple[Point, ...]:
        value = _listed(value)
        if isinstance(value, str):
            parts: Sequence[Any] = [p for p in value.split(";") if p.strip()]
        elif isinstance(value, Sequence):
            parts = value
        else:
            raise InputError(f"{flag}: expected points 'x,y;x,y;…', got {value!r}")
        if not parts:
            raise InputError(f"{flag}: no points given")
        return tuple(_point(p, flag) for p in parts)

    parse.kind = str  # type: ignore[attr-defined]
    parse.many = True  # type: ignore[attr-defined]
    return parse


def optional(inner: Parser) -> Parser:
    """``None`` stays ``None``; anything else goes through ``inner``."""

    def parse(value: Any, flag: str) -> Any:
        return None if value is None else inner(value, flag)

    parse.kind = getattr(inner, "kind", str)  # type: ignore[attr-defined]
    parse.choices = getattr(inner, "choices", None)  # type: ignore[attr-defined]
    parse.many = getattr(inner, "many", False)  # type: ignore[attr-defined]
    return parse


# ---------------------------------------------------------------------------- options


@dataclass(frozen=True)
class OptionInfo:
    """One parameter as the surfaces see it."""

    name: str  # "travel_time"
    flag: str  # "--travel-time"
    default: Any  # REQUIRED when the user must give it
    help: str
    parse: Parser
    negation: str | None = None  # "--no-aodv" for a boolean with an off switch
    metavar: str | None = None

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def kind(self) -> type:
        kind: type = getattr(self.parse, "kind", str)
        return kind

    @property
    def choices(self) -> tuple[str, ...] | None:
        return getattr(self.parse, "choices", None)

    @property
    def many(self) -> bool:
        """Whether one value is itself a list (cells, points): in a sweep spec such a list is
        an axis unless it sits in ``[fixed]``."""
        return bool(getattr(self.parse, "many", False))


def option(
    default: Any = REQUIRED,
    *,
    help: str,
    parse: Parser,
    flag: str | None = None,
    negation: str | None = None,
    metavar: str | None = None,
) -> Any:
    """Declare a Params field: its default, help line, parser and (optionally) CLI flag."""
    meta = {"help": help, "parse": parse, "flag": flag, "negation": negation, "metavar": metavar}
    if default is REQUIRED:
        return field(default=None, metadata={"swarmex": meta, "required": True})
    return field(default=default, metadata={"swarmex": meta, "required": False})


P = TypeVar("P", bound="Params")
# set on Params that went through the parsers and check() (not a field: equality, repr,
# asdict and the record ignore it)
_CHECKED = "_swarmex_checked"


@dataclass(frozen=True)
class Params:
    """Base of every mission's parameters: build with :meth:`from_values`, never invalid.

    Subclasses are frozen dataclasses whose fields are declared with :func:`option`, and
    override :meth:`check` for rules that tie fields together (no world needed).
    """

    mission: ClassVar[str] = ""
    #: groups of options of which one must be given (``(("map", "empty"),)``): checked with
    #: the required options, so that every missing one is named in the same line
    required_one_of: ClassVar[tuple[tuple[str, ...], ...]] = ()

    @classmethod
    def missing_groups(cls, given: Mapping[str, Any]) -> list[tuple[str, ...]]:
        """The groups of :attr:`required_one_of` of which ``given`` (option names with ``_``)
        sets none: what :meth:`from_values` and a sweep's spec check refuse."""
        return [group for group in cls.required_one_of
                if all(given.get(n) is None for n in group)]

    @classmethod
    def options(cls) -> dict[str, OptionInfo]:
        out = {}
        for f in fields(cls):
            meta = f.metadata.get("swarmex")
            if meta is None:
                continue
            out[f.name] = OptionInfo(
                name=f.name,
                flag=meta["flag"] or "--" + f.name.replace("_", "-"),
                default=REQUIRED if f.metadata.get("required") else f.default,
                help=meta["help"],
                parse=meta["parse"],
                negation=meta["negation"],
                metavar=meta["metavar"],
            )
        return out

    @classmethod
    def from_values(cls: type[P], values: Mapping[str, Any] | None = None, **kw: Any) -> P:
        """Parse and validate user values (CLI strings or Python values) into Params.

        Keys are the option names with ``-`` or ``_``. Raises InputError for an unknown key
        (naming the nearest valid one), a missing required option or a bad value.
        """
        raw = {**(values or {}), **kw}
        opts = cls.options()
        given: dict[str, Any] = {}
        for key, value in raw.items():
            name = str(key).replace("-", "_")
            if name not in opts:
                raise InputError(unknown_message(cls.mission, name, opts))
            if name in given:
                raise InputError(f"{opts[name].flag} is given twice")
            given[name] = value
        # every missing one in one line: roadmap's three used to come one error at a time
        missing = [info.flag for name, info in opts.items()
                   if info.required and given.get(name) is None]
        missing += [
            opts[group[0]].flag + f" (or {', '.join(opts[n].flag for n in group[1:])})"
            for group in cls.missing_groups(given)
        ]
        if missing:
            listed = ", ".join(missing[:-1]) + " and " + missing[-1] if missing[1:] else missing[0]
            raise InputError(
                f"{cls.mission}: {listed} {'are' if missing[1:] else 'is'} required"
            )
        parsed: dict[str, Any] = {}
        for name, info in opts.items():
            if name in given and given[name] is not None:
                parsed[name] = info.parse(given[name], info.flag)
            else:
                parsed[name] = info.default
        params = cls(**parsed)
        params.check()
        object.__setattr__(params, _CHECKED, True)
        return params

    def check(self) -> None:
        """Cross-field rules that need no world; raise InputError naming the option."""

    def ignored(self) -> dict[str, str]:
        """Options set to a value this run never reads (traversal's ``objective`` with an
        online policy), each with why: the command line prints a note, :func:`swarmex.run`
        warns. Not refused, because a sweep may hold the option at one value while it varies
        what reads it (madgta against optimal at ``objective = "makespan"``)."""
        return {}

    def replace(self, **changes: Any) -> Self:
        """A copy with ``changes`` (option names, CLI strings or Python values) parsed and
        checked as :meth:`from_values` does: ``params.replace(grid="12x12")``.

        Why not ``dataclasses.replace``: it calls the constructor, which runs no parser, so a
        CLI string stays a string where the run expects a tuple (:meth:`validated` catches it
        when the run starts, this catches it here). Fields that are not options (the
        simulator's own constants, e.g. exploration's ``plan_period``) are kept or replaced
        as given.
        """
        opts = self.options()
        own = {name: v for name, v in changes.items() if name.replace("-", "_") in opts}
        keep = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in opts}
        other = {name: v for name, v in changes.items() if name not in own}
        for name in other:
            if name not in keep:
                raise InputError(unknown_message(self.mission, name, opts))
        values = {name: v for name, v in self.values().items() if v is not None}
        for name, v in own.items():
            values[name.replace("-", "_")] = v
        with python_spelling(type(self)):  # a Python-only method: its errors name keywords
            out = type(self).from_values(values)
        rest = {**keep, **other}
        if rest:
            out = replace(out, **rest)
            object.__setattr__(out, _CHECKED, True)
        return out

    def validated(self) -> Self:
        """These parameters with every option's parser rerun on the value it holds and
        :meth:`check` applied: what :meth:`Mission.run` does before any work.

        Params made by :meth:`from_values` or :meth:`replace` are already valid and come back
        as they are. One built by its constructor or by ``dataclasses.replace`` skipped the
        parsers: ``replace(p, grid="12x12")`` used to reach the simulator with a string and
        fail there with "too many values to unpack"; now the string is parsed (to ``(12,
        12)``) and a bad value is an :class:`~swarmex.errors.InputError` naming the option.
        """
        if self.__dict__.get(_CHECKED):
            return self
        parsed: dict[str, Any] = {}
        for name, info in self.options().items():
            value = getattr(self, name)
            if value is None and info.required:
                raise InputError(f"{self.mission}: {info.flag} is required")
            if value is None and info.default is None:
                continue  # an optional option left unset
            parsed[name] = info.parse(value, info.flag)
        out = replace(self, **parsed)
        out.check()
        object.__setattr__(out, _CHECKED, True)
        return out

    @classmethod
    def describe(cls) -> str:
        """Every option, one per line: name, command-line flag, default (or "required") and
        help. What ``swarmex.describe(mission)`` prints and the class's own docstring ends
        with, so ``help(TraversalParams)`` shows what to pass."""
        lines = []
        for info in cls.options().values():
            if info.required:
                default = "required"
            elif info.default is None or info.default == ():
                default = "default: none"
            else:
                default = f"default {info.default!r}"
            lines.append(f"  {info.name} ({info.flag}; {default}): {info.help}")
        return "\n".join(lines)

    def values(self) -> dict[str, Any]:
        """The parameters as a plain dict (option name -> typed value)."""
        return {name: getattr(self, name) for name in self.options()}


# options of the mission commands that are outputs, not parameters of the run: a Python user
# who tries them is told the Python way (``render`` used to get "did you mean 'center'?")
COMMAND_ONLY = {
    "json": "the command line's record file; in Python, record.write(path) writes the same"
            " JSON",
    "render": "the command line's drawing; in Python, swarmex.render(record, path) draws"
              " the run a record holds",
    # PettingZoo's usual cap (its nearest name was "obstacles")
    "max_cycles": "there is no cycle cap; a run stops at its mission's own cap (foraging's"
                  " max_rounds, exploration's max_ticks, roadmap's step_budget, traversal's"
                  " event cap; docs/envs.md)",
}


def unknown_message(mission: str, name: str, opts: Mapping[str, Any]) -> str:
    """An unknown parameter's one line: the nearest valid name, or the valid names."""
    if name in COMMAND_ONLY and name not in opts:
        what = COMMAND_ONLY[name]
        return f"{mission or 'mission'}: {name!r} is not a parameter of the run: {what}"
    close = difflib.get_close_matches(name, list(opts), n=1, cutoff=0.5)
    hint = f"; did you mean {close[0]!r}?" if close else f" (valid: {', '.join(sorted(opts))})"
    return f"{mission or 'mission'}: unknown parameter {name!r}{hint}"


# a flag, and the metavar after it that only the command line needs (FILE, WxH, LAT,LON)
_FLAG = re.compile(r"(?<![\w-])(--[a-z][a-z0-9]*(?:-[a-z0-9]+)*)"
                   r"( (?:[A-Z]+x[A-Z]+|[A-Z][A-Z_]+(?:,[A-Z][A-Z_]+)*)\b)?")


@contextmanager
def python_spelling(*params_types: type[Params]) -> Iterator[None]:
    """Inside, an :class:`InputError` names options as the Python keywords the caller
    wrote (``job_time``), not as command-line flags (``--job-time``).

    Why at the Python surfaces only: the parsers and checks are shared with the command
    line, which needs its flags; ``swarmex.run(..., job_time=-2)`` answered "--job-time
    must be at least 0", a name the caller cannot write in Python. The message is rewritten
    in place (same exception object, type and attributes); a flag none of ``params_types``
    declares stays as it is. :func:`swarmex.missions.registry.any_python_spelling` does this
    for every registered mission (a record's mission is known only once it is read)."""
    try:
        yield
    except InputError as exc:
        rename_flags(exc, params_types)
        raise


def rename_flags(exc: InputError, params_types: Iterable[type[Params]]) -> None:
    """Rewrite ``exc``'s message in place: each flag of ``params_types``'s options as its
    keyword, without the metavar after it (``--map FILE`` -> ``map``)."""
    if not exc.args or not isinstance(exc.args[0], str) or "--" not in exc.args[0]:
        return
    keyword = {"--seed": "seed"}
    for params_type in params_types:
        keyword.update({info.flag: name for name, info in params_type.options().items()})
    exc.args = (_FLAG.sub(lambda m: keyword.get(m[1], m[0]), exc.args[0]), *exc.args[1:])


# ---------------------------------------------------------------------------- missions


@dataclass
class Outcome:
    """What a run leaves: the record every surface reads, plus the in-memory run object the
    renderers draw (it holds arrays the record does not, e.g. exploration's final maps)."""

    record: ResultRecord
    run: Any = None
    world: Any = None


FrameCallback = Callable[[Any], Any]


def check_seed(seed: Any) -> None:
    """A run's seed must be given: ``None`` is numpy's "fresh entropy", and the seed
    option's parser would silently read it as its default 0."""
    if seed is None:
        raise InputError("seed=None: every swarmex run is reproducible; give an integer >= 0")


def check_run_options(on_frame: Any, trace: Any) -> None:
    """``on_frame`` and ``trace`` as :meth:`Mission.run` takes them, else an InputError before
    any work. Why: ``on_frame=5`` was a TypeError from the first frame, after the world was
    built, and ``trace="false"`` (truthy) silently kept the trace."""
    if on_frame is not None and not callable(on_frame):
        raise InputError(f"on_frame must be a function of one frame (or None), got {on_frame!r}")
    if not isinstance(trace, bool):
        raise InputError(f"trace must be True or False, got {trace!r}")


@dataclass(frozen=True)
class ProgressSpec:
    """A run's progress as its frames tell it: ``count(frame)`` of ``total`` ``unit``."""

    total: int
    unit: str
    count: Callable[[Any], int]


class FrameList(list[Any]):
    """An ``on_frame`` callback that keeps every frame, in order: what ``--render`` draws
    (the same objects ``swarmex.run(..., on_frame=...)`` hands a notebook)."""

    def __call__(self, frame: Any) -> None:
        self.append(frame)

    @property
    def frames(self) -> list[Any]:
        return self
W = TypeVar("W")

#: Numbers every record has besides its mission's metrics (sweep table columns).
RECORD_NUMBERS = ("complete", "makespan", "wall_seconds")


class Mission(ABC, Generic[P, W]):
    """One mission behind the contract. Subclasses set the class attributes and implement
    :meth:`prepare` and :meth:`execute`.

    * :meth:`prepare` does every check that needs the world (map files, start cells, team
      size against free cells) and returns the prepared world; it must raise InputError
      *before* any long work.
    * :meth:`execute` runs and records; ``on_frame`` (if given) is called with the run's
      frames as they happen, the objects that ``--render`` and the monitor draw; raising
      :class:`StopRun` from it ends the run early.

    ``trace=False`` asks for a record without the per-step trace: every team metric is the
    same, but each agent's ``trajectory`` and ``jobs`` are empty and a per-agent metric that
    only the trace gives is None (:func:`~swarmex.engine.record.without_trace`). Studies of
    thousands of runs read only metrics, and a mission may then skip the trace's work and
    memory (foraging does not keep its per-round positions).
    """

    name: ClassVar[str]  # "traversal"
    command: ClassVar[str]  # "traverse"
    summary: ClassVar[str]  # one line for --help
    params_type: ClassVar[type[Params]]
    time_unit: ClassVar[str]
    #: For :meth:`rerun_values`: a recorded parameter -> the parameters whose override
    #: makes it stale. A record holds what the run used, derived values included (nests and
    #: starts per agent, a drawn food cell) and one of each set of alternatives (``map`` or
    #: ``grid``): overriding the world or the team must not keep the old world's starts, nor
    #: pass ``grid`` beside a new ``map``. A stale value is left out (its default, derived
    #: again), unless the caller gives it too.
    rerun_replaces: ClassVar[Mapping[str, Collection[str]]] = {}
    #: The options that name the world. A record whose params say ``"generated"`` (the
    #: world was given as an object, which no record can name) reruns only with one of them
    #: given again; :meth:`rerun_values` asks for it.
    world_options: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kw: Any) -> None:
        """Give the mission and its Params docstrings that list the parameters, so that
        ``help()`` on either tells a user what to pass (a dataclass's own docstring is only
        its constructor's signature, which runs no parser)."""
        super().__init_subclass__(**kw)
        ptype = cls.__dict__.get("params_type")
        name = getattr(cls, "name", None)
        if ptype is None or name is None:
            return  # an abstract intermediate class, or a plugin that sets them later
        command = getattr(cls, "command", name)
        listing = (f"Parameters (``swarmex.run({name!r}, ...)``, "
                   f"``swarmex {command}``):\n\n{ptype.describe()}")
        if cls.__doc__ is None:
            cls.__doc__ = (f"The {name} mission (``swarmex {command}``): "
                           f"{getattr(cls, 'summary', '')}\n\n{listing}")
        own = ptype.__doc__ or ""
        if own.startswith(ptype.__name__ + "("):  # the dataclass's generated signature
            ptype.__doc__ = (f"Parameters of the {name} mission: build them with "
                             f"``{ptype.__name__}.from_values(...)`` (or "
                             f"``registry.get({name!r}).params(...)``), copy them with "
                             f"``.replace(...)``; both parse and check.\n\n{listing}")

    def rerun_values(
        self, record: ResultRecord, given: Collection[str] = ()
    ) -> dict[str, Any]:
        """The parameters that run ``record`` again (with its seed): its ``params`` that are
        options of this mission, seed aside. ``given`` names the parameters the caller
        passes itself (they win, and need not be recoverable from the record); a recorded
        value they make stale (:attr:`rerun_replaces`) is left out.

        Why a hook: a record's params are what the run *used*, which is not always what a
        user passes (derived values, other units, the world kept in ``record.world``);
        a mission whose record differs from its options translates here. A record whose
        world was given as an object cannot name it: then an InputError asks for it.
        """
        opts = self.params_type.options()
        overridden = set(given)
        if "generated" in record.params and self.world_options and not (
            overridden & set(self.world_options)
        ):
            raise InputError(
                f"this record's world was given as an object ({record.params['generated']}):"
                f" pass it again from Python, e.g. swarmex.rerun(record,"
                f" {self.world_options[0]}=world) or swarmex.render(record, out,"
                f" {self.world_options[0]}=world) (from the shell: save the world to a file"
                f" and run on that)"
            )
        stale = {k for k, inputs in self.rerun_replaces.items() if overridden & set(inputs)}
        return {
            k: v
            for k, v in record.params.items()
            if k in opts and k != "seed" and k not in overridden and k not in stale
        }

    def progress(self, params: P, world: W) -> ProgressSpec | None:
        """What a progress bar of a run on ``world`` counts, from its frames (None: no bar;
        the default). The command line's bar and ``swarmex.run(progress=True)`` read it."""
        return None

    def team_metrics(self) -> Mapping[str, MetricInfo]:
        """The team metrics this mission's records hold (``record.metrics``): name → meaning.

        A method, not a class attribute, so that the declaration can live beside the code
        that computes the metrics, imported only when asked for. Empty for a mission that
        declares none (a plugin): then no name can be checked before a run.
        """
        return {}

    def check_metric(self, name: str, where: str = "--metric") -> None:
        """Raise InputError unless ``name`` is a numeric metric of this mission's records:
        a team metric (or ``metrics.NAME``, the sweep column of one whose name a parameter
        took), ``complete``, ``makespan`` or ``wall_seconds``, or an entry ``NAME.KEY`` of a
        table metric (a sweep flattens tables into such columns: ``unicasts.sent``; its keys
        are checked when the mission declares them). For checking a name before any run; it
        checks nothing when the mission declares no metrics."""
        declared = self.team_metrics()
        if not declared:
            return
        bare = name.removeprefix("metrics.")
        info = declared.get(bare)
        if name in RECORD_NUMBERS or (info is not None and info.numeric):
            return
        head, _, key = bare.partition(".")
        table = declared.get(head)
        if key and table is not None and not table.numeric:
            if not table.keys or key in table.keys:
                return
            close = difflib.get_close_matches(key, table.keys, n=1, cutoff=0.6)
            hint = f"did you mean '{head}.{close[0]}'? " if close else ""
            raise InputError(
                f"{where} {name!r}: {head} has no entry {key!r} ({hint}have:"
                f" {', '.join(table.keys)})"
            )
        if info is not None:
            article = "an" if self.name[:1] in "aeiou" else "a"
            raise InputError(
                f"{where} {name!r}: {article} {self.name} record holds it as a list or a"
                f" table per run, which has no mean; pick a number"
                + ("" if not info.keys else f" (its entries are sweep columns {bare}.KEY)")
            )
        known = [*RECORD_NUMBERS, *(k for k, v in declared.items() if v.numeric)]
        close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise InputError(
            f"{where} {name!r}: not a metric of {self.name} records ({hint}have:"
            f" {', '.join(known)})"
        )

    def params(self, values: Mapping[str, Any] | None = None, **kw: Any) -> P:
        """Parse and check ``values`` (CLI strings or Python values) into this mission's
        frozen Params (:meth:`Params.from_values`); an InputError names a bad one."""
        return self.params_type.from_values(values, **kw)  # type: ignore[return-value]

    @abstractmethod
    def prepare(self, params: P) -> W:
        """The world the run happens in, with every world-dependent check done."""

    @abstractmethod
    def execute(
        self,
        params: P,
        world: W,
        on_frame: FrameCallback | None = None,
        *,
        trace: bool = True,
    ) -> Outcome:
        """Run the mission on a prepared world and build its record (without the per-step
        trace when ``trace`` is false)."""

    def run(
        self, params: P, on_frame: FrameCallback | None = None, *, trace: bool = True,
        interpreted: Callable[[P, W], bool] | None = None,
        watch: Callable[[P, W, FrameCallback | None], FrameCallback | None] | None = None,
    ) -> Outcome:
        """Prepare the world and execute: the whole run, as ``swarmex.run`` does it. Params
        that skipped the parsers (built by their constructor) are parsed and checked first.
        ``interpreted`` (params, prepared world) -> whether this run is small enough to keep
        its kernels interpreted while numba is cold (a CLI command's rule, which
        ``swarmex rerun`` applies to a record's run too); the record is the same either way.
        ``watch`` (params, prepared world, on_frame) -> the callback to run with instead, one
        that also shows how far the run is (a CLI command's progress bar, which ``swarmex
        rerun`` and ``render`` show too); closed after the run if it has ``close()``."""
        from swarmex._kernels import interpreted_while_cold

        check_run_options(on_frame, trace)
        if not isinstance(params, self.params_type):  # a dict, None, another mission's
            raise InputError(
                f"{self.name}: run() takes {self.params_type.__name__} (from"
                f" get({self.name!r}).params(...)), got {type(params).__name__}"
            )
        params = params.validated()  # Params built by their constructor skipped the parsers
        world = self.prepare(params)
        callback = on_frame if watch is None else watch(params, world, on_frame)
        try:
            with interpreted_while_cold(interpreted is not None and interpreted(params, world)):
                return self.execute(params, world, callback, trace=trace)
        finally:
            close = getattr(callback, "close", None) if callback is not on_frame else None
            if close is not None:
                close()
