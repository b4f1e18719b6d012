"""Fourier sums of unevenly sampled complex series, in float64.

The discrete-time Fourier transform of samples ``z_n`` taken at arbitrary
times ``t_n`` (seconds),

    F(omega) = sum_n z_n exp(-i omega t_n),                                 (1)

evaluated on a uniform grid of angular frequencies ``omega_k = omega_0 + k d``
(rad/s, negative and positive: a complex series has a two-sided spectrum).
Gaps and uneven sampling need no interpolation: (1) is summed over the samples
that exist. For a complex series the least-squares fit of one complex
exponential ``a exp(i omega t)`` has a single basis function, so ``|F|^2``
*is* the least-squares (Lomb-Scargle) spectrum; no time shift is needed.

The grid is walked by the recurrence ``exp(-i omega_{k+1} t) = exp(-i omega_k t)
exp(-i d t)`` (one complex multiplication per sample and frequency instead of an
``exp``), re-seeded with exact exponentials every :data:`RESEED` steps so the
accumulated rounding stays below 1e-13 relative.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RESEED", "dtft", "dtft_at"]

RESEED = 64


def dtft(t: np.ndarray, z: np.ndarray, omega0: float, domega: float, count: int) -> np.ndarray:
    """Equation (1) on the grid ``omega0 + k*domega``, ``k = 0 .. count-1``.

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times, s. Centre them (subtract a mid epoch) so the phases
        ``omega t`` stay small and exact.
    z : ndarray, shape (n,) or (n, m)
        Complex (or real) samples; with two dimensions every column is
        transformed (the columns share the exponentials).
    omega0, domega : float
        First angular frequency and step, rad/s.
    count : int
        Number of frequencies.

    Returns
    -------
    ndarray, complex, shape (count,) or (count, m)
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(z)
    vector = z.ndim == 1
    rows = _rows(z, len(t))
    out = np.empty((count, len(rows)), dtype=complex)
    step = np.exp(-1j * domega * t)
    current = None
    for k in range(count):
        if k % RESEED == 0:
            current = np.exp(-1j * (omega0 + k * domega) * t)
        else:
            current *= step
        for j, row in enumerate(rows):
            out[k, j] = np.dot(row, current)
    return out[:, 0] if vector else out


def _rows(z: np.ndarray, n: int) -> list[np.ndarray]:
    """The columns of ``z`` as contiguous complex rows.

    Sums are taken one row at a time with 1-D ``np.dot`` (a single-threaded
    BLAS dot): a threaded matrix-vector product of this shape is 10-100
    times slower on a loaded machine, for the threads' start-up.
    """
    zt = np.ascontiguousarray(np.asarray(z).reshape(n, -1).T, dtype=complex)
    return list(zt)


def dtft_at(t: np.ndarray, z: np.ndarray, omega) -> np.ndarray:
    """Equation (1) at arbitrary angular frequencies ``omega`` (rad/s), exactly.

    Returns an array shaped like ``omega`` (times the columns of ``z``).
    """
    t = np.asarray(t, dtype=float)
    omega = np.asarray(omega, dtype=float)
    z = np.asarray(z)
    rows = _rows(z, len(t))
    flat = omega.ravel()
    out = np.empty((flat.size, len(rows)), dtype=complex)
    for k, w in enumerate(flat):
        phase = np.exp(-1j * w * t)
        for j, row in enumerate(rows):
            out[k, j] = np.dot(row, phase)
    shape = omega.shape + (() if z.ndim == 1 else (z.shape[1],))
    return out.reshape(shape)
