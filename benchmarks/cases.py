"""What every benchmark case is made of: a :class:`Case` and the error measures.

A case holds its runs (every method at every setting, see :class:`benchmarks.timing.Run`),
the reference it is measured against, and what "error" means for it. The builders are by
solver: :mod:`benchmarks.free` (the exact free body), :mod:`benchmarks.top` (the exact heavy
top), :mod:`benchmarks.torqued` (torques with no exact solution) and
:mod:`benchmarks.user_level` (the public API against the SciPy a user would write). The
references never depend on the method measured:

* exact solutions are measured against the committed mpmath references
  (tests/references/free_rotation.json, heavy_top.json);
* integrators against the exact solution at every output (itself checked against
  mpmath in the test suite) and against mpmath at the reference times; where there
  is no exact solution, against mpmath (tests/references/engine_torqued.json) or a
  cached Radau run at rtol 1e-13 (benchmarks/engine_reference.json).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["SCIPY", "Case", "floats", "rel_error", "phase_error", "grid"]

SCIPY = ("RK45", "DOP853", "LSODA", "Radau")


@dataclass
class Case:
    """One named case: its runs, its reference and what its error means.

    ``complete`` is False when the case was built with fewer settings than the full run
    (``--quick``, ``--smoke``): its targets are then not judged.
    """

    key: str
    title: str
    description: str
    error_measure: str
    reference: str
    outputs: int
    runs: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    context: dict = field(default_factory=dict)
    complete: bool = True


def floats(rows):
    """A reference's decimal strings (a list or a list of lists) as a float64 array."""
    return (
        np.array([[float(v) for v in r] for r in rows])
        if isinstance(rows[0], list)
        else np.array([float(v) for v in rows])
    )


def rel_error(got, want) -> float:
    """max over rows of ``|got - want| / |want|`` (vectors along the last axis)."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    if got.shape != want.shape or not np.all(np.isfinite(got)):
        return math.inf
    return float(np.max(np.linalg.norm(got - want, axis=-1) / np.linalg.norm(want, axis=-1)))


def phase_error(got, want) -> float:
    """max wrapped difference (rad) of the wobble phase ``atan2(omega_2, omega_1)``."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    if got.shape != want.shape or not np.all(np.isfinite(got)):
        return math.inf
    d = np.arctan2(got[:, 1], got[:, 0]) - np.arctan2(want[:, 1], want[:, 0])
    return float(np.max(np.abs(np.angle(np.exp(1j * d)))))


def grid(t, *extra):
    """The case's output times with the reference times merged in, and their indices."""
    full = np.union1d(t, np.concatenate([np.asarray(e, float) for e in extra]) if extra else [])
    return full, [np.searchsorted(full, e) for e in extra]
