"""Compiled kernels that load numba only when a kernel first runs compiled.

Every loop swarmex cannot vectorise is a *kernel*: a plain Python function over numpy arrays
and numbers, decorated with :func:`kernel` (``@kernel(cache=True, nogil=True)`` where one
would write ``@numba.njit(...)``). The decorator does not import numba. The first call that
runs compiled imports it, compiles the function (or loads the machine code from numba's disk
cache, see :mod:`swarmex._jitcache`) and keeps the dispatcher; every later call goes straight
to it.

Why not ``numba.njit`` at import time: a process that touches kernels pays about 0.8 s of CPU
before its first result even when every kernel comes from the cache (numba's import 0.3 s,
which imports ``scipy.linalg`` for its BLAS check; its target registries 0.15-0.2 s on the
first cache load; the kernel modules 0.1 s). A one-shot run on a small map does less work
than that in total: ``swarmex demo``'s 16x16 map runs in 0.25 s with the kernels
interpreted. So a caller that knows its run is small opens :func:`interpreted_while_cold`:
inside, kernels run their Python source *unless numba is already imported* in the process
(then compiling from the cache costs milliseconds per kernel and compiled code is faster).

Interpreted and compiled calls give the same results: numba compiles the Python source with
IEEE floating point (no ``fastmath``, no fused multiply-add) and the kernels use no integer
that could wrap, so the golden records are identical either way (``NUMBA_DISABLE_JIT=1``
runs every kernel interpreted; ``tests/test_kernels.py`` compares both routes).

A compiled kernel calls another kernel as usual: numba types a :class:`Kernel` found in a
function's globals as its dispatcher (registered when numba is loaded), so nesting, inlining
(``inline="always"``) and caching work as with plain dispatchers.

Once a kernel's dispatcher exists, the names that bind the kernel in swarmex's modules (its
own module's and every ``from ... import kernel``) are rebound to the dispatcher itself:
Python code then calls numba directly. Without that, each call would pay one more Python
frame (0.5-1.5 microseconds); the traversal simulator makes ~60,000 kernel calls on a
128x128 map, 5-8 % of its run. Other references (a test's own import, a user's) keep
working through the :class:`Kernel`, which forwards to the same dispatcher.
"""

from __future__ import annotations

import contextlib
import functools
import sys
import threading
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])

_lock = threading.RLock()
_interpreting = 0  # depth of interpreted_while_cold blocks (process-wide: threads share runs)
_on_load: list[Callable[[], None]] = []  # run once numba is imported (compile notices)
_registered = False  # numba knows how to type a Kernel
_cache_checked = False  # stale cached kernels dropped (swarmex._jitcache.check_kernel_cache)
_all: list[Kernel] = []  # every kernel defined, in definition order


def jit_loaded() -> bool:
    """Whether numba is imported in this process (by a kernel or by anyone else)."""
    return "numba" in sys.modules


def interpreting() -> bool:
    """Whether a kernel called now runs as Python (inside :func:`interpreted_while_cold`,
    numba not imported): callers that also have a vectorised numpy route take it then."""
    return bool(_interpreting) and not jit_loaded()


def _load_numba() -> Any:
    """Import numba, teach it the Kernel type, tell whoever waits for it."""
    global _registered, _cache_checked
    with _lock:
        if not _cache_checked:  # before numba reads a cached kernel of ours
            from swarmex._jitcache import check_kernel_cache

            check_kernel_cache()
            _cache_checked = True
        import numba

        if not _registered:
            from numba.core import types
            from numba.extending import typeof_impl

            @typeof_impl.register(Kernel)
            def _typeof_kernel(val: Kernel, c: Any) -> Any:
                return types.Dispatcher(val.dispatcher)

            _registered = True
            waiting = list(_on_load)
            _on_load.clear()
            for callback in waiting:
                callback()
        return numba


def when_loaded(callback: Callable[[], None]) -> Callable[[], None]:
    """Call ``callback`` once numba is imported: now if it is, else when a kernel loads it.

    Returns a function that withdraws a callback that has not run yet. (What imports numba
    other than a kernel is not watched: such code compiles its own functions.)"""
    with _lock:
        if jit_loaded():
            callback()
            return lambda: None
        _on_load.append(callback)

    def withdraw() -> None:
        with _lock, contextlib.suppress(ValueError):
            _on_load.remove(callback)

    return withdraw


@contextlib.contextmanager
def interpreted_while_cold(enabled: bool = True) -> Iterator[None]:
    """Within the block, kernels run as Python while numba is not imported in the process.

    For one-shot runs small enough that loading numba would cost more than the whole run
    interpreted (``enabled`` says whether this one is). Threads the run starts (the field
    cache's prefetch) follow the same rule. Results are the same either way."""
    global _interpreting
    if not enabled:
        yield
        return
    with _lock:
        _interpreting += 1
    try:
        yield
    finally:
        with _lock:
            _interpreting -= 1


class Kernel:
    """A function numba compiles on first use (see the module's docstring).

    ``py_func`` is the Python source, ``options`` the ``numba.njit`` options; attributes of
    the dispatcher (``stats``, ``signatures``, ...) are reachable on the kernel and load it.
    """

    def __init__(self, func: Callable[..., Any], options: dict[str, Any]) -> None:
        self.py_func = func
        #: what an interpreted call runs: the source, or a numpy twin (:func:`twin`)
        self.interpreted: Callable[..., Any] = func
        self.options = options
        self._dispatcher: Any = None
        functools.update_wrapper(self, func)

    @property
    def dispatcher(self) -> Any:
        """The numba dispatcher (imports numba and compiles or loads on first use)."""
        d = self._dispatcher
        if d is None:
            with _lock:
                if self._dispatcher is None:
                    numba = _load_numba()
                    self._dispatcher = numba.njit(**self.options)(self.py_func)
                    self._rebind()
                d = self._dispatcher
        return d

    def _rebind(self) -> None:
        """Point the names bound to this kernel in its package's modules at the dispatcher
        (see the module's docstring: calls from Python skip a frame)."""
        package = self.__module__.partition(".")[0] + "."
        for name, module in list(sys.modules.items()):
            if not name.startswith(package) or module is None:
                continue
            space = getattr(module, "__dict__", None)
            if not space:
                continue
            for key, value in list(space.items()):
                if value is self:
                    space[key] = self._dispatcher

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        d = self._dispatcher
        if d is None:
            if _interpreting and not jit_loaded():
                return self.interpreted(*args, **kwargs)
            d = self.dispatcher
        return d(*args, **kwargs)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") or name in ("py_func", "interpreted", "options",
                                             "_dispatcher"):
            raise AttributeError(name)
        return getattr(self.dispatcher, name)

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled by reference, like a function: what its module binds under its name
        (the kernel, or its dispatcher once loaded)."""
        return (_by_name, (self.__module__, self.__qualname__))

    def __repr__(self) -> str:
        state = "loaded" if self._dispatcher is not None else "not loaded"
        return f"<kernel {self.__module__}.{self.__qualname__} ({state})>"


def _by_name(module: str, qualname: str) -> Any:
    import importlib

    obj: Any = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    return obj


def kernels() -> list[Kernel]:
    """Every kernel defined so far (imported modules only), loaded or not."""
    return list(_all)


def twin(of: Callable[..., Any]) -> Callable[[F], F]:
    """``@twin(kernel_function)``: a numpy formulation of the kernel's computation that
    interpreted calls run instead of its loops (element-by-element loops are where the
    interpreter is slowest). It must return exactly what the kernel returns and write
    exactly what it writes; a test compares the two on random inputs."""

    def register(func: F) -> F:
        if not isinstance(of, Kernel):
            raise TypeError(f"{of!r} is not a kernel")
        of.interpreted = func
        return func

    return register


def kernel(**options: Any) -> Callable[[F], F]:
    """``@kernel(cache=True, nogil=True)``: ``numba.njit`` with the same options, deferred.

    Typed as the function it wraps, so callers keep its signature."""

    def wrap(func: F) -> F:
        k = Kernel(func, options)
        _all.append(k)
        return k  # type: ignore[return-value]

    return wrap


__all__ = ["Kernel", "interpreted_while_cold", "interpreting", "jit_loaded", "kernel", "kernels",
           "twin", "when_loaded"]
