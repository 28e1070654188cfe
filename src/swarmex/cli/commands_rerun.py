"""``swarmex rerun RECORD.json…``: run records' missions again and say whether each came out
the same; ``swarmex render RECORD.json OUT``: draw a record's run (it runs it again).

Why a command: a record is the unit a paper, a sweep or a bug report hands on, and the first
question about one is "does it still come out like this?". It answers with one line per
record and its exit status (0 every record the same, ``wall_seconds`` aside; 1 some differ,
each with its first differences), so a script or CI can check a set of records (a sweep's
``runs/`` folder) against the current code. Every file is read before the first run, so a
bad one stops the check before any work. The run itself is :func:`swarmex.rerun`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import app, console, err_console
from swarmex.cli.compiling import compile_notice
from swarmex.cli.missions import SURFACES
from swarmex.cli.outputs import RENDER_SUFFIXES, check_output
from swarmex.errors import InputError
from swarmex.experiments.rerun import STOPPED_EARLY, differences, networked_reason

#: How many differences the line names (the rest are counted).
SHOWN = 4


@app.command()
def rerun(
    record_files: list[Path] = typer.Argument(
        ..., help="Record JSONs (--json, or a sweep's runs/), or folders of them."
    ),
    json_out: Path | None = typer.Option(
        None, "--json", help="Write the new record here (one record only).", show_default=False
    ),
) -> None:
    """Run records again (same mission, parameters, seed); exit 1 if any comes out different."""
    from swarmex.engine.record import write_record
    from swarmex.experiments.rerun import load_record, rerun_params, rerun_record

    check_output(json_out, "--json", (".json",))
    files = record_paths(record_files)
    if json_out is not None and len(files) > 1:
        raise InputError(f"--json writes one record; {len(files)} records were given")
    loaded = [(path, *load_record(path)) for path in files]  # folders find relative maps
    prepared = []
    for path, record, folder in loaded:  # a missing map in the last one stops all, first
        try:
            prepared.append(rerun_params(record, folder, {}))
        except InputError as exc:
            raise InputError(f"{path}: {exc}" if len(files) > 1 else str(exc)) from None
    same = 0
    for (path, record, folder), ready in zip(loaded, prepared, strict=True):
        # a small run keeps its kernels interpreted, as the command that made it did (on a
        # cold cache a 6x6 traversal used to compile for 7-12 s); a larger one compiles,
        # with the one line that says so
        with compile_notice(err_console):
            new_record = rerun_record(record, folder, {}, rule_for=interpreted_rule,
                                      prepared=ready, watch_for=progress_watch)
        if json_out is not None:
            write_record(new_record, json_out)
        name = f"{path}: " if len(files) > 1 else ""
        line, ok = verdict(record.to_dict(), new_record.to_dict())
        console.print(f"{name}{line}", soft_wrap=True, highlight=False)
        if json_out is not None:  # as every command says what it wrote
            console.print(f"wrote {json_out}", soft_wrap=True, highlight=False)
        same += ok
    if len(files) > 1:
        console.print(f"{same} of {len(files)} records the same", highlight=False)
    if same < len(files):
        raise typer.Exit(1)


@app.command(
    "render",
    # the help as one paragraph per line: Rich keeps a docstring's line breaks, which cut
    # the second paragraph mid-sentence in --help
    help="Draw a record's run: a .png picture or a .gif/.mp4 animation (it runs it again).\n\n"
    "The record's run is made again from its parameters and seed, keeping the frames the"
    " drawing needs (the record holds paths, not frames), so it takes the run's time once"
    " more.",
)
def render(
    record_file: Path = typer.Argument(..., help="A record JSON (--json, or a sweep's runs/)."),
    out: Path = typer.Argument(..., help="The drawing: .png, .gif or .mp4."),
) -> None:
    """Draw a record's run: a .png picture or a .gif/.mp4 animation (it runs it again).

    The record's run is made again from its parameters and seed, keeping the frames the
    drawing needs (the record holds paths, not frames), so it takes the run's time once more.
    """
    from swarmex.experiments.rerun import render_record

    check_output(out, "OUT", RENDER_SUFFIXES)
    with compile_notice(err_console):
        path, why = render_record(record_file, out, rule_for=interpreted_rule,
                                  watch_for=progress_watch)
    console.print(f"wrote {path}", highlight=False, soft_wrap=True)
    if why is not None:
        err_console.print(
            f"note: the record's run came out differently today ({why}): the drawing is of"
            " today's run", highlight=False, soft_wrap=True,
        )


def interpreted_rule(mission: str) -> Any:
    """The mission command's rule for runs small enough to keep their kernels interpreted
    (:attr:`~swarmex.cli.missions.Surface.interpreted`; None: always compiled)."""
    surface = SURFACES.get(mission) if _registered(mission) else None
    return None if surface is None else surface.interpreted


def progress_watch(mission: str) -> Any:
    """The mission command's progress display (:attr:`~swarmex.cli.missions.Surface.watch`:
    a bar or a step ticker on a terminal, nothing in a pipe; None: the mission has none), so
    that a rerun or a drawing of a long run is not minutes of silence."""
    surface = SURFACES.get(mission) if _registered(mission) else None
    return None if surface is None else surface.watch


def _registered(mission: str) -> bool:
    """Load the mission's command module (commands register their surface on import,
    cli/app.py); False when a missing extra stops it (the rerun itself says which)."""
    from swarmex.cli.app import load
    from swarmex.missions.registry import get

    try:
        load(get(mission).command)
    except ImportError:
        return False
    return True


def record_paths(given: list[Path]) -> list[Path]:
    """The record files: each file as given, each folder's ``*.json`` files in name order
    (a sweep's ``runs/``, its failed runs' error files left out); an InputError names a
    folder with none."""
    out: list[Path] = []
    for path in given:
        if path.is_dir():  # a failed sweep run's <id>.error.json holds no record: skipped
            inside = sorted(p for p in path.glob("*.json") if not p.name.endswith(".error.json"))
            if not inside:
                raise InputError(f"{path}: a folder with no record (.json) in it")
            out += inside
        else:
            out.append(path)  # a missing one: load_record names it
    return out


def verdict(old: dict[str, Any], new: dict[str, Any]) -> tuple[str, bool]:
    """The line for one record (``rerun MISSION ALGORITHM, seed S: …``) and whether it came
    out the same."""
    for d in (old, new):
        d.pop("wall_seconds", None)
    what = f"{old['mission']} {old['algorithm']}, seed {old['seed']}"
    versions = (old.pop("swarmex_version", None), new.pop("swarmex_version", None))
    made = "" if versions[0] == versions[1] else f" (recorded by swarmex {versions[0]})"
    networked = networked_reason(old)  # before differences: it drops the network's parts
    if networked is not None:
        new.get("metrics", {}).pop("message_bytes", None)
    diffs = differences(old, new)
    if not diffs:
        same = "the same record" if networked is None else (
            "the simulator's run is the same (paths, jobs and every metric; the record's"
            " network block, departures, vehicles and message bytes are the wire's own)"
        )
        return f"rerun {what}: {same}{made}", True
    more = f" and {len(diffs) - SHOWN} more" if len(diffs) > SHOWN else ""
    why = "" if networked is None else f" ({networked})"
    if not why and old.get("complete") is False and new.get("complete") is True:
        # a run its caller stopped (StopRun from on_frame) ends where no parameter says
        why = f" ({STOPPED_EARLY})"
    return f"rerun {what}: differs{made} in {'; '.join(diffs[:SHOWN])}{more}{why}", False
