"""Heterogeneous fleets: per-agent parameters by id (seed 000 §4.3, issue 15).

Seed 000's server held "all personal parameters for each agent, according to its ID": nest,
target altitude, travel speed, job time, climb and descent speeds (D01: nest 2, 5 m,
300 cm/s, 10 s a job, 150 / 30 cm/s up / down; D02: nest 12, 15 m, 200 cm/s, 12 s, 250 /
50 cm/s; ...). A fleet here is that table, one row per agent:

==============  ===========================================================================
field           meaning (a missing field takes the command's own option)
==============  ===========================================================================
``id``          the agent's id, 1..m, each once (``3`` or the seed's ``"D03"``)
``nest``        start cell ``"x,y"`` or ``[x, y]`` (default: ``--nests`` round-robin by id)
``altitude``    working altitude, metres (``--altitude``)
``travel_speed``  metres per second; needs a length scale: a GPS grid (``--center``) or
                ``--edge-length`` (give this or ``travel_time``, not both)
``travel_time`` seconds per grid edge (``--travel-time``)
``job_time``    seconds per job (``--job-time``)
``up_speed``    climb speed, m/s (``--up-speed``)
``down_speed``  descent speed, m/s (``--down-speed``)
==============  ===========================================================================

Speeds are metres per second, where the seed's table has centimetres per second (its
300 cm/s is ``travel_speed = 3.0``).

Where a fleet comes from: ``--fleet FILE`` (a TOML file of ``[[agents]]`` tables, or a CSV
with a header row of the field names, an empty cell being a missing field; a nest in a CSV
is ``"x,y"`` in quotes or ``x y``); ``[[agents]]`` tables in a scenario file; and in Python
``fleet=[{"id": 1, "travel_speed": 3.0}, ...]`` (or ``agents=[...]``, the TOML form), a file
path, or :class:`FleetRow` objects. Every problem is one :class:`~swarmex.errors.InputError`
line naming the source, the row (by its id, or by its position when the id itself is bad)
and the field.
"""

from __future__ import annotations

import csv
import difflib
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from swarmex.errors import InputError
from swarmex.missions.base import Cell, Parser, integer, real

FIELDS = (
    "id", "nest", "altitude", "travel_speed", "travel_time", "job_time", "up_speed",
    "down_speed",
)
#: Physical bounds of an agent's times and speeds. Why: every value up to 1e308 used to pass,
#: and a job of 1e308 s made the makespan inf (a blank summary, a null in the JSON); a year
#: of travel per edge, 100 km of altitude and 1 mm/s are past any vehicle already.
MAX_SECONDS = 1e9
MAX_ALTITUDE = 1e5
MAX_EDGE_M = 1e6  # metres per grid edge (--edge-length)
MIN_SPEED = 1e-3
_NUMBERS: dict[str, Parser] = {
    "altitude": real(lo=0, hi=MAX_ALTITUDE),
    "travel_speed": real(lo=MIN_SPEED),
    "travel_time": real(above=0, hi=MAX_SECONDS),
    "job_time": real(lo=0, hi=MAX_SECONDS),
    "up_speed": real(lo=MIN_SPEED),
    "down_speed": real(lo=MIN_SPEED),
}
_ID = re.compile(r"^\s*[Dd]?0*(\d+)\s*$")
_NEST = re.compile(r"^\s*(-?\d+)\s*(?:,|\s)\s*(-?\d+)\s*$")
MAX_AGENTS = 100_000


@dataclass(frozen=True)
class FleetRow:
    """One agent's own values; ``None`` takes the command's option of the same name."""

    id: int
    nest: Cell | None = None
    altitude: float | None = None
    travel_speed: float | None = None
    travel_time: float | None = None
    job_time: float | None = None
    up_speed: float | None = None
    down_speed: float | None = None

    def given(self) -> dict[str, Any]:
        """The fields this row sets (id included), as plain values."""
        out: dict[str, Any] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if v is not None:
                out[f.name] = list(v) if f.name == "nest" else v
        return out


def _row_id(value: Any, where: str) -> int:
    if isinstance(value, str):
        m = _ID.match(value)
        if not m:
            raise InputError(f"{where}: id: expected an agent number such as 3 or D03, got "
                             f"{value!r}")
        value = int(m[1])
    return int(integer(lo=1, hi=MAX_AGENTS)(value, f"{where}: id"))


def _nest(value: Any, where: str) -> Cell:
    if isinstance(value, str):
        m = _NEST.match(value)
        if m:
            return int(m[1]), int(m[2])
    elif (
        isinstance(value, Sequence)
        and len(value) == 2
        and all(isinstance(v, int) and not isinstance(v, bool) for v in value)
    ):
        return int(value[0]), int(value[1])
    raise InputError(f'{where}: nest: malformed cell {value!r} (expected "x,y" or [x, y])')


def parse_row(row: Mapping[str, Any] | FleetRow, where: str, position: int) -> FleetRow:
    """One row (a mapping of field -> value, ``None`` or ``""`` = missing) as a FleetRow.

    ``where`` names the source ("--fleet fleet.csv"); ``position`` (1-based) names the row
    until its id is known.
    """
    if isinstance(row, FleetRow):
        row = row.given()
    if not isinstance(row, Mapping):
        raise InputError(f"{where}: row {position}: expected a table of {', '.join(FIELDS)},"
                         f" got {row!r:.60}")
    given = {
        str(k).strip().replace("-", "_"): v for k, v in row.items() if v is not None and v != ""
    }
    if "id" not in given:
        raise InputError(f"{where}: row {position}: id: missing (every row names its agent)")
    ident = _row_id(given["id"], f"{where}: row {position}")
    here = f"{where}: agent {ident}"
    for key in given:
        if key not in FIELDS:
            close = difflib.get_close_matches(key, FIELDS, n=1, cutoff=0.6)
            hint = f"; did you mean {close[0]!r}?" if close else f" (fields: {', '.join(FIELDS)})"
            raise InputError(f"{here}: unknown field {key!r}{hint}")
    values: dict[str, Any] = {"id": ident}
    if "nest" in given:
        values["nest"] = _nest(given["nest"], here)
    for key, parse in _NUMBERS.items():
        if key in given:
            values[key] = parse(given[key], f"{here}: {key}")
    if "travel_speed" in values and "travel_time" in values:
        raise InputError(f"{here}: travel_speed: give travel_speed or travel_time, not both")
    return FleetRow(**values)


def parse_rows(rows: Sequence[Any], where: str) -> tuple[FleetRow, ...]:
    """Rows in any order, sorted by id; the ids must be 1..m, each once."""
    if not rows:
        raise InputError(f"{where}: no agents listed")
    if len(rows) > MAX_AGENTS:
        raise InputError(f"{where}: {len(rows)} agents; at most {MAX_AGENTS}")
    out: dict[int, FleetRow] = {}
    for i, raw in enumerate(rows, start=1):
        row = parse_row(raw, where, i)
        if row.id in out:
            raise InputError(f"{where}: agent {row.id}: id: listed twice")
        out[row.id] = row
    m = len(out)
    for ident in sorted(out):
        if ident > m:
            missing = min(set(range(1, m + 1)) - set(out))
            raise InputError(
                f"{where}: agent {ident}: id: the ids of {m} agents are 1..{m}, each once"
                f" (id {missing} is missing)"
            )
    return tuple(out[i] for i in range(1, m + 1))


def is_table_list(value: Any) -> bool:
    """Whether ``value`` is a fleet given inline: a non-empty list of tables or FleetRows."""
    return (
        isinstance(value, list | tuple)
        and bool(value)
        and all(isinstance(v, Mapping | FleetRow) for v in value)
    )


def load_fleet(path: Path, where: str) -> tuple[FleetRow, ...]:
    """A fleet file: ``.csv`` (a header of field names), anything else TOML ``[[agents]]``."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(f"{where}: file not found") from None
    except IsADirectoryError:
        raise InputError(f"{where}: is a folder, not a fleet file") from None
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise InputError(f"{where}: cannot read: {reason}") from None
    if path.suffix.lower() == ".csv":
        return parse_rows(_csv_rows(text, where), where)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{where}: not valid TOML ({exc}); a fleet file is [[agents]] "
                         "tables, or a .csv") from None
    extra = sorted(set(data) - {"agents"})
    if extra:
        raise InputError(f"{where}: unknown key {extra[0]!r} (a fleet file holds [[agents]]"
                         " tables only)")
    agents = data.get("agents")
    if not isinstance(agents, list) or not all(isinstance(a, dict) for a in agents):
        raise InputError(f"{where}: no [[agents]] tables")
    return parse_rows(agents, where)


def _csv_rows(text: str, where: str) -> list[dict[str, Any]]:
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    reader = csv.DictReader(lines, skipinitialspace=True)
    header = [h.strip().replace("-", "_") for h in (reader.fieldnames or [])]
    if not header:
        raise InputError(f"{where}: empty (expected a header row: {', '.join(FIELDS)})")
    for h in header:
        if h not in FIELDS:
            close = difflib.get_close_matches(h, FIELDS, n=1, cutoff=0.6)
            hint = f"; did you mean {close[0]!r}?" if close else f" (fields: {', '.join(FIELDS)})"
            raise InputError(f"{where}: unknown column {h!r}{hint}")
    twice = next((h for i, h in enumerate(header) if h in header[:i]), None)
    if twice is not None:  # the reader keeps the last one, and the rows' errors misled
        raise InputError(f"{where}: column {twice!r} is given twice")
    rows = []
    for i, raw in enumerate(reader, start=1):
        extra = raw.get(None)
        if extra:
            raise InputError(f"{where}: row {i}: more cells than the header's {len(header)}"
                             " (quote a nest: \"x,y\")")
        rows.append({k.strip(): (v.strip() if isinstance(v, str) else v)
                     for k, v in raw.items() if k is not None})
    return rows


def fleet() -> Parser:
    """The ``fleet`` option: a file path, or rows (tables / FleetRows) -> sorted FleetRows."""

    def parse(value: Any, flag: str) -> tuple[FleetRow, ...]:
        if isinstance(value, str | Path):
            text = str(value).strip()
            if not text:
                raise InputError(f"{flag}: expected a fleet file, got {value!r}")
            p = Path(text).expanduser()
            return load_fleet(p, f"{flag} {p}")
        if isinstance(value, list | tuple):
            return parse_rows(list(value), flag)
        raise InputError(
            f"{flag}: expected a fleet file (TOML [[agents]] or CSV) or a list of agent "
            f"tables, got {value!r:.60}"
        )

    parse.kind = Path  # type: ignore[attr-defined]
    return parse


__all__ = ["FIELDS", "FleetRow", "fleet", "is_table_list", "load_fleet", "parse_rows"]
