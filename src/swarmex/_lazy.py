"""Package exports that load on first use (PEP 562).

Why: importing one module of a mission package (its Params, for the command line's options)
must not import the simulator and its compiled kernels, yet ``from swarmex.missions.roadmap
import run_roadmap`` should keep working. A package lists its exports as name -> submodule
and delegates its module-level ``__getattr__`` here.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any


def lazy_attribute(package: str, exports: dict[str, str], name: str) -> Any:
    """``package.name``, imported from ``package.<exports[name]>`` when first asked for."""
    if name in exports:
        return getattr(import_module(f"{package}.{exports[name]}"), name)
    raise AttributeError(f"module {package!r} has no attribute {name!r}")
