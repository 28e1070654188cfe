"""Running a record again (:func:`swarmex.rerun`, ``swarmex rerun``): from a record back to
the parameters, seed and trace setting that made it.

Why a module of its own: a record holds what a run *used*, not what its caller passed, so
going back takes three steps, each with its reason: each mission's
:meth:`~swarmex.missions.base.Mission.rerun_values` translates its params (derived values,
other units, the world kept in ``record.world``); input files named by a relative path are
looked for where the record lies (:func:`find_inputs`); and the new record names those files
as the old one did (:func:`respell`), so that the two compare equal.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from os import PathLike, fspath
from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmex.engine.record import ResultRecord
from swarmex.errors import InputError

#: mission name -> that mission's rule (params, prepared world) -> whether a run is small
#: enough to keep its kernels interpreted (None: always compiled)
RuleFor = Callable[[str], Callable[[Any, Any], bool] | None]
#: mission name -> that mission's watch (params, prepared world, on_frame) -> the callback
#: that also shows the run's progress (None: none)
WatchFor = Callable[[str], Callable[[Any, Any, Any], Any] | None]

if TYPE_CHECKING:
    from swarmex.missions.base import Outcome


def load_record(
    source: ResultRecord | Mapping[str, Any] | str | PathLike[str],
) -> tuple[ResultRecord, Path | None]:
    """The record, and the folder of its file when it was given as one."""
    if isinstance(source, str | PathLike):
        path = fspath(source)
        return ResultRecord.read(path), Path(path).absolute().parent
    if isinstance(source, ResultRecord):
        return source, None
    return ResultRecord.from_dict(source), None


#: why an incomplete record's rerun completes (swarmex rerun's line, swarmex render's note)
STOPPED_EARLY = ("the record's run was stopped early by its caller (StopRun from on_frame),"
                 " and a rerun cannot stop at that point")


def rerun_outcome(
    rec: ResultRecord,
    folder: Path | None,
    overrides: Mapping[str, Any],
    *,
    on_frame: Any = None,
    trace: bool | None = None,
    rule_for: RuleFor | None = None,
    prepared: tuple[Any, Any, dict[str, str]] | None = None,
    watch_for: WatchFor | None = None,
) -> Outcome:
    """:func:`rerun_record`, returning the run's whole Outcome (what the drawings read).

    ``rule_for`` (mission name) -> the rule for runs small enough to keep their kernels
    interpreted while numba is cold (:meth:`Mission.run`'s ``interpreted``; the CLI's
    rule for the mission): the same record, without a compile. ``watch_for`` (mission
    name) -> :meth:`Mission.run`'s ``watch`` (the CLI's progress bar for the mission)."""
    m, params, moved = prepared or rerun_params(rec, folder, overrides)
    if trace is None:
        trace = not rec.agents or any(a.trajectory or a.jobs for a in rec.agents)
    rule = rule_for(rec.mission) if rule_for is not None else None
    watch = watch_for(rec.mission) if watch_for is not None else None
    outcome = m.run(params, on_frame=on_frame, trace=trace, interpreted=rule, watch=watch)
    respell(outcome.record, moved)
    return outcome


def rerun_params(
    rec: ResultRecord, folder: Path | None, overrides: Mapping[str, Any]
) -> tuple[Any, Any, dict[str, str]]:
    """The mission, the parameters ``rec`` runs again with, and where its input files were
    found (recorded -> found): every check that needs no run (a missing map, a world given
    as an object), so ``swarmex rerun A B`` can refuse B before it reruns A."""
    from swarmex.missions.base import check_seed
    from swarmex.missions.registry import get

    given = dict(overrides)
    seed = given.pop("seed", rec.seed)
    check_seed(seed)
    m = get(rec.mission)
    values = m.rerun_values(rec, given=given.keys())
    moved = find_inputs(m, values, folder)
    return m, m.params({**values, **given, "seed": seed}), moved


def rerun_record(
    rec: ResultRecord,
    folder: Path | None,
    overrides: Mapping[str, Any],
    *,
    on_frame: Any = None,
    trace: bool | None = None,
    rule_for: RuleFor | None = None,
    prepared: tuple[Any, Any, dict[str, str]] | None = None,
    watch_for: WatchFor | None = None,
) -> ResultRecord:
    """Run ``rec`` again (:func:`swarmex.rerun`), with ``overrides`` applied (``seed`` among
    them: the same setting, drawn again). ``folder`` is the record file's, where relative
    input paths are also looked for. ``trace`` None is the record's own: a ``trace=False``
    record (no agent has a trajectory or a job) runs again without it. ``rule_for``:
    :func:`rerun_outcome`'s, as ``watch_for``; ``prepared``: what :func:`rerun_params` gave
    for these arguments, when the caller checked them first."""
    return rerun_outcome(rec, folder, overrides, on_frame=on_frame, trace=trace,
                         rule_for=rule_for, prepared=prepared, watch_for=watch_for).record


def render_record(
    source: ResultRecord | Mapping[str, Any] | str | PathLike[str],
    path: str | PathLike[str],
    world: Mapping[str, Any] | None = None,
    *,
    rule_for: RuleFor | None = None,
    watch_for: WatchFor | None = None,
) -> tuple[Path, str | None]:
    """Draw a record's run to ``path`` (:func:`swarmex.render`): run it again keeping the
    frames the drawing needs (a record holds paths, not every frame or the final maps), and
    say why that run did not come out as the record (``wall_seconds`` and the version
    aside), or None when it did.

    Why a rerun and not the record alone: every mission's drawing reads the run's frames or
    its in-memory state, and a run is reproducible from its record, so drawing one costs the
    run once more rather than frames stored in every record.

    ``world`` gives the world again (``map=world``, ``env=...``) when the record cannot name
    it (a run on a world object, a map file moved): only world and input-file options, since
    anything else would draw another run than the record's."""
    from swarmex.engine.atomic import check_writable
    from swarmex.missions.registry import get
    from swarmex.viz.animation import check_suffix, require_writer
    from swarmex.viz.render import draw, frame_recorder

    if not isinstance(path, str | PathLike):
        raise InputError(f"swarmex.render's path must be a file name (.png, .gif or .mp4),"
                         f" got {path!r}")
    out = Path(fspath(path))
    check_suffix(out, option="swarmex.render's path")
    require_writer(out)  # a missing video extra costs one line now, not the run
    check_writable(out)  # as must a path below a file: the rerun may take minutes
    rec, folder = load_record(source)
    given = dict(world or {})
    if given:
        m = get(rec.mission)
        opts = m.params_type.options()
        allowed = set(m.world_options) | {k for k, o in opts.items() if o.kind is Path}
        other = sorted(set(given) - allowed)
        if other:
            raise InputError(
                f"swarmex.render draws the record's own run: it takes only the world again"
                f" ({', '.join(sorted(allowed)) or 'none for ' + rec.mission}), not {other[0]!r}"
            )
    recorder = frame_recorder(rec.mission, out)
    outcome = rerun_outcome(rec, folder, given, on_frame=recorder, rule_for=rule_for,
                            watch_for=watch_for)
    draw(rec.mission, outcome, out, recorder)
    old, new = rec.to_dict(), outcome.record.to_dict()
    versions = old.get("swarmex_version"), new.get("swarmex_version")
    if same_run(old, new):
        return out, None
    # the likeliest cause first: each of these used to be blamed on "another swarmex version"
    if given:
        return out, f"{', '.join(sorted(given))} given again is not the record's"
    if not rec.complete and outcome.record.complete:
        return out, STOPPED_EARLY
    if networked_reason({"params": dict(rec.params)}) is not None:  # it reads the params
        return out, "a networked record; swarmex rerun says where"
    if versions[0] != versions[1]:
        return out, f"recorded by swarmex {versions[0]}"
    # same version: an edited record, most likely; say where, as swarmex rerun does
    return out, f"it differs in {differences(old, new)[0]}"


def same_run(old: dict[str, Any], new: dict[str, Any]) -> bool:
    """Whether a rerun (``new``) came out as its record (``old``), as ``swarmex rerun``
    judges it: ``wall_seconds`` and the version aside, and for a record of ``swarmex serve``
    without the parts only the network writes (:func:`networked_reason`). Changes both
    dicts. Why not plain equality: a networked ``--rng shared`` record is the simulator's
    run, and its drawing was announced as "came out differently" although ``swarmex rerun``
    called it the same."""
    for d in (old, new):
        d.pop("wall_seconds", None)
        d.pop("swarmex_version", None)
    if networked_reason(old) is not None and isinstance(new.get("metrics"), dict):
        new["metrics"].pop("message_bytes", None)
    return not differences(old, new)


def respell(new: ResultRecord, moved: Mapping[str, str]) -> None:
    """Name the input files in ``new`` as the first run's record did (in place)."""
    for recorded, found in moved.items():
        for part in (new.params, new.world):
            for key, value in part.items():
                if value == found:
                    part[key] = recorded


def find_inputs(m: Any, values: dict[str, Any], folder: Path | None) -> dict[str, str]:
    """Find the input files (maps, environments) a record names by a relative path.

    A relative path in a record is relative to the folder the run started in, which a record
    does not hold (``swarmex run`` and sweeps write paths relative to it too). Rerun from
    elsewhere, the file is looked for from here, then from the record file's folder and each
    folder above it (a record usually lies below where its run started). Changes ``values``
    in place and returns recorded -> found, to respell the new record as the old one.
    Raises InputError, naming the file and what to do, when it is nowhere."""
    moved: dict[str, str] = {}
    for name, info in m.params_type.options().items():
        value = values.get(name)
        if info.kind is not Path or not isinstance(value, str) or not value:
            continue
        given = Path(value).expanduser()
        if given.is_absolute() or given.exists():
            continue
        places = [folder, *folder.parents] if folder is not None else []
        found = next((d / given for d in places if (d / given).exists()), None)
        if found is None and value == "generated":  # how a record names a world object
            raise InputError(
                f"this record's {name} was given as an object (generated): pass it again"
                f" from Python, e.g. swarmex.rerun(record, {name}=world) or"
                f" swarmex.render(record, out, {name}=world)"
            )
        if found is None:
            where = " or from the record's folder and those above it" if places else ""
            raise InputError(
                f"the record's {name} {value!r} is not found from here{where} (a relative"
                f" path is taken from the folder its run started in: rerun there, or give"
                f" {name}= again; a world given as an object: {name}=world)"
            )
        values[name] = str(found)
        moved[value] = str(found)
    return moved


def networked_reason(old: dict[str, Any]) -> str | None:
    """For a record of ``swarmex serve`` (its params have a ``network`` block) or of the
    exploration process mesh (``processes``): drop the
    parts only a networked run has and say why its rerun, which is the simulator's, may
    differ; None for any other record.

    Why: a networked run with ``--rng shared`` is the simulated run (docs/net.md), so paths,
    jobs and every metric but the wire's ``message_bytes`` can be compared; claiming a
    difference for the network block the simulator never writes would be wrong. With
    ``--rng own``, departures or injected loss the networked run is another run, and the
    line says so rather than only that it differs."""
    params = old.get("params")
    if isinstance(params, dict) and "processes" in params:  # explore --processes
        params.pop("processes")
        return ("a process-mesh record (explore --processes), rerun in the simulator: its"
                " robots ran in real time as separate processes, so when each message arrived"
                " (and with it every later choice) was the machine's timing, not the seed's")
    if not isinstance(params, dict) or "network" not in params:
        return None
    params.pop("network")
    block = old.pop("network", None)
    net = block if isinstance(block, dict) else {}
    departed = old.pop("departed_agents", None)
    old.pop("vehicles", None)
    if isinstance(old.get("metrics"), dict):
        old["metrics"].pop("message_bytes", None)
    reasons = []
    if net.get("rng_mode") not in (None, "shared"):
        reasons.append(f"--rng {net.get('rng_mode')}: each agent drew from its own generator")
    if departed or net.get("left") or net.get("joined"):
        reasons.append("agents left or joined the networked run")
    if net.get("inject_loss"):
        reasons.append("the server dropped messages (--inject-loss)")
    cause = "; ".join(reasons) or "its events or messages did not follow the simulator's"
    return f"a networked record, rerun in the simulator: {cause}"


def differences(old: Any, new: Any, path: str = "") -> list[str]:
    """Where two JSON values differ, as ``path: old → new`` for numbers and words and as the
    bare path for lists and objects of another length or shape."""
    if isinstance(old, dict) and isinstance(new, dict):
        out: list[str] = []
        for key in [*old, *(k for k in new if k not in old)]:
            sub = f"{path}.{key}" if path else str(key)
            if key not in old or key not in new:
                out.append(f"{sub} ({'new' if key not in old else 'gone'})")
            else:
                out += differences(old[key], new[key], sub)
        return out
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        if all(not isinstance(v, dict | list) for v in old + new):
            return [] if old == new else [path]  # a row or a trajectory point: the path alone
        out = []
        for i, (a, b) in enumerate(zip(old, new, strict=True)):
            out += differences(a, b, f"{path}[{i}]")
        return out
    if old == new:
        return []
    if isinstance(old, dict | list) or isinstance(new, dict | list):
        return [path]
    return [f"{path}: {old!r} → {new!r}"]
