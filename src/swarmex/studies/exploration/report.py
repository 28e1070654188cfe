"""The Markdown report of ``swarmex reproduce exploration``: ``exploration.md``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from swarmex.engine.stats import summarize
from swarmex.studies.exploration.analysis import fastest_size, steps_table
from swarmex.studies.exploration.design import STRATEGY_ORDER, TEAM_VARIANTS, Design, skipped_note


def team_section(team_res: dict[str, dict[int, list[dict[str, Any]]]], d: Design) -> list[str]:
    """The team-size study: mean steps of a member (and plans per robot) per variant."""
    names = [n for n in TEAM_VARIANTS if n in team_res]
    sizes = sorted({n for v in team_res.values() for n in v})
    lines = [
        "",
        f"## Team-size study: laser {max(d.lasers):g} m, radio {max(d.comms):g} m",
        "",
        "The thesis explains its optimal team size by goal negotiation: \"the robots have to "
        "excessively agree on the choice of a goal in bigger teams\", and \"increasing the "
        "number of plan generations leads to increase in the number of steps\" (§4.2–4.3). "
        "Here a re-plan is free unless it changes the path. The variants make it cost: "
        "*loser yields its zone* — a robot that lost a conflict may not keep a goal in the "
        "winner's zone even when every frontier is in some zone (`conflict_yield`); *plan "
        "stops robot 0.6 s* — the robot stands still for 6 steps after every plan generation, "
        "as if planning took 0.6 s and the motion thread waited for it (`plan_pause=6`). "
        "Cells: mean steps of a team member ± sd (plans per robot).",
        "",
        "| robots | " + " | ".join(names) + " |",
        "|---" * (len(names) + 1) + "|",
    ]
    for n in sizes:
        cells = []
        for name in names:
            rs = team_res[name].get(n, [])
            if not rs:
                cells.append("–")
                continue
            plans = np.mean([r["plans"] / n for r in rs])
            cells.append(f"{_fmt([r['mean_steps'] for r in rs])} ({plans:.0f})")
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    best = []
    for name in names:
        by = team_res[name]
        thesis = fastest_size({n: rs for n, rs in by.items() if n <= max(d.sizes)})
        best.append(
            f"{name}: {fastest_size(by)} of {min(by)}–{max(by)} ({thesis} of the thesis's sizes)"
        )
    lines += ["", "Fastest team size — " + "; ".join(best) + ".", ""]
    return lines


def _runs_text(journalled: int, ran_now: int, pictures: int) -> str:
    """What the invocation ran: the journalled runs (reused when already in ``runs.jsonl``)
    and the picture runs of Figs. 4.2–4.3, simulated every time (their snapshots are not
    journalled). The two used to be added up as runs "reused, not rerun"."""
    return (
        f"The tables' {journalled} runs are journalled in `runs.jsonl`: {ran_now} of them "
        "ran in this invocation, the others were read back, not rerun. The "
        f"{pictures} runs drawn in Figs. 4.2–4.3 keep snapshots and paths, which are not "
        "journalled, so every invocation simulates them again."
    )


def _fmt(vals: list[float]) -> str:
    """Mean ± the sample SD (n − 1) of a few runs, or the single value (which has none).

    The population SD (n) was printed before, smaller by √(2/3) for three runs, while the
    traversal report and the docs' "within one sd" use the sample SD."""
    if not vals:
        return "–"
    if len(vals) == 1:
        return f"{vals[0]:.0f}"
    s = summarize(vals)
    return f"{s.mean:.0f} ± {s.std:.0f}"


def write_report(
    out: Path, d: Design, results, strat_rows, figures, check_rows, quick: bool, wall: float,
    runs: tuple[int, int, int],
    team_res: dict[str, dict[int, list[dict[str, Any]]]] | None = None,
    skipped_maps: list[str] | None = None,
) -> Path:
    tab = steps_table(results, d)
    lines = [
        "# Reproduction: seed 003, decentralized exploration (chapter 4)",
        "",
        f"`swarmex reproduce exploration{' --quick' if quick else ''} --out {out}` — "
        f"{'quick pipeline check' if quick else 'the thesis design'}: empty "
        f"{d.world_m:g} × {d.world_m:g} m at {d.cell * 100:g} cm, teams "
        f"{', '.join(map(str, d.sizes))}, radio {', '.join(f'{c:g}' for c in d.comms)} m, "
        f"laser {', '.join(f'{la:g}' for la in d.lasers)} m, {d.runs} run(s) each (seeds "
        f"0–{d.runs - 1}), strategy greedy-exclusion (the thesis's). Steps are 100 ms ticks; "
        "a team member's steps are the tick at which its own map showed no reachable frontier. "
        "\"± sd\": the sample standard deviation over the runs (n − 1); a single run has none.",
        "",
        "The thesis prints no numbers for these experiments (only the figures and their "
        "trends; the data were on its CD), so the comparison is with its stated trends.",
        "",
        "## Checks of the thesis's trends",
        "",
        "| trend (thesis ch. 4) | holds here | evidence |",
        "|---|---|---|",
    ]
    for c in check_rows:
        lines.append(f"| {c['trend']} | {'yes' if c['holds'] else '**no**'} | {c['evidence']} |")
    for la in d.lasers:
        lines += [
            "",
            f"## Fig. 4.1({'a' if la == max(d.lasers) else 'b'}): mean steps of a "
            f"team member, laser {la:g} m (mean ± sd over runs)",
            "",
            "| robots | " + " | ".join(f"radio {c:g} m" for c in d.comms) + " |",
            "|---" * (len(d.comms) + 1) + "|",
        ]
        for n in d.sizes:
            lines.append(
                f"| {n} | " + " | ".join(_fmt(tab.get((la, c, n), [])) for c in d.comms) + " |"
            )
    lines += [
        "",
        f"## Team makespan (steps until the last robot finished), laser {max(d.lasers):g} m",
        "",
        "| robots | " + " | ".join(f"radio {c:g} m" for c in d.comms) + " |",
        "|---" * (len(d.comms) + 1) + "|",
    ]
    for n in d.sizes:
        cells = []
        for c in d.comms:
            v = [
                r["makespan"]
                for r in results.values()
                if r["job"]["kind"] == "sweep"
                and r["job"]["robots"] == n
                and r["job"]["comm"] == c
                and r["job"]["laser"] == max(d.lasers)
            ]
            cells.append(_fmt(v))
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    if team_res:
        lines += team_section(team_res, d)
    lines += [
        "",
        "## Coordination strategies (beyond the seed)",
        "",
        "Same maps, same starts (a compact group at the centre), seeds 0–"
        f"{max((r['job']['seed'] for r in strat_rows), default=0)}; mean ± sd. "
        "`makespan`: steps until the whole team finished; `mean steps`: a member's "
        "exploration time (Fig. 4.1's measure); messages and megabytes sent include "
        "relays and heartbeats.",
        "",
    ]
    if skipped_maps:
        lines += [f"Note: {skipped_note(skipped_maps)}.", ""]
    lines += [
        "| scenario | strategy | makespan | mean steps | explored | plans | messages | MB sent |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for sc in dict.fromkeys(r["job"]["scenario"] for r in strat_rows):
        for st in STRATEGY_ORDER:
            rs = [
                r for r in strat_rows if r["job"]["scenario"] == sc and r["job"]["strategy"] == st
            ]
            if not rs:
                continue
            lines.append(
                f"| {sc} | {st} | {_fmt([r['makespan'] for r in rs])} | "
                f"{_fmt([r['mean_steps'] for r in rs])} | "
                f"{min(r['explored_fraction'] for r in rs):.3f} | "
                f"{_fmt([r['plans'] for r in rs])} | "
                f"{_fmt([r['messages_sent'] for r in rs])} | "
                f"{np.mean([r['bytes_sent'] for r in rs]) / 1e6:.1f} |"
            )
    lines += ["", "## Figures", ""]
    for title, p in figures:
        lines += [f"### {title}", "", f"![{title}]({p.name})", ""]
    lines += [
        f"Wall time of this invocation: {wall / 60:.1f} min. {_runs_text(*runs)}",
        "",
    ]
    path = out / "exploration.md"
    path.write_text("\n".join(lines), encoding="utf-8")
    return path
