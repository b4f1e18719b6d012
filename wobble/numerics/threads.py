"""One BLAS thread for the polar-motion computations: small products are faster without a thread pool.

The polar-motion estimators and forecasts do many small linear-algebra calls
(dot products of ~20,000 samples, QR of a few columns, 3x3 to 10x10 solves).
OpenBLAS spreads each over its thread pool; on a machine whose cores are busy
the threads wait for one another, and the same computation was measured 5 to
50 times slower (``wobble polar-motion``: 0.05 s against 0.75 s for one Fourier
sum of the whole record on two loaded cores). :func:`single_blas_thread` limits
the BLAS pool to one thread for the duration of a ``with`` block (threadpoolctl,
the library scikit-learn uses for the same purpose) and restores it afterwards;
nested blocks cost nothing. The limit is the process's (a BLAS library has one pool): other
threads of a caller's program also run their BLAS calls on one thread while a polar-motion
call is under way (docs/polar-motion.md says so).
"""

from __future__ import annotations

import contextlib
import functools
import threading

__all__ = ["single_blas_thread", "one_blas_thread"]

_state = threading.local()


@contextlib.contextmanager
def single_blas_thread():
    """Run the block with one BLAS thread (re-entrant; the caller's setting is restored)."""
    if getattr(_state, "depth", 0):
        _state.depth += 1
        try:
            yield
        finally:
            _state.depth -= 1
        return
    _state.depth = 1
    try:
        with _controller().limit(limits=1, user_api="blas"):
            yield
    finally:
        _state.depth = 0


@functools.lru_cache(maxsize=1)
def _controller():
    """The BLAS libraries of this process, found once (scanning them costs ~2 ms a call).

    Looked up at the first use, when NumPy's and SciPy's BLAS are both loaded
    (the callers import SciPy before they compute).
    """
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def one_blas_thread(func):
    """Decorator: ``func`` runs inside :func:`single_blas_thread`."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with single_blas_thread():
            return func(*args, **kwargs)

    return wrapper
