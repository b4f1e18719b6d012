"""When the Numba-compiled kernels run: one rule for the whole package.

The compiled kernels (:mod:`wobble.numerics.rigid_dop853`, :mod:`wobble.numerics.nome_grid`,
:mod:`wobble.numerics.taylor_table`) import Numba, which costs ~0.4 s once per process
(and a compilation of 15 to 35 s the first time after installing; the result is cached on
disk). So arrays are handed to them only from :data:`LONG_ARRAY` samples on, where they
save more than NumPy's temporaries cost, and only when Numba is installed: without it
the NumPy paths, which give the same numbers, do the work.
"""

from __future__ import annotations

import contextlib
import importlib.util
import os
import sys
import threading
from functools import lru_cache

__all__ = ["LONG_ARRAY", "activity", "available", "compilation_notice", "listen", "njit"]

#: Samples from which long evaluations (free wobble grids, heavy-top series) are compiled.
LONG_ARRAY = 8192


@lru_cache(maxsize=1)
def available() -> bool:
    """Whether the compiled kernels run: Numba can be imported (looked up without importing it) and
    its compiler is not switched off (``NUMBA_DISABLE_JIT``, under which the kernels' intrinsics
    cannot run as Python: the NumPy paths, which give the same numbers, do the work)."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0").strip() not in ("", "0"):
        return False
    return importlib.util.find_spec("numba") is not None


def njit(**options):
    """``numba.njit(cache=True, **options)`` as a decorator, or, where Numba finds no place to cache
    the kernel (a read-only installation and no writable cache directory: "cannot cache function
    ...: no locator available"), ``numba.njit(cache=False, **options)``: compiled in memory in each
    process (15 to 35 s) instead of failing."""
    import numba as nb

    def decorate(fn):
        try:
            return nb.njit(cache=True, **options)(fn)
        except RuntimeError as exc:
            if "cannot cache" not in str(exc):
                raise
            return nb.njit(cache=False, **options)(fn)

    return decorate


class _Watch:
    """Numba's just-in-time work in this process, through its event API (``numba.core.event``).

    Every kernel Numba loads from its disk cache or compiles takes its compiler lock (a
    ``"numba:compiler_lock"`` event); a compilation proper is also a ``"numba:compile"`` event.
    """

    def __init__(self):
        self.lock = threading.Lock()
        self.listening = False
        self.loads = 0  # compiler-lock acquisitions: kernels loaded or compiled
        self.compilations = 0  # "numba:compile" events
        self.notice = None  # [callback, already called] of the innermost compilation_notice block


_WATCH = _Watch()


def listen() -> None:
    """Start watching Numba's just-in-time work (imports Numba). Each kernel module calls it after
    importing Numba; a caller that must see the very first compilation calls it before."""
    if _WATCH.listening:
        return
    import numba.core.event as ev

    class _Listener(ev.Listener):
        def __init__(self, compile_event: bool):
            self.compile_event = compile_event

        def on_start(self, event):
            with _WATCH.lock:
                if self.compile_event:
                    _WATCH.compilations += 1
                else:
                    _WATCH.loads += 1
                notice = _WATCH.notice
                say = self.compile_event and notice is not None and not notice[1]
                if say:
                    notice[1] = True
            if say:
                notice[0]()

        def on_end(self, event):
            pass

    with _WATCH.lock:
        if _WATCH.listening:
            return
        ev.register("numba:compiler_lock", _Listener(False))
        ev.register("numba:compile", _Listener(True))
        _WATCH.listening = True


def activity() -> tuple[bool, int, int]:
    """(Numba imported, kernels loaded or compiled, compilations) so far: a value that changes
    whenever Numba is imported, loads a kernel or compiles one (starts watching once it is imported)."""
    imported = "numba" in sys.modules
    if imported:
        listen()
    return imported, _WATCH.loads, _WATCH.compilations


@contextlib.contextmanager
def compilation_notice(callback):
    """Within the block, call ``callback()`` once when Numba starts compiling (the first run after
    installing: 15 to 35 s; the kernels are cached on disk afterwards), for a caller that announces it.
    This layer prints nothing. An inner block takes over from an outer one until it ends."""
    previous, _WATCH.notice = _WATCH.notice, [callback, False]
    try:
        yield
    finally:
        _WATCH.notice = previous
