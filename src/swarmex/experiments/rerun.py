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

from collections.abc import Mapping
from os import PathLike, fspath
from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmex.engine.record import ResultRecord
from swarmex.errors import InputError

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


def rerun_outcome(
    rec: ResultRecord,
    folder: Path | None,
    overrides: Mapping[str, Any],
    *,
    on_frame: Any = None,
    trace: bool | None = None,
) -> Outcome:
    """:func:`rerun_record`, returning the run's whole Outcome (what the drawings read)."""
    from swarmex.missions.base import check_seed
    from swarmex.missions.registry import get

    given = dict(overrides)
    seed = given.pop("seed", rec.seed)
    check_seed(seed)
    m = get(rec.mission)
    values = m.rerun_values(rec, given=given.keys())
    moved = find_inputs(m, values, folder)
    if trace is None:
        trace = not rec.agents or any(a.trajectory or a.jobs for a in rec.agents)
    params = m.params({**values, **given, "seed": seed})
    outcome = m.run(params, on_frame=on_frame, trace=trace)
    respell(outcome.record, moved)
    return outcome


def rerun_record(
    rec: ResultRecord,
    folder: Path | None,
    overrides: Mapping[str, Any],
    *,
    on_frame: Any = None,
    trace: bool | None = None,
) -> ResultRecord:
    """Run ``rec`` again (:func:`swarmex.rerun`), with ``overrides`` applied (``seed`` among
    them: the same setting, drawn again). ``folder`` is the record file's, where relative
    input paths are also looked for. ``trace`` None is the record's own: a ``trace=False``
    record (no agent has a trajectory or a job) runs again without it."""
    return rerun_outcome(rec, folder, overrides, on_frame=on_frame, trace=trace).record


def render_record(
    source: ResultRecord | Mapping[str, Any] | str | PathLike[str],
    path: str | PathLike[str],
    world: Mapping[str, Any] | None = None,
) -> tuple[Path, bool]:
    """Draw a record's run to ``path`` (:func:`swarmex.render`): run it again keeping the
    frames the drawing needs (a record holds paths, not every frame or the final maps), and
    say whether that run came out as the record (``wall_seconds`` and the version aside).

    Why a rerun and not the record alone: every mission's drawing reads the run's frames or
    its in-memory state, and a run is reproducible from its record, so drawing one costs the
    run once more rather than frames stored in every record.

    ``world`` gives the world again (``map=world``, ``env=...``) when the record cannot name
    it (a run on a world object, a map file moved): only world and input-file options, since
    anything else would draw another run than the record's."""
    from swarmex.missions.registry import get
    from swarmex.viz.animation import check_suffix, require_writer
    from swarmex.viz.render import draw, frame_recorder

    out = Path(fspath(path))
    check_suffix(out, option="swarmex.render's path")
    require_writer(out)  # a missing video extra costs one line now, not the run
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
    outcome = rerun_outcome(rec, folder, given, on_frame=recorder)
    draw(rec.mission, outcome, out, recorder)
    return out, comparable(outcome.record.to_dict()) == comparable(rec.to_dict())


def comparable(record: dict[str, Any]) -> dict[str, Any]:
    """A record's JSON without what two runs of it may differ in: ``wall_seconds`` and the
    version of swarmex that wrote it."""
    return {k: v for k, v in record.items() if k not in ("wall_seconds", "swarmex_version")}


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
