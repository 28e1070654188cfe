"""What a user gets from ``pip install swarmex`` (a wheel, no extras), not from the editable
install with every extra that the rest of the suite runs in.

Why here and not by building a wheel: ``pip wheel`` takes seconds and the network-free
suite should not; so these tests check the declarations a wheel is built from (pyproject's
package data, version) and what the installed CLI says about itself.
"""

from __future__ import annotations

import fnmatch
import tomllib
from pathlib import Path

import swarmex
from swarmex.cli import main
from swarmex.cli.app import installed_version

ROOT = Path(swarmex.__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "swarmex"
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_version_option_prints_the_installed_version(capsys):
    assert main(["--version"]) == 0
    out = capsys.readouterr().out
    assert out == f"swarmex {installed_version()}\n"


def test_source_version_is_pyprojects():
    """``swarmex.__version__`` (written into every record) is the version pip installs."""
    assert swarmex.__version__ == PYPROJECT["project"]["version"]


def test_every_data_file_of_the_package_goes_into_the_wheel():
    """A file under src/swarmex that is not Python is read at run time (reference tables,
    py.typed); setuptools ships it only when pyproject's package-data names it, and a wheel
    without it fails only for users (the editable install reads the source tree)."""
    globs = PYPROJECT["tool"]["setuptools"]["package-data"]["swarmex"]
    data = [p.relative_to(PACKAGE).as_posix() for p in PACKAGE.rglob("*")
            if p.is_file() and p.suffix not in (".py", ".pyc") and "__pycache__" not in p.parts
            and p.suffix not in (".nbi", ".nbc")]
    assert "py.typed" in data
    missing = [f for f in data if not any(fnmatch.fnmatch(f, g) for g in globs)]
    assert missing == [], f"add to [tool.setuptools.package-data]: {missing}"


def test_license_is_an_spdx_expression_and_the_backend_can_read_it():
    """``license = { text = ... }`` is deprecated by setuptools, which warns that builds with
    it will fail after 2027-02-18: the SPDX string (PEP 639) needs setuptools >= 77."""
    assert isinstance(PYPROJECT["project"]["license"], str)
    requires = PYPROJECT["build-system"]["requires"]
    floor = next(r for r in requires if r.startswith("setuptools"))
    assert tuple(int(p) for p in floor.split(">=")[1].split(".")) >= (77,)


#: Floors measured by installing the wheel with each base dependency at a lower version
#: (docs: README "Installing"); a floor below these lets pip build a broken environment.
MEASURED_FLOORS = {
    # 0.12.0: `int | None` options raise "Type not yet supported" and typer.core has no
    # DEFAULT_MARKUP_MODE; 0.13-0.15.3 do not cap click, and with click >= 8.2 every
    # mission's --help fails (Parameter.make_metavar() missing 'ctx')
    "typer": (0, 15, 4),
    # 14.0.x does not cap numpy, installs beside numpy 2 and fails to import
    # ("numpy.core.multiarray failed to import"); 15.x caps numpy < 2; 16 supports numpy 2
    "pyarrow": (16,),
    # pyarrow 26 declares no numpy requirement and refuses numpy 1.x at import ("pyarrow
    # requires NumPy 2.0 or newer"): with numpy 1.26 kept, pip installed it and sweeps failed
    "numpy": (2, 0),
    # the first releases that declare numpy 2 support (older ones cap numpy < 2)
    "numba": (0, 60),
    "scipy": (1, 13),
    "matplotlib": (3, 8, 4),
    "shapely": (2, 0, 4),
}


def _floors() -> dict[str, tuple[int, ...]]:
    out = {}
    for req in PYPROJECT["project"]["dependencies"]:
        name, _, floor = req.partition(">=")
        out[name.strip().lower()] = tuple(int(p) for p in floor.split(",")[0].split("."))
    return out


def test_dependency_floors_are_at_least_the_measured_ones():
    floors = _floors()
    low = {n: floors.get(n) for n, v in MEASURED_FLOORS.items() if floors.get(n, ()) < v}
    assert low == {}, f"floors below what was measured to work: {low}"
