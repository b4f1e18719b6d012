"""The first-order linear recurrence x_k = lambda x_{k-1} + c_k with a constant factor, by blocks.

For a constant complex factor lambda (|lambda| <= 1) the recurrence over a block
of B steps from the state x_{k0-1} is

    x_{k0+i} = lambda^(i+1) x_{k0-1} + sum_{j<=i} lambda^(i-j) c_{k0+j},     0 <= i < B,

one product with a lower-triangular Toeplitz matrix of powers for every column
at once, instead of B Python-level steps. (scipy.signal.lfilter runs the same
recurrence in C, but importing scipy.signal costs ~0.4 s.) The powers are exact
exponentials, lambda^k = exp(k a) for lambda = exp(a); each value carries the
rounding of one block's sums (a few ulps times B), and nothing accumulates from
block to block beyond what the recurrence itself carries over (|lambda| <= 1).

Plain float64/complex128; no units.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BLOCK", "linear_recurrence"]

#: Steps per block (a 64 x 64 matrix of powers).
BLOCK = 64


def linear_recurrence(first, log_factor: complex, kicks) -> np.ndarray:
    """x_0 = ``first``; x_k = exp(``log_factor``) x_{k-1} + ``kicks[k-1]`` for k = 1 .. len(kicks).

    Parameters
    ----------
    first : array_like, shape (m,)
        The first state of every column.
    log_factor : complex
        a, with the factor lambda = exp(a) (Re a <= 0: no growth).
    kicks : array_like, shape (n - 1, m)
        c_1 .. c_{n-1}.

    Returns
    -------
    numpy.ndarray
        complex, shape (n, m): x_0 .. x_{n-1}.
    """
    kicks = np.asarray(kicks, dtype=complex)
    first = np.asarray(first, dtype=complex)
    out = np.empty((kicks.shape[0] + 1, first.size), dtype=complex)
    out[0] = first
    powers = np.exp(log_factor * np.arange(BLOCK + 1))
    lag = np.subtract.outer(np.arange(BLOCK), np.arange(BLOCK))
    toeplitz = np.where(lag >= 0, powers[np.clip(lag, 0, BLOCK)], 0)
    for k0 in range(1, out.shape[0], BLOCK):
        b = min(BLOCK, out.shape[0] - k0)
        out[k0 : k0 + b] = toeplitz[:b, :b] @ kicks[k0 - 1 : k0 - 1 + b] + powers[1 : b + 1, None] * out[k0 - 1]
    return out
