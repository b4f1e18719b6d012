"""The near-circular free wobble on a long uniform grid, compiled (Numba; float64, SI).

What :meth:`wobble.models.free._Elliptic.omega_on_grid` does in NumPy, in one pass
that writes nothing but the output. For m <= 1e-7 (Earth: m ~ 8e-15) the Jacobi
functions are their nome series (DLMF 22.11.1-3, v = pi u / 2K):

    sn = a1 sin v + a3 sin 3v,   cn = c1 cos v + c3 cos 3v,   dn = d0 + d2 cos 2v,

with ``cos 3v = c (4c^2 - 3)``, ``sin 3v = s (3 - 4s^2)`` and ``cos 2v = 2c^2 - 1``, so
each omega component is a polynomial in ``c = cos v`` or ``s = sin v``:

    omega_a = (ka0 c^2 + ka1) c,   omega_b = (kb0 s^2 + kb1) s,   omega_c = kc0 c^2 + kc1,

and ``exp(i v)`` on the grid is ``starts[b] * step[k]`` (block rotation,
:func:`wobble.numerics.phasor.block_parts`). The symmetric body is the case
``a1 = c1 = d0 = 1``, the other coefficients zero.

Why compiled: the NumPy version makes ~3.5 MB of temporaries for a century of days
(36,526 samples) and a dozen passes over them; a fresh process pays page faults for
every new megabyte, which costs more than the arithmetic. Here the output is the only
memory touched. The arithmetic is the NumPy path's, operation for operation, with no
fused multiply-adds; the two agree to an ulp (NumPy's vectorised complex product may
fuse one).

Numba is imported by this module only (~0.4 s once per process).
"""

from __future__ import annotations

import numpy as np

from wobble.numerics import compiled as _compiled
from wobble.numerics.phasor import grid_candidate

__all__ = ["polynomial_omega", "uniform_grid"]

_compiled.listen()  # a command line may announce the first compilation (15 to 35 s after installing)
_jit = _compiled.njit(nogil=True, error_model="numpy")  # cached on disk where Numba can


@_jit
def _grid_within(t, t0, dt, tol):
    """Whether every |t0 + k dt - t_k| <= tol (the same rounding as phasor.uniform_grid)."""
    for k in range(t.shape[0]):
        if not abs(k * dt + t0 - t[k]) <= tol:
            return False
    return True


def uniform_grid(t: np.ndarray, min_size: int = 256):
    """:func:`wobble.numerics.phasor.uniform_grid` without its three temporaries of len(t)."""
    cand = grid_candidate(t, min_size)
    if cand is None:
        return None
    t0, dt, tol = cand
    return (t0, dt) if _grid_within(t, t0, dt, tol) else None


@_jit
def _fill(starts, step, n, cols, coef, out):
    block = step.shape[0]
    ca, cb, cc = cols[0], cols[1], cols[2]
    ka0, ka1, kb0, kb1, kc0, kc1 = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5]
    for b in range(starts.shape[0]):
        sr, si = starts[b].real, starts[b].imag
        base = b * block
        for k in range(min(block, n - base)):
            # (sr + i si)(pr + i pi), written as NumPy's complex product is
            pr, pi = step[k].real, step[k].imag
            zr = sr * pr - si * pi
            zi = sr * pi + si * pr
            c2 = zr * zr
            j = base + k
            out[j, cc] = c2 * kc0 + kc1
            out[j, ca] = (c2 * ka0 + ka1) * zr
            out[j, cb] = (zi * zi * kb0 + kb1) * zi


def polynomial_omega(starts, step, n, cols, coef):
    """omega (n, 3) on the grid: component ``cols[0]`` is ``(ka0 c^2 + ka1) c``, ... (module docstring).

    Parameters
    ----------
    starts, step : numpy.ndarray of complex
        The block factors of exp(i v) (:func:`wobble.numerics.phasor.block_parts`).
    n : int
        Number of samples.
    cols : sequence of 3 int
        Output columns of the cos-, sin- and constant-type components.
    coef : sequence of 6 float
        ``(ka0, ka1, kb0, kb1, kc0, kc1)`` in rad/s, signs included.
    """
    out = np.empty((n, 3))
    _fill(
        np.ascontiguousarray(starts, dtype=complex),
        np.ascontiguousarray(step, dtype=complex),
        int(n),
        np.array(cols, dtype=np.int64),
        np.array(coef, dtype=float),
        out,
    )
    return out
