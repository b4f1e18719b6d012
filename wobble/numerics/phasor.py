"""Phasors exp(i v) on a uniform time grid, by block rotation (float64, SI).

A long daily series of a wobble (Earth over a century: 36,526 samples) spends
most of its time in two places: reducing v = rate t + offset to a small angle
(in double-double, :func:`wobble.numerics.phase.reduce_phase`) and evaluating
sin and cos. On a uniform grid t_k = t0 + k dt neither is needed per sample:
with blocks of B samples,

    exp(i v_{bB + k}) = exp(i v_{bB}) * exp(i k rate dt),     0 <= k < B,

so the exact reduction and the trigonometric functions are evaluated only at
the ~N/B block starts and the B samples of the first block, and every sample costs one
complex product. Each sample carries the rounding of one product of two
correctly reduced phasors (a few ulps): nothing accumulates from block to block,
unlike a running product exp(i v_k) = exp(i v_{k-1}) exp(i rate dt), whose error
grows like k eps.
"""

from __future__ import annotations

import numpy as np

__all__ = ["GRID_ULPS", "block_length", "block_parts", "block_phasors", "grid_candidate", "uniform_grid"]

#: A grid is taken as uniform when every t_k is within this many ulps of t0 + k dt.
GRID_ULPS = 4.0


def uniform_grid(t: np.ndarray, min_size: int = 256):
    """``(t0, dt)`` when ``t`` is a 1-D uniform grid t_k = t0 + k dt, else None.

    Uniform means within a few ulps of the largest ``|t|`` (``np.linspace`` and
    ``np.arange(n) * dt`` grids pass); the phase error that tolerance can cause is
    ``rate * ulps * eps * max|t|``, the rounding the samples already carry.
    Short or non-finite arrays return None (not worth it, or not a grid).
    """
    cand = grid_candidate(t, min_size)
    if cand is None:
        return None
    t0, dt, tol = cand
    grid = np.arange(t.size, dtype=float)
    grid *= dt
    grid += t0
    grid -= t
    if not np.all(np.abs(grid) <= tol):
        return None
    return t0, dt


def grid_candidate(t: np.ndarray, min_size: int):
    """``(t0, dt, tol)`` of the grid ``t`` would be, tol = GRID_ULPS ulps of the largest ``|t|``;
    None for arrays that cannot be one (not 1-D, shorter than ``min_size``, not increasing)."""
    if t.ndim != 1 or t.size < min_size:
        return None
    t0 = float(t[0])
    dt = (float(t[-1]) - t0) / (t.size - 1)
    if not (np.isfinite(dt) and dt > 0):
        return None
    return t0, dt, GRID_ULPS * np.finfo(float).eps * max(abs(t0), abs(float(t[-1])))


def block_phasors(phasor, t0: float, dt: float, n: int) -> np.ndarray:
    """exp(i v_k) for k < n on the grid t_k = t0 + k dt, by block rotation (v linear in t).

    Parameters
    ----------
    phasor : callable
        ``phasor(times) -> complex ndarray``: the exact exp(i v(t)), with v linear
        in t. Called once, at the first block's B samples (the rotations
        exp(i (v(t0 + k dt) - v(t0))) come from them, reduced exactly however
        large the angle) and the ~n/B block starts.
    t0, dt : float
        The grid (s).
    n : int
        Number of samples.

    Returns
    -------
    numpy.ndarray
        Complex, shape (n,).
    """
    starts, step = block_parts(phasor, t0, dt, n)
    return (starts[:, None] * step[None, :]).reshape(-1)[:n]


def block_length(n: int) -> int:
    """B, the samples per block of a block rotation over n samples (about sqrt(n), at least 16): the
    work is ~n/B + B exact exponentials and n products."""
    return max(16, int(np.sqrt(n)))


def block_parts(phasor, t0: float, dt: float, n: int):
    """The two factors of :func:`block_phasors`: ``exp(i v_{bB})`` at the ~n/B block starts
    and the B rotations ``exp(i k rate dt)``; sample ``bB + k`` is ``starts[b] * step[k]``."""
    block = block_length(n)
    # One call for both sets of times (the phasor's exact reduction costs ~0.1 ms a call).
    z = phasor(t0 + np.concatenate([np.arange(block, dtype=float), np.arange(0, n, block, dtype=float)]) * dt)
    first, starts = z[:block], z[block:]
    step = first * np.conj(first[0])
    return starts, step
