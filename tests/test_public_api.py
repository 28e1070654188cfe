"""What a Python user sees of ``swarmex`` itself: help(swarmex.run) says what to pass,
describe() lists a mission's parameters, dir() shows the lazy names, import stays light."""

from __future__ import annotations

import subprocess
import sys

import pytest

import swarmex
from swarmex.missions.registry import get


def test_run_docstring_names_the_missions_and_where_parameters_are_listed() -> None:
    doc = swarmex.run.__doc__ or ""
    for name in ("traversal", "foraging", "exploration", "roadmap", "describe", "InputError",
                 "StopRun", "trace=False", "seed"):
        assert name in doc


@pytest.mark.parametrize("mission", swarmex.missions())
def test_describe_lists_every_parameter_with_its_flag(mission: str) -> None:
    text = swarmex.describe(mission)
    for info in get(mission).params_type.options().values():
        line = f"  {info.name} ({info.flag}; {'required' if info.required else 'default'}"
        assert line in text


def test_describe_refuses_an_unknown_mission_by_name() -> None:
    with pytest.raises(swarmex.InputError, match="did you mean 'traversal'"):
        swarmex.describe("travrsal")


def test_dir_lists_the_lazy_public_names() -> None:
    assert set(swarmex.__all__) <= set(dir(swarmex))


def test_import_swarmex_loads_no_heavy_library() -> None:
    code = ("import sys, swarmex; heavy = ('numba', 'numpy', 'matplotlib', 'scipy', 'networkx',"
            " 'shapely'); print(sorted(m for m in heavy if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


USER_SCRIPT = '''
import swarmex
from swarmex import ResultRecord, StopRun


class Enough(StopRun):
    """Stop after the first frame."""


def watch(frame: object) -> None:
    raise Enough


record: ResultRecord = swarmex.run("traversal", grid="4x4", agents=1, on_frame=watch)
complete: bool = record.complete
text: str = swarmex.describe("traversal")
'''


def test_a_users_strict_mypy_sees_the_public_types(tmp_path) -> None:
    """py.typed: a user's ``mypy --strict`` knows ResultRecord and StopRun (StopRun was Any
    through the lazy ``__getattr__``, and subclassing it was an error)."""
    pytest.importorskip("mypy")
    from pathlib import Path

    script = tmp_path / "user.py"
    script.write_text(USER_SCRIPT)
    src = Path(swarmex.__file__).resolve().parents[1]
    out = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--follow-imports=silent",
         "--no-incremental", "--cache-dir", str(tmp_path / "cache"), str(script)],
        capture_output=True, text=True, cwd=tmp_path, env={"MYPYPATH": str(src), "PATH": ""},
    )
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.parametrize("mission", swarmex.missions())
def test_help_on_a_mission_and_its_params_lists_the_parameters(mission: str) -> None:
    # the Params' docstring was the dataclass's generated signature, the Mission's None
    m = get(mission)
    for doc in (type(m).__doc__ or "", m.params_type.__doc__ or ""):
        for name in m.params_type.options():
            assert f"  {name} (--" in doc
    assert "from_values" in (m.params_type.__doc__ or "")


def test_the_documented_dotted_names_under_swarmex_missions_resolve() -> None:
    """``swarmex.missions`` is callable and is the subpackage too: the docs' dotted names
    (``swarmex.missions.registry``, ``swarmex.missions.base.FrameList``,
    ``swarmex.missions.traversal.run_traversal``) were AttributeErrors on a function."""
    assert swarmex.missions() == ["exploration", "foraging", "roadmap", "traversal"]
    assert swarmex.missions.registry.get("traversal").name == "traversal"
    assert callable(swarmex.missions.base.FrameList())
    assert callable(swarmex.missions.traversal.run_traversal)
    with pytest.raises(AttributeError, match="no attribute or module 'nope'"):
        _ = swarmex.missions.nope


def test_import_as_of_a_missions_module_works() -> None:
    code = ("import swarmex.missions.base as b, swarmex.missions.registry as r; "
            "print(b.StopRun.__name__, r.get('foraging').name)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.strip() == "StopRun foraging", out.stderr


def test_wrong_types_are_input_errors_not_tracebacks(tmp_path) -> None:
    """Each was a TypeError or AttributeError from deep inside (``metrics=[1]``: 'int' object
    has no attribute 'removeprefix'), or silently wrong (``progress="no"`` showed the bar)."""
    import pytest

    import swarmex

    table = swarmex.sweep("traversal", out=tmp_path / "s", grid="3x3", agents=[1, 2],
                          seeds=1, backend="serial", progress=False)
    for call, said in (
        (lambda: swarmex.compare(table, {"agents": 1}, None), "metrics must be"),
        (lambda: swarmex.compare(table, {"agents": 1}, [1]), "metrics must be"),
        (lambda: swarmex.compare(table, {"agents": 1}, []), "metrics must be"),
        (lambda: swarmex.plot(table, "agents", None), "y must be a column name"),
        (lambda: swarmex.run("traversal", grid="3x3", agents=1, progress="no"),
         "progress must be True or False"),
        (lambda: swarmex.render({}, None), "path must be a file name"),
        # a string is truthy: retry_failed="no" retried and rewrote every failed run
        (lambda: swarmex.sweep("traversal", out=tmp_path / "s", grid="3x3", agents=1,
                               retry_failed="no"), "retry_failed must be True or False"),
        (lambda: swarmex.sweep("traversal", out=tmp_path / "s", grid="3x3", agents=1,
                               progress="no"), "progress must be True or False"),
        (lambda: swarmex.sweep("traversal", out=None, grid="3x3", agents=1),  # type: ignore[arg-type]
         "out must be the sweep's folder"),
        (lambda: swarmex.sweep("traversal", out=tmp_path / "s", fixed=["nests"],  # type: ignore[arg-type]
                               grid="3x3", agents=1), "fixed must be a dict"),
        (lambda: swarmex.sweep("traversal", out=tmp_path / "s", workers=1.5,  # type: ignore[arg-type]
                               grid="3x3", agents=1), "workers must be a whole number"),
        (lambda: swarmex.run(["traversal"], grid="3x3", agents=1),  # type: ignore[arg-type]
         "a mission is a name"),
        (lambda: swarmex.describe(["traversal"]), "a mission is a name"),  # type: ignore[arg-type]
        (lambda: swarmex.plot(table, "agents", "makespan", out=5),  # type: ignore[arg-type]
         "out must be a file name"),
        (lambda: swarmex.ResultRecord.read(None),  # type: ignore[arg-type]
         "ResultRecord.read: the path must be a file name"),
        (lambda: swarmex.run("traversal", grid="3x3", agents=1).write(None),  # type: ignore[arg-type]
         "ResultRecord.write: the path must be a file name"),
    ):
        with pytest.raises(swarmex.InputError, match=said):
            call()
    from pathlib import PurePath

    assert swarmex.compare(PurePath(tmp_path / "s"), {"agents": 1}).num_rows > 0
