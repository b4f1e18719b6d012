"""Phases over long spans: double-double products and exact reduction (float64, SI).

A phase ``x = rate * t + offset`` over 10^6 periods has lost six digits if it
is formed in plain float64 (the product rounds to ``|x| eps``). Here the rate
and the period are carried as double-double pairs ``(hi, lo)`` (computed once
per solution to ~32 digits, see :mod:`wobble.numerics.highprec`), the product
``rate * t`` is formed exactly with Dekker's two-product (vectorised NumPy, no
FMA needed), and the reduction modulo the period uses a three-piece split of
the period. The reduced phase then carries an error of a few ulps of the
*reduced* value, whatever ``t`` is: the bound is independent of the span
(T. J. Dekker, Numer. Math. 18, 224 (1971); W. J. Cody & W. Waite, Software
Manual for the Elementary Functions, 1980).
"""

from __future__ import annotations

import math

import numpy as np

# The error-free transformations (Knuth's two-sum, Dekker's two-product) are those of the
# double-double arithmetic.
from wobble.numerics.double_double import WHOLE_PIECES, minus_multiple, two_prod, two_sum

__all__ = ["split_dd", "reduce_phase", "PER_SAMPLE", "REACH"]

#: Whole periods up to which :func:`reduce_phase` keeps its bound (a few ulps of the period): past
#: 2^26 the multiple of the period is Dekker's exact product, while the double-double phase's own
#: rounding, about ``|phase| eps^2``, stays below an ulp of the period to about here. The models
#: refuse times beyond (``HeavyTopModel.max_time``, ``FreeRotationModel.max_time``).
REACH = 2.0**50

# The index base that means 'one table entry per sample': no dense range of whole half-periods
# starts there (|j| stays far below 2**62); the earlier test 'base < 0' took every range over
# negative times for it.
PER_SAMPLE = -(2**62)


def split_dd(hi: float, lo: float):
    """Split a double-double ``hi + lo`` into three floats of 26, 26 and the rest bits.

    ``j * piece`` is exact for the first two pieces when ``|j| < 2^26``.
    """
    hi = float(hi)
    if hi == 0.0 or not math.isfinite(hi):
        return hi, 0.0, float(lo)
    # Python floats (the C library's log2, round half to even as np.round): a scalar each time.
    e = math.floor(math.log2(abs(hi)))
    s1 = 2.0 ** (e - 25)
    p1 = round(hi / s1) * s1
    rest = hi - p1  # exact
    s2 = 2.0 ** (e - 51)
    p2 = round(rest / s2) * s2
    p3 = (rest - p2) + lo
    return float(p1), float(p2), float(p3)


def _reduce_far(x, lo, j, period):
    """x + lo - j (period[0] + period[1]) for |j| >= 2^26, where j p1 of the three-piece split is no
    longer exact: :func:`~wobble.numerics.double_double.minus_multiple` (Dekker's exact j period[0])."""
    r, r_lo = minus_multiple(x, j, period[0], period[1])
    return r + (r_lo + lo)


def reduce_phase(t, rate, period, offset: float = 0.0):
    """Reduce ``x = rate * t + offset`` modulo ``period``: ``x = j * period + r``.

    Parameters
    ----------
    t : numpy.ndarray
        Times (s), exact float64 values.
    rate : tuple of float
        Double-double ``(hi, lo)`` rate (phase per second).
    period : tuple of float
        Double-double ``(hi, lo)`` period of the phase; ``hi = inf`` means no
        reduction (``j = 0``).
    offset : float
        Phase at t = 0, added before the reduction.

    Returns
    -------
    r : numpy.ndarray
        ``|r| <= period/2``, with an absolute error of a few ulps of ``period``,
        independent of t: by the three-piece split for ``|j| < 2^26`` (6.7e7 periods), by
        Dekker's exact product ``j period`` beyond (to ``|j|`` ~ 2^50).
    j : numpy.ndarray
        Integer-valued float array.
    """
    t = np.asarray(t, dtype=float)
    p, e = two_prod(t, rate[0])
    e = e + t * rate[1]
    x, e2 = two_sum(p, offset)
    lo = e + e2
    if not np.isfinite(period[0]):
        return x + lo, np.zeros_like(x)
    j = np.rint((x + lo) / period[0])
    p1, p2, p3 = split_dd(*period)
    r = ((x - j * p1) - j * p2) + (lo - j * p3)
    big = np.abs(j) >= WHOLE_PIECES
    if np.any(big):
        r = np.where(big, _reduce_far(x, lo, j, period), r)
    # rint of the rounded quotient can miss by one near r = +-period/2 (by up to
    # |j| eps period): step back inside, so that |r| <= period/2 holds as stated.
    # (Callers such as Pi(n; am r | m) from sn and |cn| are not periodic beyond it.)
    half = 0.5 * period[0]
    over = r > half
    under = r < -half
    if np.any(over) or np.any(under):
        r = np.where(over, ((r - p1) - p2) - p3, np.where(under, ((r + p1) + p2) + p3, r))
        j = j + over - under
    return r, j
