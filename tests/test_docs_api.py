"""docs/api.md's parameter tables are generated from the Params: they never drift."""

from __future__ import annotations

import runpy
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_api_tables_match_the_params():
    gen = runpy.run_path(str(DOCS / "gen_api.py"))
    text = (DOCS / "api.md").read_text(encoding="utf-8")
    assert gen["render"](text) == text, "docs/api.md is stale: run python docs/gen_api.py"


def test_readme_library_example_runs(tmp_path, monkeypatch):
    """The README's first Python example, exactly as printed, runs and gives a record."""
    readme = (DOCS.parent / "README.md").read_text(encoding="utf-8")
    start = readme.index("```python", readme.index("## Library use"))
    code = readme[start + len("```python"):readme.index("```", start + 9)]
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(code, "README.md", "exec"), scope)  # noqa: S102
    assert scope["record"].mission == "foraging"


def _python_blocks(text: str, after: str) -> str:
    start = text.index("```python", text.index(after))
    return text[start + len("```python"):text.index("```", start + 9)]


def test_readme_pettingzoo_example_runs(tmp_path, monkeypatch):
    """README's "use it from PettingZoo" lines, as printed, run an episode to the end."""
    readme = (DOCS.parent / "README.md").read_text(encoding="utf-8")
    code = _python_blocks(readme, "## Use it from PettingZoo")
    assert len([ln for ln in code.strip().splitlines() if ln.strip()]) <= 5
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(code, "README.md", "exec"), scope)  # noqa: S102
    assert not scope["env"].agents  # the episode ended


def test_envs_doc_example_runs(tmp_path, monkeypatch):
    """docs/envs.md's first example: baseline episode == swarmex.run."""
    code = _python_blocks((DOCS / "envs.md").read_text(encoding="utf-8"), "# PettingZoo")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "envs.md", "exec"), {})  # noqa: S102


def test_optimal_doc_example_runs(tmp_path, monkeypatch):
    """docs/traversal-optimal.md's example: the solver's optimum is the record's, and no
    more than MADGTA's on the same instance (what the page says it prints)."""
    code = _python_blocks((DOCS / "traversal-optimal.md").read_text(encoding="utf-8"), "# The")
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(code, "traversal-optimal.md", "exec"), scope)  # noqa: S102
    plan, best, madgta = scope["plan"], scope["best"], scope["madgta"]
    assert plan.proven_optimal
    # an independent floor: every free vertex's job, and one edge to reach each non-nest
    # vertex (two nests on a 4x4 with two walls: 14 jobs of 5 s, 12 edges of 1 s), which
    # two walks without a revisit attain, so the optimum is exactly this bound
    free = int(scope["world"].free.sum())
    assert free == 14
    assert plan.value == free * 5.0 + (free - 2) * 1.0
    assert best.metrics["total_time_all"] == plan.value == 82.0
    assert madgta.metrics["total_time_all"] == 85.0
