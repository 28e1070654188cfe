"""Sweep specifications: a mission, its options as axes, and seeds; the product is the sweep.

A spec is a scenario file (:mod:`swarmex.experiments.scenario`) in which a *list is an axis*::

    mission = "traversal"          # traversal | foraging | exploration | roadmap
    algorithm = ["madgta", "nearest"]
    grid = ["8x8", "12x12"]        # any option of the mission's command
    agents = [2, 4]
    job-time = 10.0                # a scalar is a fixed value (still a column)
    seeds = [0, 1, 2]              # or seeds = 10 for 0..9

    [fixed]                        # options whose single value is itself a list
    obstacles = ["3,2", "3,3"]

Why a list always means an axis: a sweep is read far more often as "these values" than as
"this list-valued option", and a rule without exceptions cannot be misread. Options whose value
is a list (``obstacles``, ``nests``) go in ``[fixed]`` or are written as one string
(``"3,2;3,3"``). ``algorithm`` is passed to whichever option of the mission's command names the
algorithm (``--algorithm``, ``--strategy`` for exploration, ``--planner`` for roadmap), and its
column is still called ``algorithm``.

The runs are the product of the axes in file order with the seeds innermost, so the order, and
each run's id (a hash of mission, parameters and seed, independent of position), are the same
every time the spec is read: that is what lets an interrupted sweep resume. A parameter that
names a file (``map``, ``env``, ``fleet``) enters the id with the content of the file it
resolves to (from the spec's folder), not only as written: two specs in different folders
with the same ``map = "m.map"`` are different runs, and a map edited in place is run again
rather than answered by the old map's records.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike, fspath
from pathlib import Path
from typing import Any

from swarmex.errors import InputError
from swarmex.experiments.scenario import (
    MISSIONS,
    OptionShape,
    Scenario,
    check_mission,
    mission_shapes,
    read_toml,
    resolve_path,
    scenario_values,
)

# columns the sweep itself writes; a spec key may not take one of these names
RESERVED = ("run", "seed", "complete", "makespan", "time_unit", "wall_seconds", "error")
# options the sweep sets itself: every run writes its own record, and draws nothing
FORBIDDEN = ("json", "render", "seed")
# which command option receives the spec's ``algorithm``, by preference
ALGORITHM_OPTIONS = ("algorithm", "strategy", "planner")


#: runs a sweep may have: a million records is already a folder few file systems enjoy
MAX_RUNS = 1_000_000


@dataclass(frozen=True)
class RunSpec:
    """One run of a sweep: its place in the product, its id and what it sets."""

    index: int
    run_id: str
    params: dict[str, Any]  # spec key (as written) -> value, without the seed
    seed: int


@dataclass(frozen=True)
class SweepSpec:
    path: Path
    mission: str
    axes: dict[str, list[Any]]  # spec key -> values; a scalar key is a one-value axis
    fixed: dict[str, Any]  # the [fixed] table: passed as is
    seeds: list[int]

    @property
    def command(self) -> str:
        return MISSIONS[self.mission]

    @property
    def param_names(self) -> list[str]:
        """Parameter columns, in file order: axes, then the [fixed] keys."""
        return [*self.axes, *self.fixed]

    def runs(self) -> list[RunSpec]:
        """Every run: the product of the axes in file order, seeds innermost."""
        names = list(self.axes)
        out: list[RunSpec] = []
        files = InputFiles(self.mission, self.path.parent)
        for values in itertools.product(*self.axes.values()):
            params = dict(zip(names, values, strict=True)) | self.fixed
            inputs = files.digests(params)
            for seed in self.seeds:
                out.append(RunSpec(len(out), run_id(self.mission, params, seed, inputs),
                                   params, seed))
        return out

    def values(self, run: RunSpec, shapes: dict[str, OptionShape]) -> dict[str, Any]:
        """The mission parameters of ``run``, for ``Mission.params`` (no argv in between).

        Built by :func:`~swarmex.experiments.scenario.scenario_values`, so relative paths are
        taken from the spec's folder, and checked for required options before anything runs.
        """
        options: dict[str, Any] = {}
        given = {key.replace("_", "-") for key in run.params}
        for key, value in run.params.items():
            name = key.replace("_", "-")
            if name == "algorithm":
                name = algorithm_option(shapes, self.path, self.command)
                if name != "algorithm" and name in given:
                    # both name the same option: one silently won, and the table's column
                    # of the other one named an algorithm that never ran
                    raise InputError(
                        f"{self.path}: algorithm and {name} are the same option of swarmex"
                        f" {self.command} (--{name}); give one of them"
                    )
            options[name] = value
        options["seed"] = run.seed
        missing = [n for n, shape in shapes.items() if shape.required and n not in options]
        if missing:  # before anything runs: otherwise every run would fail the same way
            wanted = ", ".join(f"{n} = …" for n in missing)
            raise InputError(
                f"{self.path}: swarmex {self.command} needs"
                f" {', '.join('--' + n for n in missing)}; add {wanted} to the spec"
            )
        values = scenario_values(Scenario(self.path, self.mission, options), shapes)
        from swarmex.missions.registry import get

        for group in get(self.mission).params_type.missing_groups(values):  # map, grid, center
            names = [n.replace("_", "-") for n in group]
            if all(n in shapes for n in names):
                raise InputError(
                    f"{self.path}: swarmex {self.command} needs"
                    f" {' or '.join('--' + n for n in names)}; add one of"
                    f" {', '.join(f'{n} = …' for n in names)} to the spec"
                )
        for name, shape in shapes.items():
            file = values.get(name.replace("-", "_"))
            if shape.is_path and isinstance(file, Path) and not file.exists():
                # before anything runs: otherwise every run with it fails, one error file each
                raise InputError(f"{self.path}: {name} = {file}: no such file")
        return values


def listed_axes(spec: SweepSpec) -> list[tuple[str, int]]:
    """The axes, with their value counts, of an option whose one value is itself a list
    (obstacles, nests): by the spec's rule each element is one run's whole value, which is
    seldom meant (a scenario file's ``obstacles = [...]`` swept as a spec gave 8 runs of one
    wall cell each). Each surface says so in its own words."""
    from swarmex.missions.registry import get

    options = get(spec.mission).params_type.options()
    return [(key, len(values)) for key, values in spec.axes.items()
            if len(values) > 1 and getattr(options.get(key.replace("-", "_")), "many", False)]


def always_ignored(spec: SweepSpec, limit: int = 1000) -> list[tuple[str, str]]:
    """The options every run of ``spec`` sets to a value it never reads, each with why
    (``Params.ignored``: traversal's ``objective`` when no run is ``optimal``). A single run
    says so on the command line; a sweep said nothing, and its table then held a column that
    meant nothing. Checked on the configurations (seeds aside), at most ``limit`` of them: a
    larger product says nothing rather than parse them all; a configuration whose values
    fail to parse (a failed row later) is passed over."""
    from swarmex.missions.registry import get

    mission = get(spec.mission)
    shapes = mission_shapes(spec.mission)
    names = list(spec.axes)
    common: set[str] | None = None
    why: dict[str, str] = {}
    for i, values in enumerate(itertools.product(*spec.axes.values())):
        if i >= limit:
            return []
        raw = dict(zip(names, values, strict=True)) | spec.fixed
        try:  # as the runs read the spec: its algorithm key names the mission's option
            params = mission.params(spec.values(RunSpec(i, "", raw, spec.seeds[0]), shapes))
        except InputError:
            continue
        ignored = params.ignored()
        common = set(ignored) if common is None else common & set(ignored)
        why.update(ignored)
        if not common:
            return []
    return [(name, why[name]) for name in sorted(common or ())]


def run_id(
    mission: str, params: dict[str, Any], seed: int, inputs: Mapping[str, str] | None = None
) -> str:
    """A stable id of a run from what it computes (not where it sits in the product).

    ``inputs`` are the content digests of the files its parameters name
    (:class:`InputFiles`): the same text ``map = "m.map"`` in two folders, or a map edited
    since, is a different run. A run that names no file has the id it always had."""
    data: dict[str, Any] = {"mission": mission, "params": params, "seed": seed}
    if inputs:
        data["inputs"] = dict(inputs)
    text = json.dumps(data, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class InputFiles:
    """Content digests of the files a run's parameters name, each file read once per spec.

    Which parameters name files is read off the mission's options (their kind is a path);
    a relative path is taken from ``folder`` (the spec's), as the run takes it. A ROS map's
    YAML counts with the image it names. A file that cannot be read has no digest (the
    run's own check then refuses it before any run)."""

    def __init__(self, mission: str, folder: Path) -> None:
        self.folder = folder
        self.cache: dict[Path, str | None] = {}
        try:
            shapes = mission_shapes(mission)
        except InputError:  # a plugin mission no longer installed: no file is known
            shapes = {}
        self.names = {name for name, shape in shapes.items() if shape.is_path}

    def digests(self, params: Mapping[str, Any]) -> dict[str, str]:
        out: dict[str, str] = {}
        for key, value in params.items():
            if key.replace("_", "-") in self.names and isinstance(value, str):
                digest = self.digest(resolve_path(self.folder, value))
                if digest is not None:
                    out[key] = digest
        return out

    def digest(self, path: Path) -> str | None:
        if path not in self.cache:
            from swarmex.worlds.rosmap import rosmap_image

            h = hashlib.sha256()
            try:
                for part in (path, rosmap_image(path)):
                    if part is not None:
                        with open(part, "rb") as f:
                            h.update(hashlib.file_digest(f, "sha256").digest())
                self.cache[path] = h.hexdigest()
            except OSError:
                self.cache[path] = None
        return self.cache[path]


def algorithm_option(shapes: dict[str, OptionShape], path: Path, command: str) -> str:
    for name in ALGORITHM_OPTIONS:
        if name in shapes:
            return name
    raise InputError(f"{path}: swarmex {command} has no algorithm option")


def load_sweep_spec(path: str | Path) -> SweepSpec:
    """Read and check a spec; every problem is an InputError naming the file and the key."""
    path = Path(path)
    return parse_sweep_spec(read_toml(path, "sweep spec"), path)


def parse_sweep_spec(data: dict[str, Any], path: Path) -> SweepSpec:
    data = dict(data)
    mission = check_mission(data.pop("mission", None), path)
    seeds = _seeds(path, data.pop("seeds", None), data.pop("seed", None))
    fixed = data.pop("fixed", {})
    if not isinstance(fixed, dict):
        raise InputError(f"{path}: fixed must be a table ([fixed])")
    axes: dict[str, list[Any]] = {}
    for key, value in data.items():
        if isinstance(value, dict):
            raise InputError(f"{path}: unknown table [{key}] (only [fixed] is allowed)")
        values = value if isinstance(value, list) else [value]
        if not values:
            raise InputError(f"{path}: axis {key!r} has no values")
        _check_values(path, key, values)
        axes[key] = values
    for key, value in fixed.items():
        _check_values(path, key, [value])
    _check_names(path, [*axes, *fixed])
    _check_same_values(path, mission, axes)
    total = math.prod(len(v) for v in axes.values()) * len(seeds)
    if total > MAX_RUNS:  # before a list of them fills the memory (seeds = 100000000: 4 GB)
        raise InputError(f"{path}: {total:,} runs; a sweep has at most {MAX_RUNS:,} (split it"
                         " into several, or give fewer seeds or values)")
    return SweepSpec(path, mission, axes, dict(fixed), seeds)


def _seeds(path: Path, seeds: Any, seed: Any) -> list[int]:
    if seeds is not None and seed is not None:
        raise InputError(f"{path}: give seeds or seed, not both")
    value = seeds if seeds is not None else seed
    if value is None:
        return [0]
    if isinstance(value, int) and not isinstance(value, bool):
        if seeds is not None:  # seeds = N: the first N seeds
            if value < 1:
                raise InputError(f"{path}: seeds = {value}: need at least one seed")
            if value > MAX_RUNS:
                raise InputError(f"{path}: seeds = {value:,}: a sweep has at most"
                                 f" {MAX_RUNS:,} runs")
            return list(range(value))
        _non_negative(path, [value])
        return [value]
    if (
        isinstance(value, list)
        and value
        and all(isinstance(s, int) and not isinstance(s, bool) for s in value)
    ):
        if len(set(value)) != len(value):
            raise InputError(f"{path}: seeds lists a seed twice")
        _non_negative(path, value)
        return list(value)
    raise InputError(f"{path}: seeds must be a list of integers or a count, got {value!r}")


def _non_negative(path: Path, seeds: list[int]) -> None:
    """Seeds are numpy seeds, which cannot be negative: refuse them before any run, or every
    run with one fails (each with numpy's "expected non-negative integer")."""
    negative = [s for s in seeds if s < 0]
    if negative:
        raise InputError(f"{path}: seeds must be >= 0, got {negative[0]}")


def _check_values(path: Path, key: str, values: list[Any]) -> None:
    scalar = (str, int, float, bool)
    texts = []
    for v in values:
        ok = isinstance(v, scalar) or (
            isinstance(v, list)
            and all(
                isinstance(c, scalar)
                or (isinstance(c, list) and all(isinstance(e, int | float) for e in c))
                for c in v
            )
        )
        if not ok:
            raise InputError(f"{path}: {key!r} has an unsupported value {v!r}")
        texts.append(json.dumps(v, sort_keys=True))
    if len(set(texts)) != len(texts):
        raise InputError(f"{path}: axis {key!r} lists a value twice")


def _check_same_values(path: Path, mission: str, axes: dict[str, list[Any]]) -> None:
    """An axis whose values differ as written but parse to one value (``agents = [2, 2.0,
    "2"]``) would run the same runs under different ids, and its column would mix types:
    refused as a value listed twice. A file option is compared by the path the runs read
    (relative to the spec's folder), not parsed here; a value that does not parse is its
    run's error. (A spec's ``algorithm`` key for planner or strategy is not looked up: their
    names have no second spelling.)"""
    from swarmex.missions.registry import get

    opts = get(mission).params_type.options()
    for key, values in axes.items():
        opt = opts.get(key.replace("-", "_"))
        if opt is None or len(values) < 2:
            continue
        seen: dict[str, Any] = {}
        for value in values:
            if opt.kind is Path:
                parsed = (repr(resolve_path(path.parent, value).resolve())
                          if isinstance(value, str) else json.dumps(value, sort_keys=True))
            else:
                try:
                    parsed = repr(opt.parse(value, opt.flag))
                except InputError:
                    continue
            if parsed in seen:
                raise InputError(f"{path}: axis {key!r} lists one value twice ({seen[parsed]!r}"
                                 f" and {value!r})")
            seen[parsed] = value


def _check_names(path: Path, keys: list[str]) -> None:
    seen: dict[str, str] = {}
    for key in keys:
        name = key.replace("_", "-")
        if key in RESERVED or name in FORBIDDEN:
            raise InputError(f"{path}: {key!r} cannot be set in a sweep (the sweep sets it)")
        if name in seen:
            raise InputError(f"{path}: option {name!r} is given twice ({seen[name]!r}, {key!r})")
        seen[name] = key


def spec_from_keywords(
    mission: str, seeds: Any, fixed: Mapping[str, Any], axes: Mapping[str, Any]
) -> SweepSpec:
    """The spec of :func:`swarmex.sweep`'s keywords, as a TOML spec would hold them: a list
    (or range) is an axis, a tuple one shared value (``grid=(8, 8)``), None the default (left
    out, as in :func:`swarmex.run`); ``fixed`` holds shared values that are lists. Checked by
    :func:`parse_sweep_spec`, errors named ``swarmex.sweep`` and its keywords (not the
    command line's options)."""
    _check_keywords(mission, {**fixed, **{k: v for k, v in axes.items() if v is not None}})
    data: dict[str, Any] = {"mission": mission, "seeds": _spec_value(seeds, "seeds")}
    shared = {k: _spec_value(v, k) for k, v in fixed.items()}
    for key, value in axes.items():
        if value is None:
            continue
        if isinstance(value, tuple):
            shared[key] = _spec_value(value, key)
        else:
            data[key] = _spec_value(value, key)
    if shared:
        data["fixed"] = shared
    return parse_sweep_spec(data, Path("swarmex.sweep"))


def _check_keywords(mission: Any, keywords: Mapping[str, Any]) -> None:
    """Each keyword of :func:`swarmex.sweep` must be a parameter of :func:`swarmex.run`
    (``algorithm`` always is); the errors are those of ``swarmex.run`` (the nearest name),
    not the command line's "has no option --job-tim". ``seed`` is refused in its own words:
    the sweep sets it run by run from ``seeds``."""
    from swarmex.missions.base import unknown_message
    from swarmex.missions.registry import get

    if not isinstance(mission, str) or mission not in MISSIONS:
        return  # parse_sweep_spec names the mission
    opts = get(mission).params_type.options()
    for key, value in keywords.items():
        name = str(key).replace("-", "_")
        if name == "seed":
            one = value if isinstance(value, int) and not isinstance(value, bool) else "N"
            raise InputError(
                f"swarmex.sweep: {key}={value!r}: a sweep's seeds are given by seeds= (a count"
                f" N for the first N, or a list): give seeds=[{one}]"
            )
        if name != "algorithm" and name not in opts:
            raise InputError(f"swarmex.sweep: {unknown_message(mission, name, opts)}")


def _spec_value(value: Any, key: str) -> Any:
    """A Python value as a sweep spec holds it (TOML's types): paths as text, tuples and
    ranges as lists. A world object cannot be swept: runs are named by their values' JSON."""
    if isinstance(value, PathLike):
        return fspath(value)
    if isinstance(value, tuple | list | range):
        return [_spec_value(v, key) for v in value]
    if isinstance(value, Mapping):  # a spec value is never a table (runs are named by them)
        raise InputError(
            f"swarmex.sweep: {key}: a dict cannot be a sweep value; give it as a file (a"
            f" fleet: fleet='fleet.toml', its [[agents]] tables)"
        )
    if isinstance(value, str | int | float | bool):
        return value
    if value is None:
        raise InputError(
            f"swarmex.sweep: {key}: None cannot be one of a sweep's values (a spec is TOML,"
            " which has no null); leave the parameter out for its default"
        )
    tolist = getattr(value, "tolist", None)  # numpy scalars and arrays
    if callable(tolist):
        return _spec_value(tolist(), key)
    raise InputError(
        f"swarmex.sweep: {key}={value!r} cannot be swept (give a file path, or use swarmex.run"
        " for a world object)"
    )


