"""When the Numba-compiled kernels run: one rule for the whole package.

The compiled kernels (:mod:`wobble.numerics.rigid_dop853`, :mod:`wobble.numerics.nome_grid`,
:mod:`wobble.numerics.taylor_table`) import Numba, which costs ~0.4 s once per process
(and a compilation of 10-20 s the first time after installing; the result is cached on
disk). So arrays are handed to them only from :data:`LONG_ARRAY` samples on, where they
save more than NumPy's temporaries cost, and only when Numba is installed: without it
the NumPy paths, which give the same numbers, do the work.
"""

from __future__ import annotations

import importlib.util
from functools import lru_cache

__all__ = ["LONG_ARRAY", "available", "on_first_compilation", "listen"]

#: Samples from which long evaluations (free wobble grids, heavy-top series) are compiled.
LONG_ARRAY = 8192


@lru_cache(maxsize=1)
def available() -> bool:
    """Whether Numba can be imported (looked up without importing it)."""
    return importlib.util.find_spec("numba") is not None


# Called once, at Numba's first compilation in this process (see on_first_compilation).
_FIRST_COMPILATION: list = []
_LISTENING = False


def on_first_compilation(callback) -> None:
    """Have ``callback()`` called when Numba starts its first compilation in this process.

    That happens on the first run after installing (10-25 s; the kernels are cached on disk
    afterwards), which a command line may want to announce. This layer prints nothing: the
    interface registers what to say.
    """
    _FIRST_COMPILATION.append(callback)


def listen() -> None:
    """Forward Numba's first compilation to the callbacks (each kernel module calls this after
    importing Numba; Numba's event API, ``numba.core.event``, reports compilations proper, not
    the loading of a cached kernel)."""
    global _LISTENING
    if _LISTENING:
        return
    _LISTENING = True
    import numba.core.event as ev

    class _First(ev.Listener):
        def on_start(self, event):
            while _FIRST_COMPILATION:
                _FIRST_COMPILATION.pop(0)()

        def on_end(self, event):
            pass

    ev.register("numba:compile", _First())
