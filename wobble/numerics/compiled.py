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

__all__ = ["LONG_ARRAY", "available"]

#: Samples from which long evaluations (free wobble grids, heavy-top series) are compiled.
LONG_ARRAY = 8192


@lru_cache(maxsize=1)
def available() -> bool:
    """Whether Numba can be imported (looked up without importing it)."""
    return importlib.util.find_spec("numba") is not None
