"""Scalar constants to ~50 digits with the standard library (fractions, decimal).

A solution's constants (rates, quarter periods, mean precession rates) are
computed once per solution from the exact float64 inputs: products and sums
of floats are exact as :class:`fractions.Fraction`, so differences such as
``L^2 - 2 E I2`` near a separatrix carry no rounding at all; square roots,
AGMs and complete elliptic integrals are then taken in :mod:`decimal` at
``DIGITS`` digits and handed to the float64 kernels as double-double pairs
``(hi, lo)`` (see :mod:`wobble.numerics.phase`). No third-party dependency.
"""

from __future__ import annotations

import decimal
import functools
from decimal import Decimal
from fractions import Fraction

__all__ = [
    "DIGITS",
    "PI",
    "context",
    "make_context",
    "isolated",
    "dec",
    "to_dd",
    "sqrt",
    "agm_k",
    "cel",
    "cel_many",
    "carlson_rf",
    "exact",
    "sin_cos",
    "TWO_PI_DD",
]

DIGITS = 50
# pi to 60 digits (a constant: decimal has no trigonometry).
PI = Decimal("3.14159265358979323846264338327950288419716939937510582097494")


def make_context(prec: int) -> decimal.Context:
    """A decimal context of ``prec`` digits with every other setting given, none copied from
    ``decimal.DefaultContext`` (which a script may have changed): rounding half to even, the
    standard exponent range, and traps on the three signals that would mean a bug here (invalid
    operation, division by zero, overflow), not on inexact or float operations."""
    return decimal.Context(
        prec=prec,
        rounding=decimal.ROUND_HALF_EVEN,
        Emin=-999999,
        Emax=999999,
        capitals=1,
        clamp=0,
        flags=[],
        traps=[decimal.InvalidOperation, decimal.DivisionByZero, decimal.Overflow],
    )


def isolated(template):
    """Decorator: run the function in a copy of ``template()``, a decimal context, so that its
    Decimal arithmetic never takes the caller's (a script's precision, rounding or traps; decimal's
    default 28 digits) and the caller's flags stay as they were."""

    def wrap(fn):
        @functools.wraps(fn)
        def run(*args, **kwargs):
            with decimal.localcontext(template()):
                return fn(*args, **kwargs)

        return run

    return wrap


_CONTEXT = make_context(DIGITS)


def context() -> decimal.Context:
    """The decimal context used here (DIGITS significant digits): one shared template, which
    decimal.localcontext copies; its own methods (plus, divide, sqrt, subtract) only set flags."""
    return _CONTEXT


def exact(x) -> Fraction:
    """The exact rational value of a float (or int, Fraction)."""
    return x if isinstance(x, Fraction) else Fraction(x)


def dec(x) -> Decimal:
    """A Fraction, float or Decimal as a Decimal at DIGITS digits."""
    ctx = context()
    if isinstance(x, Decimal):
        return ctx.plus(x)
    if isinstance(x, int):
        return ctx.plus(Decimal(x))
    x = exact(x)
    return ctx.divide(Decimal(x.numerator), Decimal(x.denominator))


def sqrt(x) -> Decimal:
    """Square root at DIGITS digits of a non-negative Fraction, float or Decimal."""
    return context().sqrt(dec(x))


def to_dd(x) -> tuple[float, float]:
    """Double-double ``(hi, lo)`` with ``hi + lo`` equal to x to ~32 digits."""
    d = dec(x)
    if d.is_infinite():
        return float(d), 0.0
    hi = float(d)
    # Decimal.from_float, not Decimal(hi): exact either way, but the constructor signals FloatOperation,
    # which a caller's context may trap (this runs at import, in whatever context the caller has).
    lo = float(context().subtract(d, Decimal.from_float(hi))) if hi != 0.0 else 0.0
    return hi, lo


#: 2 pi as a double-double, formed in this module's context (a bare ``2 * PI`` takes the caller's:
#: decimal's default 28 digits gave a 2 pi 4.4e-28 off, 1.7e-13 rad after 2^49.9 turns).
TWO_PI_DD = to_dd(_CONTEXT.multiply(2, PI))


def agm_k(m1) -> Decimal:
    """Complete K(m) = pi / (2 AGM(1, sqrt(m1))) from the exact complement m1 > 0 (A&S 17.6.1)."""
    b = sqrt(m1)
    with decimal.localcontext(context()):
        a = Decimal(1)
        tol = Decimal(10) ** (-DIGITS + 2)
        while abs(a - b) > tol * a:
            a, b = (a + b) / 2, (a * b).sqrt()
        return PI / (2 * a)


def cel(kc, p, a, b) -> Decimal:
    """Bulirsch's general complete elliptic integral, for p > 0 and kc > 0.

    cel(kc, p, a, b) = int_0^{pi/2} (a cos^2 + b sin^2) / ((cos^2 + p sin^2) sqrt(cos^2 + kc^2 sin^2)) dtheta,

    so K = cel(k', 1, 1, 1) and Pi(n | m) = cel(k', 1 - n, 1, 1). Quadratically
    convergent (R. Bulirsch, Numer. Math. 13, 305 (1969); Numerical Recipes 6.11).
    """
    return cel_many(kc, [(p, a, b)])[0]


def carlson_rf(x, y, z, ctx: decimal.Context | None = None) -> Decimal:
    """Carlson's R_F(x, y, z) for x, y, z >= 0 (at most one zero), in ``ctx`` (default :func:`context`).

    Duplication until the arguments agree to 1e-12, then the fifth-order series, whose remainder is of
    the sixth power of their spread, 1e-72 (B. C. Carlson, Numer. Algorithms 10, 13 (1995), eq. 2.2):
    every digit of a context up to 70. The incomplete F(phi | m) is sin(phi) R_F(cos^2, 1 - m sin^2, 1).
    """
    with decimal.localcontext(ctx or context()):
        # Exact inputs (Decimal(float) is exact); the arithmetic below rounds to the context.
        x, y, z = (v if isinstance(v, Decimal) else Decimal.from_float(float(v)) for v in (x, y, z))
        # Outside the domain the duplication would take the square root of a negative or, with two zeros,
        # quarter the third argument until it underflows: refuse instead.
        if not all(v.is_finite() and v >= 0 for v in (x, y, z)) or (x == 0) + (y == 0) + (z == 0) > 1:
            raise ValueError(f"carlson_rf takes finite x, y, z >= 0 with at most one zero, not ({x}, {y}, {z})")
        tol = Decimal("1e-12")
        while True:
            mean = (x + y + z) / 3
            if max(abs(mean - x), abs(mean - y), abs(mean - z)) <= tol * mean:
                break
            sx, sy, sz = x.sqrt(), y.sqrt(), z.sqrt()
            lam = sx * sy + sy * sz + sz * sx
            x, y, z = (x + lam) / 4, (y + lam) / 4, (z + lam) / 4
        dx, dy = 1 - x / mean, 1 - y / mean
        dz = -(dx + dy)
        e2 = dx * dy - dz * dz
        e3 = dx * dy * dz
        return (1 - e2 / 10 + e3 / 14 + e2 * e2 / 24 - 3 * e2 * e3 / 44) / mean.sqrt()


def cel_many(kc, terms) -> list[Decimal]:
    """:func:`cel` ``(kc, p, a, b)`` for each ``(p, a, b)`` of ``terms``, in one loop.

    The sequence of e, em and kc that Bulirsch's iteration runs through (and so its stopping
    point) depends on kc alone: the integrals share one square root per step instead of one
    each, and each is the one :func:`cel` alone would give, operation for operation.
    """
    qc = dec(kc)
    terms = [(dec(p), dec(a), dec(b)) for p, a, b in terms]
    if qc <= 0 or any(p <= 0 for p, _, _ in terms):
        raise ValueError("cel here takes p > 0 and kc > 0")
    with decimal.localcontext(context()):
        ca = Decimal(10) ** (-DIGITS + 5)
        e = qc
        em = Decimal(1)
        state = []
        for p, a, b in terms:
            p = p.sqrt()
            state.append([a, b / p, p])
        for _ in range(200):
            for st in state:
                a, b, p = st
                f = a
                a = a + b / p
                g = e / p
                b = b + f * g
                b = b + b
                st[0], st[1], st[2] = a, b, g + p
            g = em
            em = em + qc
            if abs(g - qc) <= g * ca:
                break
            qc = e.sqrt()
            qc = qc + qc
            e = qc * em
        return [(PI / 2) * (b + a * em) / (em * (em + p)) for a, b, p in state]


def _sin_cos_series(x: Decimal, prec: int) -> tuple[Decimal, Decimal]:
    """sin and cos for |x| <= pi/4 at ``prec`` digits: the Taylor series of x / 2^6 (about half
    the terms of x's own), then six doublings, sin 2a = 2 sin a cos a and cos 2a = 1 - 2 sin^2 a
    (no cancellation for 2a <= pi/4; relative errors at most double per step, well inside the
    guard digits). Relative accuracy is kept down to the smallest x."""
    with decimal.localcontext(make_context(prec + 10)):
        h = x / 64
        h2 = h * h
        tol = Decimal(10) ** (-prec - 8)
        s_term, c_term = h, Decimal(1)
        s_sum, c_sum = h, Decimal(1)
        s_tol = tol * abs(h)
        k = 1
        while abs(s_term) > s_tol or abs(c_term) > tol:
            c_term = -c_term * h2 / ((2 * k - 1) * (2 * k))
            s_term = -s_term * h2 / ((2 * k) * (2 * k + 1))
            c_sum += c_term
            s_sum += s_term
            k += 1
        for _ in range(6):
            s_sum, c_sum = 2 * s_sum * c_sum, 1 - 2 * s_sum * s_sum
    with decimal.localcontext(make_context(prec + 5)):
        return +s_sum, +c_sum


def sin_cos(x, prec: int = DIGITS) -> tuple[Decimal, Decimal]:
    """sin x and cos x of an exact float (or Decimal) x in [-pi, pi], to ``prec`` digits.

    The argument is folded to |x| <= pi/4 with the 60-digit ``PI`` (sin(pi/2 - h) =
    cos h, ...), so both results keep their *relative* accuracy near their zeros
    (cos(pi/2 - 1e-17) = 1e-17 to ``prec`` digits), as needed for a top next to the
    vertical or the horizontal. Taylor series; no third-party dependency.
    """
    with decimal.localcontext(make_context(prec + 10)):
        d = x if isinstance(x, Decimal) else Decimal(exact(x).numerator) / Decimal(exact(x).denominator)
        if abs(d) > PI * (1 + Decimal(10) ** -40):
            raise ValueError("sin_cos takes |x| <= pi")
        sign = -1 if d < 0 else 1
        d = abs(d)
        half_pi = PI / 2
        quarter_pi = PI / 4
        # Fold to [0, pi/2]: sin(pi - d) = sin d, cos(pi - d) = -cos d.
        c_sign = 1
        if d > half_pi:
            d = PI - d
            c_sign = -1
        if d <= quarter_pi:
            s, c = _sin_cos_series(d, prec)
        else:
            c, s = _sin_cos_series(half_pi - d, prec)
    with decimal.localcontext(make_context(prec)):
        return +(sign * s), +(c_sign * c)
