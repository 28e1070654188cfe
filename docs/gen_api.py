"""Regenerate the parameter and metric tables of docs/api.md from the missions' Params
and their declared team metrics.

Run from the repository root: ``python docs/gen_api.py`` (``--check`` exits 1 when the file
is stale; tests/test_docs_api.py runs that check, so the tables always match the code).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import swarmex
from swarmex.missions.base import REQUIRED
from swarmex.missions.registry import get

API = Path(__file__).with_name("api.md")
BEGIN, END = "<!-- params:begin -->", "<!-- params:end -->"


def _default(value: object) -> str:
    if value is REQUIRED:
        return "**required**"
    if value is None:
        return "—"
    if isinstance(value, tuple) and not value:
        return "none"
    return f"`{value!r}`" if not isinstance(value, str) else f'`"{value}"`'


def tables() -> str:
    out = []
    for name in swarmex.missions():
        m = get(name)
        out += [f"### `{name}` (`swarmex {m.command}`)", "", m.summary, "",
                "| parameter | CLI | default | meaning |", "|---|---|---|---|"]
        for info in m.params_type.options().values():
            flag = info.flag if info.negation is None else f"{info.flag}/{info.negation}"
            meaning = info.help.replace("|", "\\|")
            out.append(f"| `{info.name}` | `{flag}` | {_default(info.default)} | {meaning} |")
        out += ["", "Team metrics of its records (`record.metrics`, sweep table columns):", "",
                "| metric | meaning | mean over seeds |", "|---|---|---|"]
        for key, metric in m.team_metrics().items():
            meaning = metric.meaning.replace("|", "\\|")
            mean = "yes" if metric.numeric else "no"
            if metric.keys:  # a table: its entries are the sweep columns
                mean = "each entry: " + ", ".join(f"`{key}.{k}`" for k in metric.keys)
            out.append(f"| `{key}` | {meaning} | {mean} |")
        out.append("")
    return "\n".join(out)


def render(text: str) -> str:
    block = f"{BEGIN}\n{tables()}\n{END}"
    return re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: block, text, flags=re.S)


if __name__ == "__main__":
    current = API.read_text(encoding="utf-8")
    fresh = render(current)
    if "--check" in sys.argv:
        sys.exit(0 if fresh == current else 1)
    API.write_text(fresh, encoding="utf-8")
