"""The cyclic garbage collector during a run: collect rarely, or not at all.

A simulation allocates millions of short-lived, acyclic containers (messages, option lists,
a record's trajectory rows). CPython's collector walks the young generation every 700
allocations and, every so often, every object alive; with millions of rows alive that makes
building a record quadratic in its size. The runs make no cyclic garbage, so collecting less
changes nothing but the time. Both settings are process-wide, like every ``gc`` setting: a
concurrent run only collects less often; each is restored on exit.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator

# the collector's generation-0 threshold during a run (CPython's default is 700)
GC_YOUNG = 100_000


@contextlib.contextmanager
def fewer_collections() -> Iterator[None]:
    """Raise the young generation's threshold to :data:`GC_YOUNG` while a simulation runs
    (a 40-robot exploration spent 15 % of its CPU in the collector)."""
    old = gc.get_threshold()
    gc.set_threshold(max(old[0], GC_YOUNG), *old[1:])
    try:
        yield
    finally:
        gc.set_threshold(*old)


@contextlib.contextmanager
def no_collections() -> Iterator[None]:
    """No collection at all, for a bounded burst of acyclic allocations (a record's rows:
    3 M lists for 1,024 foraging robots, where the full collections it triggered cost more
    than the run)."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()
