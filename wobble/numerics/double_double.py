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
Valid for magnitudes between about 1e-290 and the largest double (Veltkamp's split
scales operands above 2^996 by 2^-28 first, as Hida, Li & Bailey's library does, so that
the splitting constant's product does not overflow); a product must fit a double.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "PI",
    "two_sum",
    "quick_two_sum",
    "two_prod",
    "add",
    "add_same_sign",
    "mul",
    "div",
    "sqrt",
    "sqrt_float",
    "agm_k",
    "agm_ke",
    "split3",
    "minus_multiple",
    "SPLIT_THRESHOLD",
    "WHOLE_PIECES",
]

_SPLITTER = 134217729.0  # 2^27 + 1
# Above 2^996 the product _SPLITTER * a overflows: such operands are split scaled by 2^-28
# (exact, a power of two) and the halves scaled back.
SPLIT_THRESHOLD = 2.0**996
_SPLIT_SCALE = 2.0**-28
#: Multiples up to which j times each 26-bit piece of a split period (:func:`split3`,
#: :func:`wobble.numerics.phase.split_dd`) is exact; past it, :func:`minus_multiple`.
WHOLE_PIECES = float(2**26)
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
    # A comparison and a reduction instead of np.where: the same code runs on NumPy scalars.
    if np.any(np.abs(a) > SPLIT_THRESHOLD):
        return _split_scaled(a)
    c = _SPLITTER * a
    hi = c - (c - a)
    return hi, a - hi


def _split_scaled(a):
    """Veltkamp's split of operands some of which lie above 2^996, each scaled by 2^-28 or 1."""
    big = np.abs(a) > SPLIT_THRESHOLD
    scale = 1.0 - big * (1.0 - _SPLIT_SCALE)  # exactly 2^-28 where big, 1 elsewhere
    s = a * scale
    c = _SPLITTER * s
    hi = c - (c - s)
    return hi / scale, (s - hi) / scale


def two_prod(a, b):
    """Dekker's error-free product: ``a * b = p + e`` exactly (while ``a b`` and its halves' products fit a double)."""
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


def add_same_sign(ah, al, bh, bl):
    """Double-double sum of two values of the same sign (Hida, Li & Bailey's "sloppy" addition).

    Nine operations fewer than :func:`add`, and as accurate when nothing cancels: the AGM
    and Bulirsch's cel add only positive terms.
    """
    s, e = two_sum(ah, bh)
    return quick_two_sum(s, e + (al + bl))


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


def sqrt_float(x):
    """Double-double square root of a float64 ``x >= 0``, scaled by an even power of two first.

    :func:`sqrt` squares its float root, whose rounding error underflows for x below
    ~1e-290; the scaling is exact and keeps 32 digits down to the smallest normal float.
    """
    _, e = np.frexp(x)
    half = e // 2  # x = (x 4^-half) 4^half, with x 4^-half in [1/4, 2)
    hi, lo = sqrt(np.ldexp(x, -2 * half), 0.0 * x)
    return np.ldexp(hi, half), np.ldexp(lo, half)


def agm_k(m1):
    """Complete K(m) = pi / (2 AGM(1, sqrt(m1))) as a double-double, for 0 <= m1 <= 1.

    The arithmetic-geometric mean (A&S 17.6.1) in double-double arithmetic, from the
    exact float complement ``m1 = 1 - m``, until ``a`` and ``b`` agree to four
    float64 ulps, then ``(a + b)/2`` (the neglected term ``(a - b)^2 / (16 a)`` is
    below 1e-31 a). An element that has converged takes no further steps while the
    others iterate, so every element gets the very floats a call with it alone
    would give. Relative error of ``hi + lo`` below 1e-31 down to the smallest normal
    m1 (2.2e-308); ``m1 = 0`` gives ``(inf, 0)``.
    About 0.5 us per element for arrays, 30 us for a scalar.

    Returns
    -------
    hi, lo : numpy.ndarray
    """
    k, _ = _agm(m1, gauss_sum=False)
    return k


def agm_ke(m1):
    """K(m) and E(m) as double-doubles: the AGM with Gauss's sum (A&S 17.6.3-4).

    ``E = K (1 - sum_n 2^(n-1) c_n^2)`` with ``c_0^2 = m = 1 - m1`` (exact) and
    ``c_(n+1)^2 = c_n^4 / (16 a_(n+1)^2)`` (no cancellation); ``1 - sum`` is formed in
    double-double, where it loses about log10 K digits of 32 (m next to 1). Relative
    error below 1e-28; ``m1 = 0`` gives K = inf, E = 1.

    Returns
    -------
    (k_hi, k_lo), (e_hi, e_lo) : tuples of numpy.ndarray
    """
    return _agm(m1, gauss_sum=True)


def _agm(m1, gauss_sum):
    m1 = np.asarray(m1, dtype=float)
    scalar = m1.ndim == 0
    if scalar:  # NumPy scalars: no masks, and twenty times faster than 0-d arrays
        m1 = m1[()]
    zero = m1 <= 0
    safe = (1.0 if zero else m1) if scalar else np.where(zero, 1.0, m1)
    a = (np.ones_like(safe), np.zeros_like(safe))
    b = sqrt_float(safe)
    c2 = two_sum(1.0, -safe)  # c_0^2 = m, exactly
    total = (0.5 * c2[0], 0.5 * c2[1])
    weight = 1.0
    for _ in range(64):
        active = np.abs(a[0] - b[0]) > 2.0**-50 * a[0]
        if not np.any(active):
            break
        a_new, b_new = _agm_step(a, b)
        if gauss_sum:
            four_a = (4.0 * a_new[0], 4.0 * a_new[1])
            c2_new = div(*mul(*c2, *c2), *mul(*four_a, *four_a))
            total_new = add_same_sign(*total, weight * c2_new[0], weight * c2_new[1])
            weight *= 2.0
        if scalar:
            a, b = a_new, b_new
            if gauss_sum:
                c2, total = c2_new, total_new
            continue
        a, b = _where(active, a_new, a), _where(active, b_new, b)
        if gauss_sum:
            c2, total = _where(active, c2_new, c2), _where(active, total_new, total)
    k = div(PI[0], PI[1], *add_same_sign(*a, *b))  # pi / (2 M), M = (a + b)/2
    e = mul(*k, *add(1.0, 0.0, -total[0], -total[1])) if gauss_sum else None
    if scalar:
        k = (np.asarray(np.inf if zero else k[0]), np.asarray(0.0 if zero else k[1]))
        e = None if e is None else (np.asarray(1.0 if zero else e[0]), np.asarray(0.0 if zero else e[1]))
    else:
        k = (np.where(zero, np.inf, k[0]), np.where(zero, 0.0, k[1]))
        e = None if e is None else (np.where(zero, 1.0, e[0]), np.where(zero, 0.0, e[1]))
    return k, e


def _where(mask, new, old):
    return np.where(mask, new[0], old[0]), np.where(mask, new[1], old[1])


def _agm_step(a, b):
    s = add_same_sign(*a, *b)
    return (0.5 * s[0], 0.5 * s[1]), sqrt(*mul(*a, *b))


def split3(hi, lo):
    """Split ``hi + lo`` into three floats: 26 bits, 26 bits and the rest, elementwise.

    ``j * p1`` and ``j * p2`` are exact for integers ``|j| < 2^27``, so
    ``((x - j p1) - j p2) - j p3`` reduces ``x`` modulo ``hi + lo`` with an error of
    a few ulps of the result plus ``|j|`` times the rounding of ``p3`` (Cody & Waite
    1980; the vectorised form of :func:`wobble.numerics.phase.split_dd`), for
    ``|hi|`` above ~1e-290. Non-finite or zero ``hi`` gives ``(hi, 0, lo)``.
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


def minus_multiple(x, j, hi, lo):
    """``x - j (hi + lo)`` as a double-double, for integer-valued ``j`` of any size below 2^53.

    Where a three-piece split (:func:`split3`) stops being exact (``|j| >=`` :data:`WHOLE_PIECES`), ``j hi``
    is taken by Dekker's exact product instead. With ``|x - j (hi + lo)| <= |hi|`` (``j`` the
    nearest multiple, or one off), ``x - fl(j hi)`` is exact (Sterbenz: the two agree within a
    factor of two), so the result keeps a few ulps of ``hi`` while ``|j lo| eps``, about
    ``|x| eps^2``, stays below them: to ``|j|`` ~ 2^50.
    """
    jh, jl = two_prod(j, hi)
    s, e1 = two_sum(x - jh, -jl)
    r, e2 = two_sum(s, -(j * lo))
    return r, e1 + e2
