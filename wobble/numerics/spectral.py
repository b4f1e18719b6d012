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

Sums are matrix products (BLAS); callers run them with one BLAS thread
(:func:`wobble.numerics.threads.single_blas_thread`): a threaded product of
this shape is 10-100 times slower on a loaded machine, for the threads' start-up.

The grid is walked by the recurrence ``exp(-i omega_{k+1} t) = exp(-i omega_k t)
exp(-i d t)`` (one complex multiplication per sample and frequency instead of an
``exp``), re-seeded with exact exponentials every :data:`RESEED` steps so the
accumulated rounding stays below 1e-13 relative.

At arbitrary frequencies (:func:`dtft_at`) every exponential is exact, or, on a
uniform time grid t_k = t0 + k dt (``grid=(t0, dt)``, from
:func:`wobble.numerics.phasor.uniform_grid`), the product of two exact ones,
exp(-i omega (t0 + b B dt)) exp(-i omega j dt) for sample k = b B + j (block
rotation, as :mod:`wobble.numerics.phasor` does): about 2 sqrt(n) exponentials
instead of n, each sample within a few ulps of the exact exponential, nothing
accumulating (:func:`phases`).
"""

from __future__ import annotations

import numpy as np

from wobble.numerics.phasor import block_length

__all__ = ["RESEED", "dtft", "dtft_at", "exponentials", "phases"]

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

    Notes
    -----
    The exponentials of :data:`RESEED` consecutive frequencies are built by the
    recurrence into one block and multiplied with all the columns at once (one
    matrix product per block instead of one dot product per frequency and
    column: the Python loop was the cost for short records and many columns).
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(z)
    vector = z.ndim == 1
    cols = np.ascontiguousarray(z.reshape(len(t), -1), dtype=complex)
    out = np.empty((count, cols.shape[1]), dtype=complex)
    step = np.exp(-1j * domega * t)
    block = np.empty((min(RESEED, count), len(t)), dtype=complex)
    for k0 in range(0, count, RESEED):
        rows = min(RESEED, count - k0)
        block[0] = np.exp(-1j * (omega0 + k0 * domega) * t)
        for j in range(1, rows):
            np.multiply(block[j - 1], step, out=block[j])
        np.matmul(block[:rows], cols, out=out[k0 : k0 + rows])
    return out[:, 0] if vector else out


def dtft_at(t: np.ndarray, z: np.ndarray, omega, grid: tuple[float, float] | None = None) -> np.ndarray:
    """Equation (1) at arbitrary angular frequencies ``omega`` (rad/s).

    Every exponential is exact; with ``grid = (t0, dt)`` (``t`` is that uniform
    grid: :func:`wobble.numerics.phasor.uniform_grid`) they come from
    :func:`phases` instead, within a few ulps, for a fraction of the cost.
    Returns an array shaped like ``omega`` (times the columns of ``z``).
    """
    t = np.asarray(t, dtype=float)
    omega = np.asarray(omega, dtype=float)
    z = np.asarray(z)
    cols = np.ascontiguousarray(z.reshape(len(t), -1), dtype=complex)
    flat = omega.ravel()
    out = np.empty((flat.size, cols.shape[1]), dtype=complex)
    for k0 in range(0, flat.size, RESEED):  # blocks bound the memory of the exponentials
        np.matmul(exponentials(t, flat[k0 : k0 + RESEED], grid), cols, out=out[k0 : k0 + RESEED])
    shape = omega.shape + (() if z.ndim == 1 else (z.shape[1],))
    return out.reshape(shape)


def exponentials(t: np.ndarray, omega, grid: tuple[float, float] | None = None) -> np.ndarray:
    """exp(-i omega_m t_k), shape (m, n), for the 1-D angular frequencies ``omega`` (rad/s): exact, or,
    with ``grid = (t0, dt)`` (``t`` that uniform grid), by block rotation (:func:`phases`)."""
    if grid is not None:
        return phases(t.size, omega, grid)
    return np.exp(-1j * np.multiply.outer(np.asarray(omega, dtype=float).reshape(-1), t))


def phases(n: int, omega, grid: tuple[float, float]) -> np.ndarray:
    """exp(-i omega_m t_k) on the uniform grid t_k = t0 + k dt, k < n, by block rotation: shape (m, n).

    Sample k = b B + j (B about sqrt(n)) is exp(-i omega (t0 + b B dt)) exp(-i omega j dt):
    two exact exponentials and one complex product, so each sample is within a few
    ulps of exp(-i omega t_k), whatever k (nothing accumulates, unlike a running
    product); the arguments' own rounding, omega t ~ 100 rad to 1e-14, is the same
    either way. ``omega`` is a 1-D array of angular frequencies (rad/s).
    """
    t0, dt = grid
    omega = np.asarray(omega, dtype=float).reshape(-1)
    block = block_length(n)  # as wobble.numerics.phasor's block rotation, for many frequencies here
    starts = np.exp(-1j * np.multiply.outer(omega, t0 + np.arange(0, n, block, dtype=float) * dt))
    steps = np.exp(-1j * np.multiply.outer(omega, np.arange(block, dtype=float) * dt))
    return (starts[:, :, None] * steps[:, None, :]).reshape(omega.size, -1)[:, :n]
