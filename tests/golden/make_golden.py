"""Write tests/golden/records.json: the canonical hash and headline numbers of every golden
scenario, run through the CLI's ``--json``. Run from the repository root:
``python tests/golden/make_golden.py [--full DIR]`` (``--full`` also keeps the records)."""

from __future__ import annotations

import hashlib
import json
import sys
import tempfile
from pathlib import Path

from swarmex.cli import main

try:
    from tests.golden.scenarios import SCENARIOS
except ImportError:  # run as a script from the repository root
    sys.path.insert(0, str(Path(__file__).parent))
    from scenarios import SCENARIOS  # type: ignore[no-redef]


def canonical(record: dict) -> str:
    record = {k: v for k, v in record.items() if k != "wall_seconds"}
    return json.dumps(record, sort_keys=True, separators=(",", ":"))


def digest(record: dict) -> str:
    return hashlib.sha256(canonical(record).encode()).hexdigest()


def run_cli(command: str, argv: list[str]) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "r.json"
        code = main([command, *argv, "--json", str(out)])
        if code not in (0, 1):
            raise SystemExit(f"{command} {argv} exited {code}")
        return json.loads(out.read_text())


if __name__ == "__main__":
    full = Path(sys.argv[sys.argv.index("--full") + 1]) if "--full" in sys.argv else None
    golden = {}
    for name, mission, command, argv in SCENARIOS:
        rec = run_cli(command, argv)
        assert rec["mission"] == mission, (name, rec["mission"])
        golden[name] = {"sha256": digest(rec), "makespan": rec["makespan"],
                        "complete": rec["complete"]}
        if full:
            full.mkdir(parents=True, exist_ok=True)
            (full / f"{name}.json").write_text(canonical(rec))
        print(name, golden[name], file=sys.stderr)
    Path(__file__).with_name("records.json").write_text(json.dumps(golden, indent=1) + "\n")
