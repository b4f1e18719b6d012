"""Vectorised double-double arithmetic in float64 NumPy (no FMA, no extended precision).

A double-double ``(hi, lo)`` represents ``hi + lo`` with ``|lo| <= ulp(hi)/2``:
about 32 significant digits carried by two float64 arrays. The operations are
built from the error-free transformations of Knuth (two-sum) and Dekker
(two-product by Veltkamp splitting), so they need only IEEE round-to-nearest
``+ - * / sqrt`` and run elementwise on arrays of any shape. Each result is
within a few units of ``2^-104`` relative of the exact operation on the
represented values (T. J. Dekker, Numer. Math. 18, 224 (1971); Y. Hida,
X. S. Li & D. H. Bailey, "Algorithms for quad-double precision floating point
arithmetic", ARITH-15 (2001), the "sloppy" addition excepted: :func:`add` is
their accurate one).

Used where a float64 quantity must be known to more than 16 digits for a
vectorised kernel: the quarter period K(m) of arrays of parameters (AGM in
double-double, :func:`agm_k`), to reduce ``u`` modulo K without losing the
digits of the reduced argument (:func:`wobble.numerics.elliptic.jacobi`), and
Bulirsch's complete integral ``cel`` (:func:`wobble.numerics.elliptic.ellippi`).
Valid for magnitudes between about 1e-290 and 1e300 (Veltkamp's split
overflows above).
"""

from __future__ import annotations

import numpy as np

__all__ = ["PI", "two_sum", "quick_two_sum", "two_prod", "add", "mul", "div", "sqrt", "agm_k", "split3"]

_SPLITTER = 134217729.0  # 2^27 + 1
#: pi as a double-double (hi, lo).
PI = (3.141592653589793, 1.2246467991473532e-16)


def two_sum(a, b):
    """Knuth's error-free sum: ``a + b = s + e`` exactly, any magnitudes."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


def quick_two_sum(a, b):
    """Dekker's error-free sum for ``|a| >= |b|`` (or a = 0): ``a + b = s + e``."""
    s = a + b
    return s, b - (s - a)


def _split(a):
    c = _SPLITTER * a
    hi = c - (c - a)
    return hi, a - hi


def two_prod(a, b):
    """Dekker's error-free product: ``a * b = p + e`` exactly (``|a b| < 1e300``)."""
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


def add(ah, al, bh, bl):
    """Double-double sum ``(ah + al) + (bh + bl)`` (Hida, Li & Bailey's accurate addition)."""
    s, e = two_sum(ah, bh)
    t, f = two_sum(al, bl)
    e = e + t
    s, e = quick_two_sum(s, e)
    e = e + f
    return quick_two_sum(s, e)


def mul(ah, al, bh, bl):
    """Double-double product."""
    p, e = two_prod(ah, bh)
    e = e + (ah * bl + al * bh)
    return quick_two_sum(p, e)


def div(ah, al, bh, bl):
    """Double-double quotient, by one correction of the float quotient (Dekker)."""
    q1 = ah / bh
    p, e = two_prod(q1, bh)
    r = (((ah - p) - e) + al) - q1 * bl
    q2 = r / bh
    return quick_two_sum(q1, q2)


def sqrt(ah, al):
    """Double-double square root of a non-negative value, by one Newton (Heron) correction."""
    s = np.sqrt(ah)
    p, e = two_prod(s, s)
    # (s == 0) keeps the division finite at zero without np.where, so that the same
    # code runs on NumPy scalars (twenty times faster than on 0-d arrays).
    r = ((((ah - p) - e) + al) / (2.0 * s + (s == 0))) * (s != 0)
    return quick_two_sum(s, r)


def agm_k(m1):
    """Complete K(m) = pi / (2 AGM(1, sqrt(m1))) as a double-double, for 0 <= m1 <= 1.

    The arithmetic-geometric mean (A&S 17.6.1) in double-double arithmetic, from the
    exact float complement ``m1 = 1 - m``, until ``a`` and ``b`` agree to four
    float64 ulps, then ``(a + b)/2`` (the neglected term ``(a - b)^2 / (16 a)`` is
    below 1e-31 a). An element that has converged takes no further steps while the
    others iterate, so every element gets the very floats a call with it alone
    would give. Relative error of ``hi + lo`` below 1e-31 for m1 >= 1e-290 (5e-27
    at m1 = 1e-300, where Dekker's products underflow); ``m1 = 0`` gives ``(inf, 0)``.
    About 0.5 us per element for arrays, 30 us for a scalar.

    Returns
    -------
    hi, lo : numpy.ndarray
    """
    m1 = np.asarray(m1, dtype=float)
    if m1.ndim == 0:  # NumPy scalars: no masks, and twenty times faster than 0-d arrays
        x = m1[()]
        if x <= 0:
            return np.asarray(np.inf), np.asarray(0.0)
        a, b = (np.float64(1.0), np.float64(0.0)), sqrt(x, np.float64(0.0))
        while abs(a[0] - b[0]) > 2.0**-50 * a[0]:
            a, b = _agm_step(a, b)
        k = _agm_k_final(a, b)
        return np.asarray(k[0]), np.asarray(k[1])
    zero = m1 <= 0
    a = (np.ones_like(m1), np.zeros_like(m1))
    b = sqrt(np.where(zero, 1.0, m1), np.zeros_like(m1))
    for _ in range(64):
        active = np.abs(a[0] - b[0]) > 2.0**-50 * a[0]
        if not np.any(active):
            break
        a_new, b_new = _agm_step(a, b)
        a = (np.where(active, a_new[0], a[0]), np.where(active, a_new[1], a[1]))
        b = (np.where(active, b_new[0], b[0]), np.where(active, b_new[1], b[1]))
    k = _agm_k_final(a, b)
    return np.where(zero, np.inf, k[0]), np.where(zero, 0.0, k[1])


def _agm_step(a, b):
    s = add(*a, *b)
    return (0.5 * s[0], 0.5 * s[1]), sqrt(*mul(*a, *b))


def _agm_k_final(a, b):
    """pi / (2 M) with M = (a + b)/2: pi / (a + b)."""
    return div(PI[0], PI[1], *add(*a, *b))


def split3(hi, lo):
    """Split ``hi + lo`` into three floats: 26 bits, 26 bits and the rest, elementwise.

    ``j * p1`` and ``j * p2`` are exact for integers ``|j| < 2^27``, so
    ``((x - j p1) - j p2) - j p3`` reduces ``x`` modulo ``hi + lo`` with an error of
    a few ulps of the result plus ``|j|`` times the rounding of ``p3`` (Cody & Waite
    1980; the vectorised form of :func:`wobble.numerics.phase.split_dd`).
    Non-finite or zero ``hi`` gives ``(hi, 0, lo)``.
    """
    hi = np.asarray(hi, dtype=float)
    lo = np.asarray(lo, dtype=float)
    ok = np.isfinite(hi) & (hi != 0.0)
    safe = np.where(ok, np.abs(hi), 1.0)
    e = np.floor(np.log2(safe))
    s1 = np.exp2(e - 25)
    p1 = np.where(ok, np.round(hi / s1) * s1, hi)
    rest = np.where(ok, hi - p1, 0.0)  # exact
    s2 = np.exp2(e - 51)
    p2 = np.round(rest / s2) * s2
    p3 = (rest - p2) + lo
    return p1, p2, np.where(ok, p3, lo)
