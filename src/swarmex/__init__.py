"""swarmex: teams of agents that explore, cover and search unknown environments.

The public API is small and explicit::

    import swarmex
    swarmex.missions()                 # ['exploration', 'foraging', 'roadmap', 'traversal']
    rec = swarmex.run("foraging", grid=128, agents=16, algorithm="sectors", seed=3)
    rec.to_dict()                      # == the JSON of `swarmex forage ... --seed 3 --json`
    swarmex.rerun(rec)                 # the same record again (also from a record file)
    swarmex.render(rec, "run.gif")     # draw it: .png picture, .gif/.mp4 animation
    swarmex.compare(table, {"algorithm": "madgta"})  # a sweep's paired differences

The package is organised as a simulation core (``worlds``, ``sensing``, ``planning``,
``comm``, ``engine``), the four missions behind one contract (``missions``), and the
surfaces built on it (``net``, ``envs``, ``viz``, ``experiments``, ``studies``, ``cli``).
Heavy modules are imported only when a mission first runs, so ``import swarmex`` is cheap.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from os import PathLike, fspath
from pathlib import Path
from typing import TYPE_CHECKING, Any

import swarmex.missions as _missions_package  # before `missions` below
from swarmex._jitcache import ensure_cache_dir as _ensure_cache_dir
from swarmex.errors import InputError

_ensure_cache_dir()  # before any kernel module imports numba: cache=True must not fail

if TYPE_CHECKING:
    from swarmex.engine.record import ResultRecord
    from swarmex.missions.base import StopRun

__version__ = "0.1.0"
__all__ = [
    "InputError", "ResultRecord", "StopRun", "__version__", "compare", "describe", "missions",
    "plot", "render", "rerun", "run", "sweep",
]


class _Missions:
    """``swarmex.missions()``: the registered mission names (built-in and from installed
    plugins), sorted. ``swarmex.missions.NAME``: the subpackage ``swarmex.missions``'s
    module NAME (``swarmex.missions.registry``, ``swarmex.missions.base``,
    ``swarmex.missions.traversal``), imported on first use.

    Why an object and not a plain function: the package's ``missions`` attribute cannot be
    both the function and the subpackage, and as a function it hid the subpackage, so the
    documented dotted names failed: ``swarmex.missions.registry.get`` was an AttributeError
    ("'function' object has no attribute 'registry'") and ``import
    swarmex.missions.base as b`` an ImportError, even after importing the module.
    """

    __slots__ = ()

    def __call__(self) -> list[str]:
        from swarmex.missions.registry import names

        return names()

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):  # no dunder of the module (help, pickle, inspect probe them)
            raise AttributeError(name)
        try:
            return getattr(_missions_package, name)
        except AttributeError:
            pass
        try:
            return importlib.import_module(f"swarmex.missions.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"swarmex.missions.{name}":
                raise  # the module exists and one of its imports is missing: say that
        raise AttributeError(f"swarmex.missions has no attribute or module {name!r}")

    def __dir__(self) -> list[str]:
        return sorted(n for n in vars(_missions_package) if not n.startswith("_"))

    def __repr__(self) -> str:
        return "<swarmex.missions: call it for the mission names; attributes: the subpackage>"


# the subpackage swarmex.missions is imported above, first, so that this object and not the
# subpackage is the package's ``missions`` attribute (an import of a module already loaded
# does not set its parent's attribute again)
missions = _Missions()


def run(
    mission: str,
    *,
    seed: int = 0,
    on_frame: Callable[[Any], Any] | None = None,
    trace: bool = True,
    progress: bool = False,
    **params: Any,
) -> ResultRecord:
    """Run one mission and return its result record.

    ``mission`` is one of :func:`missions` (``"traversal"``, ``"foraging"``,
    ``"exploration"``, ``"roadmap"``, and any installed plugin's). ``params`` are the mission
    command's options with ``-`` written ``_`` (``travel_time``, ``food_units``,
    ``laser_range``, ...); ``print(swarmex.describe("traversal"))`` lists a mission's
    parameters with their defaults and meaning (docs/api.md has the same tables). Values may
    be the CLI's strings or plain Python values (``grid="12x12"`` or ``grid=(12, 12)``,
    ``nests=[(1, 2), (3, 4)]``, ``map=Path(...)``). For example::

        rec = swarmex.run("traversal", grid="12x12", agents=4, seed=3)
        rec.complete, rec.makespan, rec.metrics["total_time_all"]

    ``seed`` (an integer >= 0) drives every random choice: the same parameters and seed give
    the same record, ``wall_seconds`` aside. Bad parameters raise :class:`InputError` (a
    ``ValueError``) naming the parameter, before any work starts; so do the checks that
    need the world (a missing map file, a nest on an obstacle, more agents than free cells).

    ``on_frame(frame)`` is called with the run's frames as they happen (what ``--render``
    draws); raising :class:`StopRun` from it ends the run early (the record is then
    incomplete, ``complete`` False). ``trace=False`` leaves the per-step trace (agents'
    trajectories and jobs) out of the record, for studies of many runs that read only
    metrics; every team metric is the same. ``progress=True`` shows the command line's bar
    of a run that lasts more than half a second (traversal: jobs started of the free cells)
    on standard error, when that is a terminal or a notebook's output; it reads the run's
    frames, which costs some time (a traversal's frames about half its CPU again).

    Returns a :class:`ResultRecord`; ``record.to_dict()`` equals the JSON that
    ``swarmex COMMAND ... --json`` writes for the same options and seed, ``wall_seconds``
    aside.
    """
    from swarmex.missions.base import check_seed, python_spelling
    from swarmex.missions.registry import get

    m = get(mission)
    if "seed" in params:
        raise InputError("give the seed once, as seed=")
    check_seed(seed)
    with python_spelling(m.params_type):
        p = m.params({**params, "seed": seed})
        if not isinstance(progress, bool):  # "no" is truthy: it would have shown the bar
            raise InputError(f"progress must be True or False, got {progress!r}")
        if ignored := p.ignored():
            import warnings

            for name, why in ignored.items():
                warnings.warn(f"{name} is ignored: {why}", UserWarning, stacklevel=2)
        watch = None
        if progress:
            from swarmex.experiments.progress import progress_watch

            watch = progress_watch(m)
        return m.run(p, on_frame=on_frame, trace=trace, watch=watch).record


def rerun(
    record: ResultRecord | Mapping[str, Any] | str | PathLike[str],
    *,
    on_frame: Callable[[Any], Any] | None = None,
    trace: bool | None = None,
    progress: bool = False,
    **overrides: Any,
) -> ResultRecord:
    """Run a record again: the same mission, parameters and seed, so the same record
    (``wall_seconds`` aside) when the same swarmex version made it.

    ``record`` is a :class:`ResultRecord`, its ``to_dict()``, or a record JSON file (what
    ``--json`` and the sweeps write). ``overrides`` change parameters, as in :func:`run`
    (``swarmex.rerun(rec, agents=8)``, ``seed=5`` included), or give the world again when
    the record could not name it (``map=world`` for a run on a world object). ``trace`` is
    the record's own by default: a record made with ``trace=False`` (no agent has a
    trajectory or a job) runs again without its trace, so that it too comes back the same.
    ``swarmex rerun FILE`` does this from the shell and says whether the record came out the
    same. ``progress=True`` shows the run's bar, as :func:`run`'s.
    """
    from swarmex.experiments.progress import watches_if
    from swarmex.experiments.rerun import load_record, rerun_record
    from swarmex.missions.registry import any_python_spelling

    watch_for = watches_if(progress)
    rec, folder = load_record(record)
    with any_python_spelling():
        return rerun_record(rec, folder, overrides, on_frame=on_frame, trace=trace,
                            watch_for=watch_for)


def render(
    record: ResultRecord | Mapping[str, Any] | str | PathLike[str],
    path: str | PathLike[str],
    *,
    progress: bool = False,
    **world: Any,
) -> Path:
    """Draw a run: a picture (``.png``) or an animation (``.gif``; ``.mp4`` needs the
    ``video`` extra) of ``record``'s run, what ``--render`` draws. Returns the path.

    ``record`` is what :func:`run` returned, its ``to_dict()``, or a record file. The run is
    made again from the record, keeping the frames the drawing needs (a record holds paths,
    not frames), so drawing costs the run's time once more. If that run no longer comes out
    as the record (another swarmex version, an edited record), the drawing is of today's run and a
    ``RuntimeWarning`` says so. ``world`` gives the world again when the record cannot name
    it, as for :func:`rerun`: ``swarmex.render(rec, "run.png", map=world)`` for a run on a
    world object (only world and input-file parameters: any other would draw another run).
    ``swarmex render RECORD.json OUT.png`` does this from the shell. ``progress=True``
    shows the run's bar, as :func:`run`'s.
    """
    import warnings

    from swarmex.experiments.progress import watches_if
    from swarmex.experiments.rerun import render_record
    from swarmex.missions.registry import any_python_spelling

    with any_python_spelling():
        out, why = render_record(record, path, world, watch_for=watches_if(progress))
    if why is not None:
        warnings.warn(
            f"{out}: the record's run came out differently today ({why}); the drawing is of"
            " today's run",
            RuntimeWarning,
            stacklevel=2,
        )
    return out


def sweep(
    mission: str,
    *,
    out: str | PathLike[str],
    seeds: int | Sequence[int] = 1,
    fixed: Mapping[str, Any] | None = None,
    backend: str = "local",
    workers: int | None = None,
    retry_failed: bool = False,
    progress: bool = True,
    **axes: Any,
) -> Any:
    """Run the product of parameter lists over seeds, as ``swarmex sweep SPEC.toml`` does,
    and return the results table (a ``pyarrow.Table``, one row per run; ``.to_pylist()``, or
    ``.to_pandas()`` where pandas is installed).

    Each keyword is a parameter of :func:`run`: a list (or range) is an axis, anything else,
    a tuple included (``grid=(8, 8)``), a value every run shares; ``fixed`` holds shared
    values that are themselves lists (``nests=[[0, 0], [5, 5]]``). ``seeds``
    is a count (the first N) or a list. ``out`` is the sweep's folder: every run's record is
    written there as it finishes, with ``results.parquet``; calling again with the same
    arguments resumes (finished runs are skipped), and an interrupted call loses no finished
    run. ``backend`` is ``"local"`` (a process pool of ``workers``, default all cores),
    ``"serial"`` (this process) or ``"ray"``. A run that fails is a row with its ``error``;
    bad parameters raise :class:`InputError` before any run. ``progress`` shows the command
    line's bar (done/total, runs per second, ETA) on standard error when that is a terminal
    or a notebook's output. For example::

        table = swarmex.sweep("traversal", out="runs", algorithm=["madgta", "nearest"],
                              grid="8x8", agents=[2, 4], seeds=5)
        table.group_by(["algorithm", "agents"]).aggregate([("makespan", "mean")])

    Why the folder is required: a sweep is the long, resumable unit of work; its records are
    the data, and the table is rebuilt from them (docs/sweeps.md).
    """
    from pathlib import Path

    from swarmex.experiments.progress import SweepBar
    from swarmex.experiments.scenario import mission_shapes
    from swarmex.experiments.sweep import check_backend, read_results, run_sweep
    from swarmex.experiments.sweep_spec import always_ignored, listed_axes, spec_from_keywords

    # checked here: a string is truthy, so retry_failed="no" retried (and rewrote) every
    # failed run, and a wrong type ended in a TypeError deep in the sweep
    for name, flag in (("retry_failed", retry_failed), ("progress", progress)):
        if not isinstance(flag, bool):
            raise InputError(f"{name} must be True or False, got {flag!r}")
    if not isinstance(out, str | PathLike):
        raise InputError(f"out must be the sweep's folder (a str or path), got {out!r}")
    if fixed is not None and not isinstance(fixed, Mapping):
        raise InputError(f"fixed must be a dict of shared values, such as"
                         f" {{'nests': [[0, 0]]}}, got {fixed!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)):
        raise InputError(f"workers must be a whole number, got {workers!r}")
    check_backend(backend, workers, python=True)  # in these words, not --workers
    from swarmex.missions.registry import any_python_spelling

    with any_python_spelling():
        spec = spec_from_keywords(mission, seeds, fixed or {}, axes)
    import warnings

    for key, count in listed_axes(spec):
        warnings.warn(f"{key} is an axis of {count} values, one per run; for one list of {key}"
                      " in every run, give it in fixed= or as a tuple", UserWarning, stacklevel=2)
    for name, why in always_ignored(spec):
        warnings.warn(f"{name} is ignored in every run: {why}", UserWarning, stacklevel=2)
    bar = SweepBar(disable=not progress)
    try:
        with any_python_spelling():
            result = run_sweep(
                spec, mission_shapes(mission), Path(fspath(out)), backend=backend,
                workers=workers, retry_failed=retry_failed, on_start=bar.on_start,
                on_outcome=bar.on_outcome,
            )
    finally:
        bar.stop()
    return read_results(result.out_dir)[0]


def compare(
    results: Any,
    baseline: Mapping[str, Any],
    metrics: Sequence[str] = ("makespan",),
) -> Any:
    """Paired comparisons of a sweep: every other value of one parameter against a baseline
    value, run by run on the same configuration and seed. Returns a ``pyarrow.Table``.

    ``results`` is the table :func:`sweep` returned or a sweep folder; ``baseline`` names
    the compared parameter and its baseline value (``{"algorithm": "madgta"}``); ``metrics``
    are table columns. One row per variant value, group of the other varied parameters and
    metric, plus a pooled row per variant and metric (its group columns null) when there
    are several groups: ``pairs``, ``baseline_mean``, ``mean``, the mean difference ``diff``
    with its Student-t 95 % interval ``diff_low``/``diff_high``, the mean ratio − 1
    ``relative`` (a fraction) with ``relative_low``/``relative_high`` over
    ``relative_pairs`` pairs (a baseline of 0 has no ratio), and the pairs where
    the variant is lower or higher (``lower_in``, ``higher_in``). Failed runs leave their
    pair out. ``swarmex sweep SPEC --baseline algorithm=madgta`` prints the same. For
    example::

        table = swarmex.sweep("traversal", out="runs", algorithm=["madgta", "madgta+"],
                              grid="12x12", agents=4, seeds=10)
        swarmex.compare(table, {"algorithm": "madgta"}, ["makespan", "total_time_all"])
    """
    from swarmex.experiments.compare import as_table, axis_name, comparisons, load

    if not isinstance(baseline, Mapping) or len(baseline) != 1:
        raise InputError(f"baseline must name one parameter and its value, such as"
                         f" {{'algorithm': 'madgta'}}, got {baseline!r}")
    if isinstance(metrics, str):
        metrics = [metrics]
    if (not isinstance(metrics, Sequence) or not metrics
            or not all(isinstance(m, str) for m in metrics)):
        raise InputError(f"metrics must be a column name or a non-empty list of them, such as"
                         f" ['makespan', 'total_time_all'], got {metrics!r}")
    table, meta = load(results)
    ((name, value),) = baseline.items()
    axes = [a for a in meta.get("axes", []) if a in table.column_names]
    name = axis_name(axes, str(name))
    metrics = list(dict.fromkeys(metrics))  # a metric asked twice: one row, not two
    inputs = {"seed", *axes, *meta.get("params", [])}
    given = [m for m in metrics if m in inputs or m.replace("-", "_") in inputs]
    if given:  # a parameter compared with itself, pair by pair, is rows of zeros
        raise InputError(f"metrics: {given[0]!r} is a parameter of the runs, not a result")
    out = as_table(comparisons(table, meta, name, value, metrics), name, axes)
    if out.num_rows == 0:
        import warnings

        warnings.warn(f"no pairs against {name} = {value}: every run with that value, or"
                      " every run it would pair with, failed (see the table's error column)",
                      UserWarning, stacklevel=2)
    return out


def plot(
    results: Any,
    x: str,
    y: str,
    *,
    hue: str | None = None,
    where: Mapping[str, Any] | None = None,
    kind: str = "auto",
    out: str | PathLike[str] | None = None,
) -> Any:
    """A sweep's metric ``y`` against the parameter ``x``, as ``swarmex plot`` draws it:
    means over the seeds with Student-t 95 % bands (a numeric ``x``) or grouped bars with
    whiskers (a categorical one; ``kind`` "line" or "bar" chooses), one series per ``hue``
    value. ``results`` is the table :func:`sweep` returned or a sweep folder; ``where``
    keeps the rows with these values (``{"grid": "8x8"}``). Returns the matplotlib
    ``Figure`` (a notebook shows it), also written to ``out`` (.png or .svg) when given.
    Varied parameters that are neither ``x`` nor ``hue`` are pooled, with a
    ``UserWarning`` saying so. A time (``makespan``, ``*_time*``, ``steps``) of a run that
    did not finish is where it stopped, not a finish time: such points are drawn hollow (bars
    hatched), with a ``UserWarning``; ``where={"complete": True}`` keeps the finished runs."""
    import warnings

    from swarmex.experiments.compare import load
    from swarmex.viz.files import save_figure
    from swarmex.viz.plot import SUFFIXES, sweep_figure

    for label, name in (("x", x), ("y", y), ("hue", hue)):
        if not isinstance(name, str) and not (label == "hue" and name is None):
            raise InputError(f"{label} must be a column name (a str), got {name!r}")
    if where is not None and not isinstance(where, Mapping):
        raise InputError(f"where must be a dict of parameter values, such as {{'agents': 4}},"
                         f" got {where!r}")
    table, meta = load(results)
    # a pair (grid=(5, 5)) as the table spells it, "5,5"
    filters = [f"{k}={','.join(map(str, v)) if isinstance(v, tuple | list) else v}"
               for k, v in (where or {}).items()]
    fig, note = sweep_figure(table.to_pylist(), meta, x, y, hue, filters, kind)
    for line in (note or "").splitlines():
        line = line.removeprefix("note: ").replace("--hue or --where", "hue= or where=")
        warnings.warn(line.replace("--where complete=true", "where={'complete': True}"),
                      UserWarning, stacklevel=2)
    if out is not None:
        if not isinstance(out, str | PathLike):
            raise InputError(f"out must be a file name (.png or .svg), got {out!r}")
        path = Path(fspath(out))
        if path.suffix.lower() not in SUFFIXES:
            raise InputError(f"out: {path} must end in .png or .svg")
        save_figure(fig, path)
    return fig


def describe(mission: str) -> str:
    """A mission's summary and every parameter of :func:`run` for it, one per line: its
    name, command-line flag, default and meaning; then the team metrics its records hold
    (the tables of docs/api.md, as text).

    Why a function: the parameters live in each mission's Params declarations, which
    ``help(swarmex.run)`` cannot show without importing every mission.
    """
    from swarmex.missions.registry import get

    m = get(mission)
    head = f"{m.name} (swarmex {m.command}): {m.summary}\nparameters of swarmex.run:\n"
    metrics = m.team_metrics()
    width = max((len(k) for k in metrics), default=0)
    tail = "".join(f"  {k:<{width}}  {v.meaning}\n" for k, v in metrics.items())
    if tail:
        tail = "\nteam metrics of its records (record.metrics):\n" + tail
    return head + m.params_type.describe() + tail


def __dir__() -> list[str]:
    return sorted({*globals(), "ResultRecord", "StopRun"})


def __getattr__(name: str) -> Any:
    if name == "ResultRecord":
        from swarmex.engine.record import ResultRecord

        return ResultRecord
    if name == "StopRun":
        from swarmex.missions.base import StopRun

        return StopRun
    raise AttributeError(f"module 'swarmex' has no attribute {name!r}")
