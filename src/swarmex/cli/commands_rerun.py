"""``swarmex rerun RECORD.json``: run a record's mission again and say whether it came out
the same.

Why a command: a record is the unit a paper, a sweep or a bug report hands on, and the first
question about one is "does it still come out like this?". It answers with one line and its
exit status (0 the same record, ``wall_seconds`` aside; 1 it differs, with the first
differences), so a script or CI can check a set of records against the current code. The
run itself is :func:`swarmex.rerun`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from swarmex.cli.app import app, console, err_console
from swarmex.cli.compiling import compile_notice
from swarmex.cli.outputs import check_output

#: How many differences the line names (the rest are counted).
SHOWN = 4


@app.command()
def rerun(
    record_file: Path = typer.Argument(..., help="A record JSON (--json, or a sweep's runs/)."),
    json_out: Path | None = typer.Option(
        None, "--json", help="Write the new record here.", show_default=False
    ),
) -> None:
    """Run a record again (same mission, parameters, seed); exit 1 if it comes out different."""
    from swarmex.engine.record import write_record
    from swarmex.experiments.rerun import load_record, rerun_record

    check_output(json_out, "--json", (".json",))
    record, folder = load_record(record_file)  # its folder helps find relative maps
    old = record.to_dict()
    # the one line while numba compiles: a rerun runs compiled (unlike the small runs its
    # record may come from), so on a cold cache a 6x6 traversal took 7-12 s without a word
    with compile_notice(err_console):
        new_record = rerun_record(record, folder, {})
    if json_out is not None:
        write_record(new_record, json_out)
    new = new_record.to_dict()
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
        console.print(f"rerun {what}: {same}{made}", soft_wrap=True, highlight=False)
        return
    more = f" and {len(diffs) - SHOWN} more" if len(diffs) > SHOWN else ""
    why = "" if networked is None else f" ({networked})"
    if not why and old.get("complete") is False and new.get("complete") is True:
        # a run its caller stopped (StopRun from on_frame) ends where no parameter says
        why = (" (the record's run ended incomplete and the rerun completed: a run stopped"
               " early by its caller, e.g. StopRun from on_frame, cannot be rerun to that"
               " point)")
    console.print(
        f"rerun {what}: differs{made} in {'; '.join(diffs[:SHOWN])}{more}{why}",
        soft_wrap=True,
        highlight=False,
    )
    raise typer.Exit(1)


def networked_reason(old: dict[str, Any]) -> str | None:
    """For a record of ``swarmex serve`` (its params have a ``network`` block): drop the
    parts only a networked run has and say why its rerun, which is the simulator's, may
    differ; None for any other record.

    Why: a networked run with ``--rng shared`` is the simulated run (docs/net.md), so paths,
    jobs and every metric but the wire's ``message_bytes`` can be compared; claiming a
    difference for the network block the simulator never writes would be wrong. With
    ``--rng own``, departures or injected loss the networked run is another run, and the
    line says so rather than only that it differs."""
    params = old.get("params")
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
