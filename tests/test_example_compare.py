"""examples/compare_algorithms.py, the library's workflow in one script, runs as its docstring
says (``--quick``) and writes what it promises; a second run resumes its sweep."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from PIL import Image

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "compare_algorithms.py"


def test_the_quick_example_writes_its_outputs_and_resumes(tmp_path: Path, capsys) -> None:
    spec = importlib.util.spec_from_file_location("compare_algorithms", EXAMPLE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--out", str(tmp_path), "--quick"]) == 0
    text = capsys.readouterr().out
    assert "sweep: 12 runs" in text and "madgta+        makespan:" in text
    for name in ("makespan.png", "largest-gain.png"):
        with Image.open(tmp_path / name) as image:
            assert image.size[0] > 300
    stamps = {p: p.stat().st_mtime_ns for p in (tmp_path / "sweep" / "runs").glob("*.json")}
    assert len(stamps) == 12
    assert module.main(["--out", str(tmp_path), "--quick"]) == 0
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps  # resumed: nothing ran again
